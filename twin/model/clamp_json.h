#pragma once
// One clamp as scenario and trial files write it: {"id", "material_point_m", "grip_radius_m"}.

#include "twin/model/clamp.h"
#include "twin/base/json_field.h"

namespace twin {

// Reads the id (non-empty), the material point (m) and the optional grip radius (m, >= 0,
// default 0); rejects other keys. Errors name the field. Callers add their own checks (ids
// unique, point on the sheet).
ClampSpec read_clamp_spec(const JsonField& c);

}  // namespace twin
