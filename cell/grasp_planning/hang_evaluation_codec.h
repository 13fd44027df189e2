#pragma once
// A HangEvaluation as bytes and back, bit for bit, for candidate simulations run on other MPI
// ranks (twin/distributed/rank_group.h): a decoded evaluation equals the one computed.
#include <string>

#include "cell/grasp_planning/hang_evaluation.h"

namespace cell {

std::string encode_hang_evaluation(const HangEvaluation& e);
// Throws std::runtime_error when the bytes are not a whole encoded evaluation.
HangEvaluation decode_hang_evaluation(const std::string& bytes);

}  // namespace cell
