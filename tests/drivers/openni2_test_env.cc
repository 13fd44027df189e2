#include "tests/drivers/openni2_test_env.h"

#include <spawn.h>
#include <sys/wait.h>
#include <fcntl.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

extern char** environ;

namespace testing_support {
namespace fs = std::filesystem;

OpenNI2TestEnv::OpenNI2TestEnv(const std::vector<std::string>& system_drivers) {
  const fs::path library = fs::canonical(OPENNI2_LIBRARY_FILE);  // the real libOpenNI2.so.0
  const fs::path system_repository = library.parent_path() / "OpenNI2" / "Drivers";
  const fs::path drivers = dir_ / "OpenNI2" / "Drivers";
  REQUIRE(fs::exists(OPENNI2_SIM_PLUGIN));
  fs::create_directories(drivers);
  fs::create_symlink(library, dir_ / "libOpenNI2.so.0");
  fs::create_symlink(fs::canonical(OPENNI2_SIM_PLUGIN), drivers / "libprepreg_openni2_sim.so.0");
  for (const std::string& name : system_drivers) {
    REQUIRE(fs::exists(system_repository / name));
    fs::create_symlink(system_repository / name, drivers / name);
  }
}

void OpenNI2TestEnv::write_sim_config(const std::string& json) const {
  write_file(dir_ / "sim_cameras.json", json);
}

OpenNI2TestEnv::ChildResult OpenNI2TestEnv::run_child(
    const std::string& test_name, const std::map<std::string, std::string>& extra_env) const {
  return run({fs::read_symlink("/proc/self/exe").string(), test_name}, extra_env);
}

OpenNI2TestEnv::ChildResult OpenNI2TestEnv::run(const std::vector<std::string>& command,
                                                const std::map<std::string, std::string>& extra_env) const {
  std::map<std::string, std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry(*e);
    const auto eq = entry.find('=');
    if (eq != std::string::npos) env[entry.substr(0, eq)] = entry.substr(eq + 1);
  }
  env["LD_LIBRARY_PATH"] = dir_.str();
  env["PREPREG_OPENNI2_SIM_CONFIG"] = (dir_ / "sim_cameras.json").string();
  env["PREPREG_OPENNI2_SIM_TEST_BACKENDS"] = "1";
  env["PREPREG_OPENNI2_TEST_DIR"] = dir_.str();
  for (const auto& [key, value] : extra_env) env[key] = value;
  std::vector<std::string> env_strings;
  for (const auto& [key, value] : env) env_strings.push_back(key + "=" + value);
  std::vector<char*> envp;
  for (std::string& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);

  std::vector<std::string> args = command;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  const std::string log = (dir_ / "child_output.txt").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  ChildResult result;
  if (spawned != 0) {
    result.output = "posix_spawn failed";
    return result;
  }
  int status = 0;
  waitpid(pid, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  result.output = text.str();
  return result;
}

std::string openni2_test_dir() {
  const char* dir = std::getenv("PREPREG_OPENNI2_TEST_DIR");
  return dir != nullptr ? dir : "";
}

}  // namespace testing_support
