#include "drivers/openni2_runtime.h"

#include <OpenNI.h>

#include <mutex>

namespace drivers {
namespace {

std::mutex runtime_mutex;
int runtime_holders = 0;

}  // namespace

OpenNI2Runtime::OpenNI2Runtime() {
  std::lock_guard lock(runtime_mutex);
  if (runtime_holders == 0) {
    if (openni::OpenNI::initialize() != openni::STATUS_OK) {
      message_ = "OpenNI2 initialisation failed: " + openni2_error_text();
      // OpenNI counts initialize() calls even when they fail; balance it so a later try starts
      // from a clean state.
      openni::OpenNI::shutdown();
      return;
    }
  }
  ++runtime_holders;
  ok_ = true;
}

OpenNI2Runtime::~OpenNI2Runtime() {
  if (!ok_) return;
  std::lock_guard lock(runtime_mutex);
  if (--runtime_holders == 0) openni::OpenNI::shutdown();
}

std::string openni2_error_text() {
  const char* text = openni::OpenNI::getExtendedError();
  if (text == nullptr || *text == '\0') return "no details";
  std::string s(text);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

}  // namespace drivers
