#include "geometry/triangulation.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "io/config.hpp"

namespace vkvo::geometry {

TriangulationParams load_triangulation_params(const YAML::Node& section) {
  TriangulationParams p;
  io::read_param(section, "max_y_diff", p.max_y_diff);
  io::read_param(section, "min_depth", p.min_depth);
  io::read_param(section, "max_depth", p.max_depth);
  io::read_param(section, "min_line_plane_angle_deg", p.min_line_plane_angle_deg);
  io::read_param(section, "line_fit_min_points", p.line_fit_min_points);
  return p;
}

std::optional<Eigen::Vector3d> triangulate_stereo_point(const StereoCamera& stereo, const Eigen::Vector2d& left,
                                                        const Eigen::Vector2d& right,
                                                        const TriangulationParams& params) {
  if (std::abs(left.y() - right.y()) > params.max_y_diff) return std::nullopt;
  const double disparity = left.x() - right.x();
  if (!(disparity > 0)) return std::nullopt;
  const double depth = stereo.camera.fx * stereo.baseline / disparity;
  if (depth < params.min_depth || depth > params.max_depth) return std::nullopt;
  return depth * stereo.camera.backproject(left);
}

std::optional<Eigen::Vector3d> triangulate_two_view(const PinholeCamera& camera, const Eigen::Isometry3d& T_world_c1,
                                                    const Eigen::Vector2d& pixel1, const Eigen::Isometry3d& T_world_c2,
                                                    const Eigen::Vector2d& pixel2) {
  // DLT on normalised coordinates: x cross (P X) = 0 with P = [R | t] of world -> camera.
  Eigen::Matrix4d A;
  const Eigen::Isometry3d T[2] = {T_world_c1.inverse(), T_world_c2.inverse()};
  const Eigen::Vector3d x[2] = {camera.backproject(pixel1), camera.backproject(pixel2)};
  for (int i = 0; i < 2; ++i) {
    const Eigen::Matrix<double, 3, 4> P = T[i].matrix().topRows<3>();
    A.row(2 * i) = x[i].x() * P.row(2) - P.row(0);
    A.row(2 * i + 1) = x[i].y() * P.row(2) - P.row(1);
  }
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (std::abs(X[3]) < 1e-12 * X.head<3>().norm()) return std::nullopt;  // point at infinity: parallel rays
  const Eigen::Vector3d point = X.head<3>() / X[3];
  for (const auto& Ti : T)
    if ((Ti * point).z() <= 0) return std::nullopt;
  return point;
}

const char* to_string(LineTriangulationMethod method) {
  switch (method) {
    case LineTriangulationMethod::planes: return "planes";
    case LineTriangulationMethod::points: return "points";
    case LineTriangulationMethod::failed: return "failed";
  }
  return "?";
}

namespace {

// Back-projected plane of an observed segment in the world frame: a . X + d = 0, |a| = 1.
Eigen::Vector4d world_plane(const PinholeCamera& camera, const LineObservation& obs) {
  const Eigen::Vector3d a_camera = camera.K().transpose() * image_line(obs.segment);
  const Eigen::Vector3d a = (obs.T_world_camera.linear() * a_camera).normalized();
  Eigen::Vector4d plane;
  plane << a, -a.dot(obs.T_world_camera.translation());
  return plane;
}

// Depth along the viewing ray of a segment endpoint at which the ray passes closest to the line (negative: behind).
bool endpoints_in_front(const PinholeCamera& camera, const PlueckerLine& L, const LineObservation& obs) {
  const Eigen::Vector3d P0 = L.closest_point_to_origin(), d = L.direction();
  const Eigen::Vector3d w = P0 - obs.T_world_camera.translation();
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector3d r = obs.T_world_camera.linear() * camera.backproject(obs.segment.segment<2>(2 * e));
    // Closest approach of the ray t r to the line P0 + s d (relative to the camera centre).
    const double rr = r.dot(r), rd = r.dot(d), den = rr - rd * rd;
    if (den <= 1e-12 * rr) return false;
    const double t = (r.dot(w) - rd * d.dot(w)) / den;
    if (t <= 0) return false;
  }
  return true;
}

}  // namespace

