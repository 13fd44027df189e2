#pragma once
// Writes an LCM log with LCM's LogFile API, as lcm-logger writes one: for the tests of the tools
// that read a cell run's log back (diagnose_cell_log, observed_trial_from_log).
#include <catch2/catch.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace testing_support {

class LcmLogWriter {
 public:
  explicit LcmLogWriter(const std::string& path) : log_(path, "w") { REQUIRE(log_.good()); }
  // One event on `channel` stamped `utime` (us) holding the encoded message.
  template <typename T>
  void write(const std::string& channel, std::int64_t utime, const T& message) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
    REQUIRE(message.encode(bytes.data(), 0, static_cast<int>(bytes.size())) == static_cast<int>(bytes.size()));
    lcm::LogEvent e;
    e.eventnum = event_++;
    e.timestamp = utime;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(bytes.size());
    e.data = bytes.data();
    REQUIRE(log_.writeEvent(&e) == 0);
  }

 private:
  lcm::LogFile log_;
  std::int64_t event_ = 0;
};

}  // namespace testing_support
