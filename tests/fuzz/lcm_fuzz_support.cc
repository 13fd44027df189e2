#include "tests/fuzz/lcm_fuzz_support.h"

#include <chrono>

namespace fuzz {

std::vector<RawMessage> split_messages(const std::uint8_t* data, std::size_t size,
                                       const std::vector<std::string>& channels) {
  std::vector<RawMessage> messages;
  std::size_t at = 0;
  while (at + 3 <= size && !channels.empty()) {
    const std::string& channel = channels[data[at] % channels.size()];
    const std::size_t length = data[at + 1] | (static_cast<std::size_t>(data[at + 2]) << 8);
    at += 3;
    const std::size_t taken = std::min(length, size - at);
    messages.push_back({channel, std::string_view(reinterpret_cast<const char*>(data + at), taken)});
    at += taken;
  }
  return messages;
}

void deliver(drivers::LcmBus& bus, const std::vector<RawMessage>& messages) {
  for (const RawMessage& m : messages) {
    bus.publish_raw(m.channel, m.payload.data(), m.payload.size());
    // memq:// queues in-process: handle each at once, as a live subscriber would.
    while (bus.handle_for(std::chrono::milliseconds(0)).messages > 0) {
    }
  }
}

}  // namespace fuzz
