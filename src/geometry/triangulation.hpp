#pragma once
// Triangulation of points (stereo, two-view) and lines (two back-projected planes, two points on the line, or a
// robust fit over many).
#include <optional>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"

namespace vkvo::geometry {

// Gates for stereo matches and line triangulation. Reference defaults (EuRoC config): |dy| <= 2 px, depth in
// [0.1, 10] m. YAML keys: max_y_diff, min_depth, max_depth, min_line_plane_angle_deg.
struct TriangulationParams {
  double max_y_diff = 2.0;
  double min_depth = 0.1;
  double max_depth = 10.0;
  // Two back-projected planes meeting at a smaller angle are treated as degenerate (near-parallel).
  double min_line_plane_angle_deg = 1.0;
  // >= 2: a stereo line is first fitted over its associated stereo points when at least this many agree (AirVO's
  // code), planes otherwise; measured better than planes alone (docs/accuracy.md). 0: the two back-projected planes
  // alone (the paper).
  int line_fit_min_points = 3;
};
TriangulationParams load_triangulation_params(const YAML::Node& section);

// A stereo point match -> point in the rectified left camera frame; nullopt when the row difference or the depth
// gate fails (including zero / negative disparity).
std::optional<Eigen::Vector3d> triangulate_stereo_point(const StereoCamera& stereo, const Eigen::Vector2d& left,
                                                        const Eigen::Vector2d& right,
                                                        const TriangulationParams& params);

// Linear (DLT) triangulation from two views, in the world frame; nullopt when the point is not in front of both
// cameras or the rays are (nearly) parallel.
std::optional<Eigen::Vector3d> triangulate_two_view(const PinholeCamera& camera, const Eigen::Isometry3d& T_world_c1,
                                                    const Eigen::Vector2d& pixel1, const Eigen::Isometry3d& T_world_c2,
                                                    const Eigen::Vector2d& pixel2);

enum class LineTriangulationMethod { planes, points, failed };
const char* to_string(LineTriangulationMethod method);

struct LineTriangulation {
  PlueckerLine line;  // world frame (of the observations' poses), |v| = 1
  LineTriangulationMethod method = LineTriangulationMethod::failed;
};

// Intersection of the planes back-projected from two observations; nullopt when the planes meet at less than
// min_plane_angle_rad or the line would lie behind one of the cameras.
std::optional<PlueckerLine> triangulate_line_from_planes(const PinholeCamera& camera, const LineObservation& a,
                                                         const LineObservation& b, double min_plane_angle_rad);

// Planes first; when they are degenerate, the line through two already triangulated points on it (world frame),
// if given. The result says which method produced it.
LineTriangulation triangulate_line(const PinholeCamera& camera, const LineObservation& a, const LineObservation& b,
                                   const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_on_line,
                                   const TriangulationParams& params);

// Two views of a line from different poses (two keyframes): the planes' intersection, kept only when the segment
// seen in `a` then lies within [min_depth, max_depth] of camera a at both ends. A temporal baseline is often longer
// than the stereo one, but it is along the motion, so lines parallel to it stay degenerate (nullopt).
std::optional<PlueckerLine> triangulate_two_view_line(const PinholeCamera& camera, const LineObservation& a,
                                                      const LineObservation& b, const TriangulationParams& params);

// The line through the largest set of `points` that agree with one line, each within its own `tolerance`, fitted
// to them by least squares (their principal axis); nullopt with fewer than max(2, min_points) agreeing points or
// all of them within a millimetre. Every pair of points is tried as a hypothesis: lines carry tens of points.
std::optional<PlueckerLine> fit_line_to_points(const std::vector<Eigen::Vector3d>& points,
                                               const std::vector<double>& tolerances, int min_points);

// Stereo convenience: left and right segments of the rectified pair -> line in the left camera frame.
LineTriangulation triangulate_stereo_line(
    const StereoCamera& stereo, const Segment2d& left, const Segment2d& right,
    const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_on_line,
    const TriangulationParams& params);

}  // namespace vkvo::geometry
