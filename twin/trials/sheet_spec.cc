#include "twin/trials/sheet_spec.h"

#include <filesystem>

#include <fmt/format.h>

#include "twin/mesh/mesh_io.h"

namespace twin {

Mat3 rotation_from_degrees(const Vec3& deg) {
  const Vec3 r = deg * M_PI / 180.0;
  return (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(r.x(), Vec3::UnitX())).toRotationMatrix();
}

SheetSpec read_sheet_spec(const JsonField& f, const std::string& base) {
  SheetSpec s;
  f.only_keys({"width_m", "height_m", "edge_length_m", "target_triangles", "pattern",
               "mesh_file", "placement"});
  if (auto file = f.optional("mesh_file")) {
    for (const char* k : {"width_m", "height_m", "edge_length_m", "target_triangles"}) {
      if (f.has(k)) f[k].fail("cannot be combined with mesh_file");
    }
    const std::filesystem::path p(file->string());
    const std::string path =
        p.is_absolute() || base.empty() ? p.string() : (std::filesystem::path(base) / p).string();
    s.mesh = file->read_named_file([&] { return read_flat_sheet_mesh(path); });
    s.description = fmt::format("mesh {} ({} triangles)", path, s.mesh.triangle_count());
  } else {
    const double width = f["width_m"].positive("m");
    const double height = f["height_m"].positive("m");
    double edge = 0.0;
    if (f.has("edge_length_m") == f.has("target_triangles")) {
      f.fail_child("edge_length_m", "or 'target_triangles' must be given, exactly one of them");
    }
    if (auto e = f.optional("edge_length_m")) edge = e->positive("m");
    if (auto t = f.optional("target_triangles")) {
      edge = edge_length_for_triangle_count(width, height, t->positive_integer());
    }
    TriangulationPattern pattern = TriangulationPattern::kOffsetRows;
    if (auto pat = f.optional("pattern")) {
      const std::string name = pat->string();
      if (name == "right_triangles") {
        pattern = TriangulationPattern::kRightTriangles;
      } else if (name != "offset_rows") {
        pat->fail("must be \"offset_rows\" (default) or \"right_triangles\"");
      }
    }
    s.mesh = make_rectangular_sheet(width, height, edge, pattern);
    s.description = fmt::format("rectangle {} x {} m, edge {:.4f} m, {} triangles", width,
                                height, edge, s.mesh.triangle_count());
  }
  if (auto pl = f.optional("placement")) {
    pl->only_keys({"origin_m", "rotation_deg"});
    if (auto o = pl->optional("origin_m")) s.placement.origin_m = o->vec3("m");
    if (auto r = pl->optional("rotation_deg")) s.placement.rotation = rotation_from_degrees(r->vec3("deg"));
  }
  return s;
}

}  // namespace twin
