#include "twin/diagnosis/refit_search_codec.h"

#include <cstdint>
#include <stdexcept>

#include <fmt/format.h>

#include "twin/distributed/byte_codec.h"

namespace twin::diagnosis {

using distributed::ByteReader;
using distributed::ByteWriter;

std::string encode_refit_search(const IdentificationResult& result, int rank) {
  if (!result.estimates.empty()) throw std::invalid_argument("encode_refit_search: a search's result has no intervals yet");
  ByteWriter w;
  w.put<std::int32_t>(rank);
  w.put_string(result.method).put_string(result.objective_name).put_string(result.stop_reason);
  w.put_doubles(result.coordinates.data(), static_cast<std::size_t>(result.coordinates.size()));
  w.put_doubles(result.start_coordinates.data(), static_cast<std::size_t>(result.start_coordinates.size()));
  w.put(result.objective).put<std::int32_t>(result.evaluations).put<std::int32_t>(result.simulations);
  w.put(result.seconds).put(result.noise_sigma_m);
  w.put<std::uint64_t>(result.at_search_edge.size());
  for (char edge : result.at_search_edge) w.put<std::int8_t>(static_cast<std::int8_t>(edge));
  return w.take();
}

namespace {
VecX to_vector(const std::vector<double>& v) { return Eigen::Map<const VecX>(v.data(), static_cast<Eigen::Index>(v.size())); }
}  // namespace

DecodedRefitSearch decode_refit_search(const std::string& bytes, const IdentificationProblem& problem) {
  ByteReader r(bytes);
  DecodedRefitSearch d;
  d.rank = r.get<std::int32_t>();
  IdentificationResult& res = d.result;
  res.method = r.get_string();
  res.objective_name = r.get_string();
  res.stop_reason = r.get_string();
  res.coordinates = to_vector(r.get_doubles());
  res.start_coordinates = to_vector(r.get_doubles());
  res.objective = r.get<double>();
  res.evaluations = r.get<std::int32_t>();
  res.simulations = r.get<std::int32_t>();
  res.seconds = r.get<double>();
  res.noise_sigma_m = r.get<double>();
  const auto edges = r.get<std::uint64_t>();
  if (edges > bytes.size()) throw std::runtime_error("refit search: more search-edge flags than the message holds");
  for (std::uint64_t j = 0; j < edges; ++j) res.at_search_edge.push_back(static_cast<char>(r.get<std::int8_t>()));
  if (!r.at_end()) throw std::runtime_error("refit search: bytes left after the result");
  const auto parameters = static_cast<Eigen::Index>(problem.parameters().size());
  // A failed search has no coordinates (refit_search: identify_gradient's "no result").
  if (res.coordinates.size() != 0) {
    if (res.coordinates.size() != parameters) {
      throw std::runtime_error(fmt::format("refit search: {} coordinates for {} parameters", res.coordinates.size(), parameters));
    }
    res.material = problem.material_at(res.coordinates);
  }
  return d;
}

}  // namespace twin::diagnosis
