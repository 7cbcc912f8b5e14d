#pragma once
// 3D lines: Pluecker coordinates (n, v) with n = X x v for any point X on the line (the normal of the plane through
// the line and the origin, |n| / |v| = distance to the origin), the orthonormal (U, W) form used for 4-DoF
// optimisation, transformation, projection to image lines and endpoint trimming. See method-notes "3D lines".
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"

namespace vkvo::geometry {

// A 2D segment in pixels: (x1, y1, x2, y2).
using Segment2d = Eigen::Vector4d;

struct PlueckerLine {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::UnitX();

  // Line through two distinct points: n = X1 x X2, v = X2 - X1, scaled so that |v| = 1. (The paper's eq. 6 writes
  // v = (X1 - X2) / |X1 - X2| with n = X1 x X2, which flips the sign of n relative to v; this form keeps n = X x v.)
  static PlueckerLine from_points(const Eigen::Vector3d& X1, const Eigen::Vector3d& X2);

  Eigen::Matrix<double, 6, 1> vector() const;
  static PlueckerLine from_vector(const Eigen::Matrix<double, 6, 1>& L);

  PlueckerLine normalized() const;                  // |v| = 1
  Eigen::Vector3d closest_point_to_origin() const;  // (v x n) / |v|^2
  Eigen::Vector3d direction() const { return v.normalized(); }
  double distance_to(const Eigen::Vector3d& X) const;  // Euclidean distance of a point to the line
};

// Orthonormal representation: U = [n/|n|, v/|v|, (n x v)/|n x v|] in SO(3), W = [[w1, -w2], [w2, w1]] in SO(2)
// with (w1, w2) = (|n|, |v|) / |(|n|, |v|)|. Undefined for lines through the origin (n = 0).
struct OrthonormalLine {
  Eigen::Matrix3d U = Eigen::Matrix3d::Identity();
  Eigen::Matrix2d W = Eigen::Matrix2d::Identity();

  static OrthonormalLine from_pluecker(const PlueckerLine& L);
  PlueckerLine to_pluecker() const;  // scaled so that |v| = 1
  // The 4-DoF update U <- U Exp(delta[0:3]), W <- W Rot(delta[3]).
  OrthonormalLine plus(const Eigen::Vector4d& delta) const;
};

// 6x6 transform of Pluecker coordinates from frame a to frame b: L_b = H(T_b_a) L_a (eq. 7).
Eigen::Matrix<double, 6, 6> line_transform_matrix(const Eigen::Isometry3d& T_b_a);
PlueckerLine transform_line(const Eigen::Isometry3d& T_b_a, const PlueckerLine& L_a);

// Line projection matrix K_L with l = K_L n (eq. 8). Derivation: pixels p = K x with x normalised image points; the
// image line of the plane with normal n is x^T n = 0, i.e. p^T K^-T n = 0, so l ~ K^-T n. Multiplying K^-T by
// fx*fy gives [[fy, 0, 0], [0, fx, 0], [-fy cx, -fx cy, fx fy]] (the paper prints fx / fy swapped on the diagonal).
Eigen::Matrix3d line_projection_matrix(const PinholeCamera& camera);
// Image line (A, B, C) of a line given in the camera frame.
Eigen::Vector3d project_line(const PinholeCamera& camera, const PlueckerLine& L_camera);
// Image line through two pixels (homogeneous cross product).
Eigen::Vector3d image_line(const Segment2d& segment);
// Signed distance of a pixel to an image line, in pixels.
double point_line_distance(const Eigen::Vector3d& line, const Eigen::Vector2d& pixel);

// One observation of a line: the segment seen by a camera at pose T_world_camera.
struct LineObservation {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  Segment2d segment = Segment2d::Zero();
};

// How far an observed segment lies from the projection of a world line: the larger of its two endpoints' distances
// to the projected image line, in pixels (the line residual of eq. 9, unweighted). Infinity when the line projects
// to a point (it passes through the camera centre).
double line_reprojection_error(const PlueckerLine& L_world, const PinholeCamera& camera, const LineObservation& obs);

// The point of the 3D line that the ray through `pixel` passes closest to (where the pixel's ray meets the line);
// nullopt when the ray is parallel to the line.
std::optional<Eigen::Vector3d> point_on_line_seen_at(const PlueckerLine& L_world, const PinholeCamera& camera,
                                                     const Eigen::Isometry3d& T_world_camera,
                                                     const Eigen::Vector2d& pixel);

// The 3D segment covered by the observations: each observed endpoint's ray is intersected with (closest point to)
// the 3D line, and the extreme points along the line are kept. For output and visualisation.
std::pair<Eigen::Vector3d, Eigen::Vector3d> trim_line(const PlueckerLine& L_world, const PinholeCamera& camera,
                                                      const std::vector<LineObservation>& observations);

}  // namespace vkvo::geometry
