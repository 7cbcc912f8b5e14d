#pragma once
// A 2D line segment in pixel coordinates and the few geometric helpers the line pipeline needs.
#include <cmath>

#include <Eigen/Core>

namespace vkvo::features {

struct LineSegment {
  Eigen::Vector2f p0 = Eigen::Vector2f::Zero();
  Eigen::Vector2f p1 = Eigen::Vector2f::Zero();

  float length() const { return (p1 - p0).norm(); }
  Eigen::Vector2f midpoint() const { return 0.5f * (p0 + p1); }
  // Unit vector from p0 to p1 (zero for a degenerate segment).
  Eigen::Vector2f direction() const {
    const float len = length();
    return len > 0.0f ? Eigen::Vector2f((p1 - p0) / len) : Eigen::Vector2f::Zero();
  }
  // Supporting line A x + B y + C = 0 with A^2 + B^2 = 1, so that |A x + B y + C| is the point-line distance
  // (paper eq. 1). (A, B) is the unit normal, the direction rotated by +90 degrees.
  Eigen::Vector3f coefficients() const {
    const Eigen::Vector2f d = direction();
    const Eigen::Vector2f normal(-d.y(), d.x());
    return {normal.x(), normal.y(), -normal.dot(p0)};
  }
  // Distance of `point` to the infinite supporting line.
  float distance_to_line(const Eigen::Vector2f& point) const {
    const Eigen::Vector3f abc = coefficients();
    return std::abs(abc.x() * point.x() + abc.y() * point.y() + abc.z());
  }
};

}  // namespace vkvo::features
