#pragma once
// Triangle surface meshes on disk (Wavefront OBJ, PLY) and the step from a flat surface mesh to
// the sheet's rest state. File input errors throw std::runtime_error naming the file and line
// (or, for binary PLY bodies, the element), per the error policy in STYLE.md.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "twin/mesh/sheet_mesh.h"
#include "twin/base/types.h"

namespace twin {

// A triangle mesh in 3D, as read from or written to a file.
struct SurfaceMesh {
  std::vector<Vec3> positions;                // #V, metres
  std::vector<std::array<int, 3>> triangles;  // #F, 0-based vertex indices
  std::vector<Vec2> uv;                       // empty, or #V texture/material coordinates (m)
};

// Reads .obj or .ply (chosen by extension, case-insensitive). Polygons are fan-triangulated.
// OBJ: v, vt and f (a, a/b, a//c, a/b/c, negative = relative indices); other statements are
//   ignored. uv is filled only if every position is used with exactly one vt value.
// PLY: ascii / binary_little_endian / binary_big_endian 1.0, any element order, x y z of any
//   numeric type, optional u v / s t / texture_u texture_v, faces from the list property
//   vertex_indices or vertex_index; other properties and elements are skipped.
// Throws std::runtime_error with a message starting "<path>:<line>: " for text errors (OBJ,
// PLY header, ASCII PLY body) or "<path>: element <name> <index>" for binary bodies, saying what
// was expected. Non-finite coordinates, out-of-range indices and wrong element counts are errors.
SurfaceMesh read_surface_mesh(const std::filesystem::path& path);

// A per-vertex scalar written as an extra float64 vertex property in PLY (e.g. error_m).
struct VertexScalar {
  std::string name;            // PLY property name: non-empty, no whitespace, not x y z u v
  std::vector<double> values;  // #V
};

// Writes ASCII (default) or binary_little_endian PLY: vertex x y z (double) [, u v (double)]
// [, scalars (double)], face list (uchar count, int indices). Writes "<path>.tmp" and renames it
// over `path`, so an existing file is never left half-written. Throws std::invalid_argument on a
// size mismatch or bad scalar name and std::runtime_error on I/O failure, both naming the path.
void write_ply(const std::filesystem::path& path, const SurfaceMesh& mesh,
               const std::vector<VertexScalar>& scalars = {}, bool binary = false);

// Writes OBJ: v, vt (if uv), f (a/a b/b c/c with uv, else a b c); same atomic write as write_ply.
void write_obj(const std::filesystem::path& path, const SurfaceMesh& mesh);

// write_ply (ASCII) or write_obj by extension, case-insensitive.
void write_surface_mesh(const std::filesystem::path& path, const SurfaceMesh& mesh);

// Turns a flat surface mesh into the sheet's rest state.
// With uv: rest_uv = uv (positions may then be any shape, e.g. a draped sheet).
// Without uv: projects the positions onto their least-squares plane (normal = eigenvector of the
//   smallest eigenvalue of the 3x3 covariance, signed towards +z, else +y, else +x). u = world x
//   projected into the plane (world y if the plane is normal to x), v = n x u, rest_uv = (p.u,
//   p.v). A mesh whose z values are all equal keeps rest_uv = (x, y) exactly. Throws
//   std::invalid_argument naming the worst vertex if it is farther than flatness_tolerance_m
//   from the plane.
// Triangles that are all clockwise in (u, v) are flipped; mixed orientation throws naming a
// triangle. The result passes validate_sheet_mesh (which is called, and may throw).
SheetMesh sheet_mesh_from_flat(const SurfaceMesh& mesh, double flatness_tolerance_m = 1e-4);

// A flat mesh file as a sheet: read_surface_mesh, then sheet_mesh_from_flat, whose errors are
// then prefixed with the file's path (a sheet named in a trial, scenario or goal).
SheetMesh read_flat_sheet_mesh(const std::filesystem::path& path);

// The surface of a sheet at world positions x (3n stacked, see types.h), with the sheet's
// triangles and its rest_uv as uv. Throws std::invalid_argument if x.size() != 3n.
SurfaceMesh surface_from_positions(const SheetMesh& sheet, const VecX& x);

}  // namespace twin
