#include "drivers/lcm_channels.h"

#include <stdexcept>

namespace drivers::channels {

std::string device_channel(std::string_view prefix, std::string_view device) {
  if (device.empty()) {
    throw std::invalid_argument("LCM channel " + std::string(prefix) + "<name>: empty device name");
  }
  std::string channel(prefix);
  for (char c : device) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '_';
    if (!ok) {
      throw std::invalid_argument("LCM channel " + std::string(prefix) + "<name>: device name '" +
                                  std::string(device) +
                                  "' may only contain letters, digits and '_'");
    }
    channel += (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
  }
  return channel;
}

}  // namespace drivers::channels
