#pragma once
// Messages from the bus for the LCM harnesses: an input is a sequence of messages, each one byte
// choosing the channel (modulo the harness's channel list), two bytes of length (little endian)
// and that many bytes of payload (fewer at the end of the input). The payload is what arrives on
// the wire: the type's 8-byte fingerprint and the encoded fields, as anyone on the network segment
// may publish them. Seeds come from a fake-cell lcm-logger log (tests/fuzz/seeds_from_log.py).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/lcm_bus.h"

namespace fuzz {

struct RawMessage {
  std::string channel;
  std::string_view payload;
};

std::vector<RawMessage> split_messages(const std::uint8_t* data, std::size_t size,
                                       const std::vector<std::string>& channels);

// Publishes every message on `bus` (memq://) and dispatches them all to its subscribers.
void deliver(drivers::LcmBus& bus, const std::vector<RawMessage>& messages);

}  // namespace fuzz
