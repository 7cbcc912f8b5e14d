#include "geometry/line3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vkvo::geometry {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}
}  // namespace

PlueckerLine PlueckerLine::from_points(const Eigen::Vector3d& X1, const Eigen::Vector3d& X2) {
  const Eigen::Vector3d d = X2 - X1;
  const double length = d.norm();
  if (!(length > 0)) throw std::invalid_argument("PlueckerLine::from_points: the two points coincide");
  return {X1.cross(X2) / length, d / length};
}

Eigen::Matrix<double, 6, 1> PlueckerLine::vector() const {
  Eigen::Matrix<double, 6, 1> L;
  L << n, v;
  return L;
}

PlueckerLine PlueckerLine::from_vector(const Eigen::Matrix<double, 6, 1>& L) { return {L.head<3>(), L.tail<3>()}; }

PlueckerLine PlueckerLine::normalized() const {
  const double s = v.norm();
  return {n / s, v / s};
}

Eigen::Vector3d PlueckerLine::closest_point_to_origin() const { return v.cross(n) / v.squaredNorm(); }

double PlueckerLine::distance_to(const Eigen::Vector3d& X) const {
  return (X - closest_point_to_origin()).cross(direction()).norm();
}

OrthonormalLine OrthonormalLine::from_pluecker(const PlueckerLine& L) {
  // Gram-Schmidt keeps U a rotation even when n and v are not exactly orthogonal after arithmetic drift.
  const Eigen::Vector3d u2 = L.v.normalized();
  const Eigen::Vector3d n_perp = L.n - L.n.dot(u2) * u2;
  const double n_norm = n_perp.norm();
  if (!(n_norm > 0)) throw std::invalid_argument("OrthonormalLine: line through the origin has no orthonormal form");
  OrthonormalLine out;
  out.U.col(0) = n_perp / n_norm;
  out.U.col(1) = u2;
  out.U.col(2) = out.U.col(0).cross(u2);
  const double v_norm = L.v.norm();
  const double scale = std::hypot(n_norm, v_norm);
  const double w1 = n_norm / scale, w2 = v_norm / scale;
  out.W << w1, -w2, w2, w1;
  return out;
}

PlueckerLine OrthonormalLine::to_pluecker() const {
  const double w1 = W(0, 0), w2 = W(1, 0);
  return {(w1 / w2) * U.col(0), U.col(1)};
}

OrthonormalLine OrthonormalLine::plus(const Eigen::Vector4d& delta) const {
  OrthonormalLine out;
  const Eigen::Vector3d omega = delta.head<3>();
  const double angle = omega.norm();
  const Eigen::Matrix3d dR =
      angle > 0 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  out.U = U * dR;
  out.W = W * Eigen::Rotation2Dd(delta[3]).toRotationMatrix();
  return out;
}

Eigen::Matrix<double, 6, 6> line_transform_matrix(const Eigen::Isometry3d& T_b_a) {
  const Eigen::Matrix3d R = T_b_a.linear();
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  H.topLeftCorner<3, 3>() = R;
  H.topRightCorner<3, 3>() = skew(T_b_a.translation()) * R;
  H.bottomRightCorner<3, 3>() = R;
  return H;
}

PlueckerLine transform_line(const Eigen::Isometry3d& T_b_a, const PlueckerLine& L_a) {
  return PlueckerLine::from_vector(line_transform_matrix(T_b_a) * L_a.vector());
}

Eigen::Matrix3d line_projection_matrix(const PinholeCamera& c) {
  Eigen::Matrix3d K_L;
  K_L << c.fy, 0, 0, 0, c.fx, 0, -c.fy * c.cx, -c.fx * c.cy, c.fx * c.fy;
  return K_L;
}

Eigen::Vector3d project_line(const PinholeCamera& camera, const PlueckerLine& L_camera) {
  return line_projection_matrix(camera) * L_camera.n;
}

Eigen::Vector3d image_line(const Segment2d& s) {
  return Eigen::Vector3d(s[0], s[1], 1.0).cross(Eigen::Vector3d(s[2], s[3], 1.0));
}

double point_line_distance(const Eigen::Vector3d& l, const Eigen::Vector2d& p) {
  return (l.x() * p.x() + l.y() * p.y() + l.z()) / l.head<2>().norm();
}

double line_reprojection_error(const PlueckerLine& L_world, const PinholeCamera& camera, const LineObservation& obs) {
  const Eigen::Vector3d l = project_line(camera, transform_line(obs.T_world_camera.inverse(), L_world));
  if (l.head<2>().norm() < 1e-12) return std::numeric_limits<double>::infinity();
  return std::max(std::abs(point_line_distance(l, obs.segment.head<2>())),
                  std::abs(point_line_distance(l, obs.segment.tail<2>())));
}

namespace {

// s of the point P0 + s d of a line (|d| = 1) that the ray through `pixel` passes closest to; nullopt when the ray
// is parallel to the line.
std::optional<double> parameter_seen_at(const Eigen::Vector3d& P0, const Eigen::Vector3d& d,
                                        const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera,
                                        const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d C = T_world_camera.translation();
  const Eigen::Vector3d r = T_world_camera.linear() * camera.backproject(pixel).normalized();
  // Closest points of the line P0 + s d and the ray C + t r: normal equations of |P0 + s d - C - t r|^2.
  const Eigen::Vector3d w = P0 - C;
  const double dr = d.dot(r);
  const double det = dr * dr - 1.0;  // |d| = |r| = 1
  if (std::abs(det) < 1e-12) return std::nullopt;
  return (d.dot(w) - dr * r.dot(w)) / det;
}

}  // namespace

std::optional<Eigen::Vector3d> point_on_line_seen_at(const PlueckerLine& L_world, const PinholeCamera& camera,
                                                     const Eigen::Isometry3d& T_world_camera,
                                                     const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d P0 = L_world.closest_point_to_origin();
  const Eigen::Vector3d d = L_world.direction();
  const auto s = parameter_seen_at(P0, d, camera, T_world_camera, pixel);
  if (!s) return std::nullopt;
  return P0 + *s * d;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> trim_line(const PlueckerLine& L_world, const PinholeCamera& camera,
                                                      const std::vector<LineObservation>& observations) {
  const Eigen::Vector3d P0 = L_world.closest_point_to_origin();
  const Eigen::Vector3d d = L_world.direction();
  double s_min = std::numeric_limits<double>::infinity(), s_max = -s_min;
  for (const auto& obs : observations) {
    for (int e = 0; e < 2; ++e) {
      const auto s = parameter_seen_at(P0, d, camera, obs.T_world_camera, obs.segment.segment<2>(2 * e));
      if (!s) continue;
      s_min = std::min(s_min, *s);
      s_max = std::max(s_max, *s);
    }
  }
  if (!(s_min <= s_max)) throw std::invalid_argument("trim_line: no usable observation");
  return {P0 + s_min * d, P0 + s_max * d};
}

}  // namespace vkvo::geometry
