#pragma once
// A refit search's result (refit_search) as bytes, for the searches a diagnosis spreads over
// ranks (diagnose.cc): every number bit for bit (byte_codec.h), so a search's result is the
// same wherever it ran. The material is not sent: a search's material is its problem's
// material at the result's coordinates, and the receiving rank rebuilds it from the same problem.
#include <string>

#include "twin/trials/identification.h"

namespace twin::diagnosis {

// `rank`: where the search ran (progress lines only). A result with estimates (intervals come
// after the searches, in finish_refit) is refused: std::invalid_argument.
std::string encode_refit_search(const IdentificationResult& result, int rank);

struct DecodedRefitSearch {
  IdentificationResult result;
  int rank = 0;
};
// Throws std::runtime_error when the bytes are truncated or hold more than one result, or the
// coordinates do not match the problem's parameters.
DecodedRefitSearch decode_refit_search(const std::string& bytes, const IdentificationProblem& problem);

}  // namespace twin::diagnosis
