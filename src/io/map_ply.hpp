#pragma once
// ASCII PLY export of a map for viewers (MeshLab, CloudCompare, Open3D): map points as vertices, 3D line segments
// as edges between their two endpoint vertices, and optionally the camera path as a chain of edges.
#include <filesystem>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace vkvo::io {

struct MapGeometry {
  std::vector<Eigen::Vector3d> points;                             // light grey vertices
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;  // red edges (endpoint pairs)
  std::vector<Eigen::Vector3d> trajectory;                         // green polyline of camera centres
};

// Vertex order: points, then 2 per line (start, end), then trajectory positions. Written to a temporary file and
// renamed, so a reader never sees a half-written map. Throws std::runtime_error naming the file on failure.
void write_map_ply(const std::filesystem::path& file, const MapGeometry& map);

}  // namespace vkvo::io
