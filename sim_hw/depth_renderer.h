#pragma once
// A z-buffer rasterizer for simulated cameras: renders a RenderScene into a pinhole camera as the
// true distance along the optical axis, the surface normal and which surface was hit, per pixel.
// Exact at pixel centres for planar triangles (barycentric coverage test, 1/z interpolated
// linearly in the image, which is perspective-correct). Lens distortion is ignored (a D415's
// depth stream is rectified). A 6k-triangle sheet plus floor renders at 848x480 in a few ms.

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "drivers/depth_camera.h"
#include "sim_hw/render_scene.h"

namespace sim_hw {

inline constexpr std::int32_t kNoSurface = -1;     // the ray hit nothing
inline constexpr std::int32_t kFloorSurface = -2;  // the ray hit the floor plane

struct RenderedView {
  int width = 0, height = 0;
  std::vector<float> depth_m;               // z along the optical axis (m); 0 = nothing hit
  std::vector<Eigen::Vector3f> normal_cam;  // unit surface normal in the camera frame, facing it
  std::vector<std::int32_t> surface;        // index into RenderScene::meshes, or the values above
};

// Renders into `view` (resized as needed; reuse it across frames to avoid allocations).
// camera_to_cell: pose of the camera (x right, y down, z forward) in the cell frame (m).
void render_view(const RenderScene& scene, const Eigen::Isometry3d& camera_to_cell,
                 const drivers::Intrinsics& intrinsics, RenderedView& view);

}  // namespace sim_hw
