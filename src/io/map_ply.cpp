#include "io/map_ply.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

void write_map_ply(const fs::path& file, const MapGeometry& map) {
  const std::size_t line_vertices = 2 * map.lines.size();
  const std::size_t vertex_count = map.points.size() + line_vertices + map.trajectory.size();
  const std::size_t path_edges = map.trajectory.empty() ? 0 : map.trajectory.size() - 1;
  const std::size_t edge_count = map.lines.size() + path_edges;

  write_file_atomically(file, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment vkvo map: points, 3D line segments (edges), camera path\n"
        << "element vertex " << vertex_count << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "element edge " << edge_count << "\n"
        << "property int vertex1\nproperty int vertex2\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "end_header\n";
    const auto vertex = [&](const Eigen::Vector3d& p, const char* rgb) {
      out << fmt::format("{:.6f} {:.6f} {:.6f} {}\n", p.x(), p.y(), p.z(), rgb);
    };
    for (const auto& p : map.points) vertex(p, "200 200 200");
    for (const auto& [a, b] : map.lines) {
      vertex(a, "255 40 40");
      vertex(b, "255 40 40");
    }
    for (const auto& p : map.trajectory) vertex(p, "40 220 40");

    const std::size_t first_line_vertex = map.points.size();
    for (std::size_t k = 0; k < map.lines.size(); ++k)
      out << first_line_vertex + 2 * k << ' ' << first_line_vertex + 2 * k + 1 << " 255 40 40\n";
    const std::size_t first_path_vertex = first_line_vertex + line_vertices;
    for (std::size_t k = 0; k < path_edges; ++k)
      out << first_path_vertex + k << ' ' << first_path_vertex + k + 1 << " 40 220 40\n";
  });
}

}  // namespace vkvo::io
