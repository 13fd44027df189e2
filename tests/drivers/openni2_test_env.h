#pragma once
// A private OpenNI2 installation for tests, and a way to run test cases inside it.
//
// How OpenNI2 (Debian 12, 2.2.0.33) finds drivers: OpenNI::initialize() takes the directory of
// the loaded libOpenNI2.so.0 (dladdr), reads /etc/openni2/OpenNI.ini (Debian patches the path; no
// OpenNI.ini next to the library and no environment variable is consulted), and loads every
// lib*.so.0 in "<library dir>/<Repository>", Repository defaulting to OpenNI2/Drivers. So a
// directory holding a symlink libOpenNI2.so.0 -> the system library and OpenNI2/Drivers/ with our
// plug-in (and libOniFile.so.0 for .oni playback), put first on LD_LIBRARY_PATH of a child
// process, is a complete OpenNI2 set-up that loads only those drivers. (A Repository set in
// /etc/openni2/OpenNI.ini would override this; Debian ships it commented out.)
//
// Tests run their OpenNI2 parts as hidden Catch2 cases ("[.openni2-child]") in a child process
// started with that environment; the parent case passes when the child's assertions all pass.

#include <map>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"

namespace testing_support {

class OpenNI2TestEnv {
 public:
  // Builds the directory with our plug-in and these drivers of the system's OpenNI2 repository;
  // REQUIREs that they exist.
  explicit OpenNI2TestEnv(const std::vector<std::string>& system_drivers = {"libOniFile.so.0"});

  std::string dir() const { return dir_.str(); }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }
  // Writes the plug-in's device list (PREPREG_OPENNI2_SIM_CONFIG) for the child.
  void write_sim_config(const std::string& json) const;

  struct ChildResult {
    int exit_code = -1;
    std::string output;  // the child's stdout and stderr
  };
  // Runs this test executable's hidden case `test_name` with the OpenNI2 environment and the
  // extra variables; the child finds the env directory in PREPREG_OPENNI2_TEST_DIR.
  ChildResult run_child(const std::string& test_name,
                        const std::map<std::string, std::string>& extra_env = {}) const;
  // Runs any program (argv[0] = its path) with the OpenNI2 environment.
  ChildResult run(const std::vector<std::string>& argv,
                  const std::map<std::string, std::string>& extra_env = {}) const;

 private:
  TempDir dir_{"openni2_env"};
};

// In a child: the directory of the running OpenNI2TestEnv (for recordings etc.).
std::string openni2_test_dir();

}  // namespace testing_support
