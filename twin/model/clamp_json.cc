#include "twin/model/clamp_json.h"

namespace twin {

ClampSpec read_clamp_spec(const JsonField& c) {
  c.only_keys({"id", "material_point_m", "grip_radius_m"});
  ClampSpec spec;
  spec.id = c["id"].string();
  if (spec.id.empty()) c["id"].fail("must not be empty");
  spec.material_point_m = c["material_point_m"].vec2("m");
  if (auto r = c.optional("grip_radius_m")) spec.grip_radius_m = r->non_negative("m");
  return spec;
}

}  // namespace twin
