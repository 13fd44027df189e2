#include "cell/grasp_planning/hang_evaluation_codec.h"

#include <cstdint>
#include <stdexcept>

#include "twin/distributed/byte_codec.h"

namespace cell {

std::string encode_hang_evaluation(const HangEvaluation& e) {
  twin::distributed::ByteWriter w;
  w.put<std::uint8_t>(e.solved).put<std::uint8_t>(e.feasible).put_string(e.reason);
  const HangMetrics& m = e.metrics;
  w.put(m.lowest_z_m).put(m.sag_m).put(m.clearance_m).put(m.min_bend_radius_m).put(m.overturned_fraction);
  w.put(e.seconds).put_doubles(e.x.data(), static_cast<std::size_t>(e.x.size()));
  return w.take();
}

HangEvaluation decode_hang_evaluation(const std::string& bytes) {
  twin::distributed::ByteReader r(bytes);
  HangEvaluation e;
  e.solved = r.get<std::uint8_t>() != 0;
  e.feasible = r.get<std::uint8_t>() != 0;
  e.reason = r.get_string();
  HangMetrics& m = e.metrics;
  m.lowest_z_m = r.get<double>();
  m.sag_m = r.get<double>();
  m.clearance_m = r.get<double>();
  m.min_bend_radius_m = r.get<double>();
  m.overturned_fraction = r.get<double>();
  e.seconds = r.get<double>();
  const std::vector<double> x = r.get_doubles();
  e.x = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  if (!r.at_end()) throw std::runtime_error("hang evaluation: bytes left after the evaluation");
  return e;
}

}  // namespace cell
