#include "drivers/camera_registry.h"

#include <map>
#include <mutex>
#include <stdexcept>

namespace drivers {
namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, DepthCameraFactory> factories;
};

Registry& registry() {
  static Registry instance;
  return instance;
}

}  // namespace

void register_depth_camera_backend(const std::string& backend, DepthCameraFactory factory) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  r.factories[backend] = std::move(factory);
}

std::unique_ptr<DepthCamera> make_depth_camera(const std::string& backend) {
  Registry& r = registry();
  DepthCameraFactory factory;
  {
    std::lock_guard lock(r.mutex);
    auto it = r.factories.find(backend);
    if (it == r.factories.end()) {
      std::string known;
      for (const auto& [name, f] : r.factories) known += (known.empty() ? "" : ", ") + name;
      throw std::invalid_argument("unknown depth camera backend \"" + backend +
                                  "\" (registered: " + (known.empty() ? "none" : known) + ")");
    }
    factory = it->second;
  }
  return factory();
}

std::vector<std::string> depth_camera_backends() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, f] : r.factories) names.push_back(name);
  return names;
}

}  // namespace drivers
