#pragma once
// Runs a shell command line from a test and returns its exit status (-1 when it did not exit
// normally), with its stdout and stderr appended to `output`. Header-only, no project libraries;
// for processes that must be killed on failure use child_process.h.
#include <sys/wait.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace testing_support {

inline int run_command(const std::string& command, std::string& output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot start: " + command);
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace testing_support