std::optional<PlueckerLine> triangulate_line_from_planes(const PinholeCamera& camera, const LineObservation& a,
                                                         const LineObservation& b, double min_plane_angle_rad) {
  const Eigen::Vector4d p1 = world_plane(camera, a), p2 = world_plane(camera, b);
  const Eigen::Vector3d a1 = p1.head<3>(), a2 = p2.head<3>();
  const Eigen::Vector3d v = a1.cross(a2);
  if (v.norm() < std::sin(min_plane_angle_rad)) return std::nullopt;
  // Points X on both planes satisfy a_i . X = -d_i, so n = X x (a1 x a2) = d1 a2 - d2 a1.
  PlueckerLine L{p1[3] * a2 - p2[3] * a1, v};
  L = L.normalized();
  if (!endpoints_in_front(camera, L, a) || !endpoints_in_front(camera, L, b)) return std::nullopt;
  return L;
}

LineTriangulation triangulate_line(const PinholeCamera& camera, const LineObservation& a, const LineObservation& b,
                                   const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_on_line,
                                   const TriangulationParams& params) {
  const double min_angle = params.min_line_plane_angle_deg * M_PI / 180.0;
  if (auto L = triangulate_line_from_planes(camera, a, b, min_angle)) return {*L, LineTriangulationMethod::planes};
  if (points_on_line && (points_on_line->first - points_on_line->second).norm() > 1e-9)
    return {PlueckerLine::from_points(points_on_line->first, points_on_line->second), LineTriangulationMethod::points};
  return {};
}

std::optional<PlueckerLine> triangulate_two_view_line(const PinholeCamera& camera, const LineObservation& a,
                                                      const LineObservation& b, const TriangulationParams& params) {
  const auto L = triangulate_line_from_planes(camera, a, b, params.min_line_plane_angle_deg * M_PI / 180.0);
  if (!L) return std::nullopt;
  const auto [e0, e1] = trim_line(*L, camera, {a});
  const Eigen::Isometry3d T_a_world = a.T_world_camera.inverse();
  for (const Eigen::Vector3d& e : {e0, e1}) {
    const double depth = (T_a_world * e).z();
    if (depth < params.min_depth || depth > params.max_depth) return std::nullopt;
  }
  return L;
}

LineTriangulation triangulate_stereo_line(
    const StereoCamera& stereo, const Segment2d& left, const Segment2d& right,
    const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_on_line,
    const TriangulationParams& params) {
  return triangulate_line(stereo.camera, {Eigen::Isometry3d::Identity(), left}, {stereo.T_left_right(), right},
                          points_on_line, params);
}

std::optional<PlueckerLine> fit_line_to_points(const std::vector<Eigen::Vector3d>& points,
                                               const std::vector<double>& tolerances, int min_points) {
  const std::size_t n = points.size();
  const auto within = [&](const PlueckerLine& line, std::size_t k) {
    return line.distance_to(points[k]) <= tolerances[k];
  };
  std::vector<std::size_t> best;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      if ((points[i] - points[j]).norm() < 1e-3) continue;
      const PlueckerLine hypothesis = PlueckerLine::from_points(points[i], points[j]);
      std::vector<std::size_t> agreeing;
      for (std::size_t k = 0; k < n; ++k)
        if (within(hypothesis, k)) agreeing.push_back(k);
      if (agreeing.size() > best.size()) best = std::move(agreeing);
    }
  if (best.size() < static_cast<std::size_t>(std::max(2, min_points))) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const std::size_t k : best) centroid += points[k];
  centroid /= static_cast<double>(best.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const std::size_t k : best) scatter += (points[k] - centroid) * (points[k] - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d direction = eigen.eigenvectors().col(2);  // eigenvalues ascend: the largest spread
  return PlueckerLine::from_points(centroid, centroid + direction).normalized();
}

}  // namespace vkvo::geometry
