#pragma once
// OpenNI2 is one process-wide library context: OpenNI::initialize() loads every driver in its
// repository and OpenNI::shutdown() unloads them. Each OpenNI2 camera, recorder or tool holds an
// OpenNI2Runtime while it uses the library, so the first holder initialises and the last one shuts
// down, whatever order cameras are created and destroyed in.

#include <string>

namespace drivers {

class OpenNI2Runtime {
 public:
  OpenNI2Runtime();  // never throws; check ok()
  ~OpenNI2Runtime();
  OpenNI2Runtime(const OpenNI2Runtime&) = delete;
  OpenNI2Runtime& operator=(const OpenNI2Runtime&) = delete;

  bool ok() const { return ok_; }
  const std::string& message() const { return message_; }  // why initialisation failed

 private:
  bool ok_ = false;
  std::string message_;
};

// OpenNI2's own explanation of the last failure in this thread's calls (getExtendedError), or
// "no details" when it has none.
std::string openni2_error_text();

}  // namespace drivers
