#pragma once
// Test support: the messages a cell publishes for one cycle, made up from a seeded RNG (a
// hanging grid sheet, a prediction a few mm off, random observed flags), with the prediction
// error computed here by a plain loop, independently of the tracker's code the monitor uses.
// Used by the monitor tests on memq:// and by the cycle publisher of the udpm test.

#include <cstdint>
#include <lcmt_iiwa_status.hpp>
#include <prepreg_lcm/camera_status_t.hpp>
#include <prepreg_lcm/cell_state_t.hpp>
#include <prepreg_lcm/prediction_error_t.hpp>
#include <prepreg_lcm/sheet_state_t.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "drivers/lcm_bus.h"

namespace testing_support {

struct CycleMessages {
  prepreg_lcm::sheet_state_t observed, predicted;
  prepreg_lcm::prediction_error_t error;
  std::vector<std::pair<std::string, prepreg_lcm::camera_status_t>> cameras;  // name, status
  lcmt_iiwa_status arm;  // published for LEFT and RIGHT
  prepreg_lcm::cell_state_t state;
};

// grid x grid vertices; `lost_camera` (may be "") is reported LOST. frames_utime = utime - 40 ms.
CycleMessages make_cycle(std::int64_t cycle_id, std::int64_t utime, std::mt19937& rng, int grid = 8,
                         const std::string& lost_camera = "");

struct EncodedMessage {
  std::string channel;
  std::vector<std::uint8_t> bytes;
};

// In the cell's order: SHEET_OBSERVED, SHEET_PREDICTED, PREDICTION_ERROR, CAMERA_STATUS_*,
// IIWA_STATUS_LEFT/RIGHT, CELL_STATE (last).
std::vector<EncodedMessage> encode_cycle(const CycleMessages& cycle);

// Publishes encode_cycle(cycle). Returns false if any publish failed.
bool publish_cycle(drivers::LcmBus& bus, const CycleMessages& cycle);

template <typename T>
std::vector<std::uint8_t> encode_message(const T& msg) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace testing_support
