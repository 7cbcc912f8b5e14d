// The only translation unit that instantiates the templated Ceres functors (compile time).
#include "backend/cost_functions.hpp"

#include <cmath>

#include <ceres/autodiff_cost_function.h>
#include <ceres/autodiff_manifold.h>
#include <ceres/numeric_diff_cost_function.h>
#include <ceres/product_manifold.h>
#include <ceres/rotation.h>

namespace vkvo::backend {

namespace {

template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

struct Intrinsics {
  double fx, fy, cx, cy, baseline, inv_sigma;
  Intrinsics(const geometry::StereoCamera& s, double sigma)
      : fx(s.camera.fx),
        fy(s.camera.fy),
        cx(s.camera.cx),
        cy(s.camera.cy),
        baseline(s.baseline),
        inv_sigma(1.0 / sigma) {}
};

template <typename T>
void world_to_camera_rotation(const T* q, const Vec3<T>& a, Vec3<T>& out) {
  const Eigen::Map<const Eigen::Quaternion<T>> rotation(q);
  out = rotation * a;
}

// Reprojection error of a world point (eq. 10); the stereo variant adds the right image's u (same v after
// rectification): u_right = fx (x - b) / z + cx.
template <bool kStereo>
struct PointResidual {
  Intrinsics k;
  PointMeasurement m;

  template <typename T>
  bool operator()(const T* pose, const T* X, T* r) const {
    const T* q = pose;
    const T* t = pose + 4;
    Vec3<T> p;
    world_to_camera_rotation(q, Vec3<T>(X[0], X[1], X[2]), p);
    p += Vec3<T>(t[0], t[1], t[2]);
    if (!(p.z() > T(1e-6))) return false;  // behind the camera: no valid projection
    const T inv_z = T(1) / p.z();
    const T u = k.fx * p.x() * inv_z + k.cx;
    r[0] = (u - m.pixel.x()) * k.inv_sigma;
    r[1] = (k.fy * p.y() * inv_z + k.cy - m.pixel.y()) * k.inv_sigma;
    if constexpr (kStereo) r[2] = (u - k.fx * k.baseline * inv_z - m.right_x) * k.inv_sigma;
    return true;
  }
};

// Distances of a segment's endpoints to the image line l = K_L n (eq. 8, 9), n in the camera frame.
template <typename T>
void endpoint_distances(const Intrinsics& k, const Vec3<T>& n, const geometry::Segment2d& s, T* r) {
  const T A = k.fy * n.x();
  const T B = k.fx * n.y();
  const T C = -k.fy * k.cx * n.x() - k.fx * k.cy * n.y() + k.fx * k.fy * n.z();
  const T inv_norm = T(1) / ceres::sqrt(A * A + B * B);
  r[0] = (A * s[0] + B * s[1] + C) * inv_norm * k.inv_sigma;
  r[1] = (A * s[2] + B * s[3] + C) * inv_norm * k.inv_sigma;
}

template <bool kStereo>
struct LineResidual {
  Intrinsics k;
  LineMeasurement m;

  template <typename T>
  bool operator()(const T* pose, const T* L, T* r) const {
    const T* q = pose;
    const T* t = pose + 4;
    // Pluecker transform world -> camera (eq. 7): n_c = R n + [t]x R v, v_c = R v.
    Vec3<T> Rn, v_c;
    world_to_camera_rotation(q, Vec3<T>(L[0], L[1], L[2]), Rn);
    world_to_camera_rotation(q, Vec3<T>(L[3], L[4], L[5]), v_c);
    const Vec3<T> n_c = Rn + Vec3<T>(t[0], t[1], t[2]).cross(v_c);
    endpoint_distances(k, n_c, m.left, r);
    if constexpr (kStereo) {
      // Right camera: p_right = p_left - (b, 0, 0), so n_right = n_c + (-b, 0, 0) x v_c.
      const Vec3<T> n_r = n_c + Vec3<T>(T(0), k.baseline * v_c.z(), -k.baseline * v_c.y());
      endpoint_distances(k, n_r, *m.right, r + 2);
    }
    return true;
  }
};

// U = [n/|n|, v/|v|, n x v / |n x v|] (n made orthogonal to v first) and (w1, w2) = (|n|, |v|) / |(|n|, |v|)|.
template <typename T>
void orthonormal(const T* x, Eigen::Matrix<T, 3, 3>& U, T& w1, T& w2) {
  const Vec3<T> n(x[0], x[1], x[2]), v(x[3], x[4], x[5]);
  const T v_norm = v.norm();
  const Vec3<T> u2 = v / v_norm;
  const Vec3<T> n_perp = n - n.dot(u2) * u2;
  const T n_norm = n_perp.norm();
  U.col(0) = n_perp / n_norm;
  U.col(1) = u2;
  U.col(2) = U.col(0).cross(u2);
  const T scale = ceres::sqrt(n_norm * n_norm + v_norm * v_norm);
  w1 = n_norm / scale;
  w2 = v_norm / scale;
}

struct OrthonormalLinePlus {
  template <typename T>
  bool Plus(const T* x, const T* delta, T* x_plus_delta) const {
    Eigen::Matrix<T, 3, 3> U, dR;
    T w1, w2;
    orthonormal(x, U, w1, w2);
    ceres::AngleAxisToRotationMatrix(delta, ceres::ColumnMajorAdapter3x3(dR.data()));
    const Eigen::Matrix<T, 3, 3> U_new = U * dR;
    const T c = ceres::cos(delta[3]), s = ceres::sin(delta[3]);
    const T w1_new = w1 * c - w2 * s, w2_new = w2 * c + w1 * s;  // W Rot(phi), first column
    const Vec3<T> n = (w1_new / w2_new) * U_new.col(0);
    for (int i = 0; i < 3; ++i) {
      x_plus_delta[i] = n[i];
      x_plus_delta[3 + i] = U_new(i, 1);
    }
    return true;
  }

  template <typename T>
  bool Minus(const T* y, const T* x, T* y_minus_x) const {
    Eigen::Matrix<T, 3, 3> Ux, Uy;
    T w1x, w2x, w1y, w2y;
    orthonormal(x, Ux, w1x, w2x);
    orthonormal(y, Uy, w1y, w2y);
    const Eigen::Matrix<T, 3, 3> dR = Ux.transpose() * Uy;
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(dR.data()), y_minus_x);
    y_minus_x[3] = ceres::atan2(w1x * w2y - w2x * w1y, w1x * w1y + w2x * w2y);
    return true;
  }
};

template <typename Functor, int kResiduals, int kModelSize>
std::unique_ptr<ceres::CostFunction> autodiff(Functor f) {
  return std::make_unique<ceres::AutoDiffCostFunction<Functor, kResiduals, 7, kModelSize>>(new Functor(f));
}

template <typename Functor, int kResiduals, int kModelSize>
std::unique_ptr<ceres::CostFunction> numeric(Functor f) {
  return std::make_unique<ceres::NumericDiffCostFunction<Functor, ceres::CENTRAL, kResiduals, 7, kModelSize>>(
      new Functor(f));
}

}  // namespace

std::unique_ptr<ceres::CostFunction> make_point_cost(const geometry::StereoCamera& stereo, const PointMeasurement& m,
                                                     double sigma) {
  const Intrinsics k(stereo, sigma);
  if (m.stereo()) return autodiff<PointResidual<true>, 3, 3>({k, m});
  return autodiff<PointResidual<false>, 2, 3>({k, m});
}

std::unique_ptr<ceres::CostFunction> make_line_cost(const geometry::StereoCamera& stereo, const LineMeasurement& m,
                                                    double sigma) {
  const Intrinsics k(stereo, sigma);
  if (m.stereo()) return autodiff<LineResidual<true>, 4, 6>({k, m});
  return autodiff<LineResidual<false>, 2, 6>({k, m});
}

std::unique_ptr<ceres::CostFunction> make_numeric_point_cost(const geometry::StereoCamera& stereo,
                                                             const PointMeasurement& m, double sigma) {
  const Intrinsics k(stereo, sigma);
  if (m.stereo()) return numeric<PointResidual<true>, 3, 3>({k, m});
  return numeric<PointResidual<false>, 2, 3>({k, m});
}

std::unique_ptr<ceres::CostFunction> make_numeric_line_cost(const geometry::StereoCamera& stereo,
                                                            const LineMeasurement& m, double sigma) {
  const Intrinsics k(stereo, sigma);
  if (m.stereo()) return numeric<LineResidual<true>, 4, 6>({k, m});
  return numeric<LineResidual<false>, 2, 6>({k, m});
}

std::unique_ptr<ceres::Manifold> make_line_manifold() {
  return std::make_unique<ceres::AutoDiffManifold<OrthonormalLinePlus, 6, 4>>();
}

std::unique_ptr<ceres::LossFunction> make_robust_loss(double chi2_threshold, double weight) {
  auto huber = std::make_unique<ceres::HuberLoss>(std::sqrt(chi2_threshold));
  if (weight == 1.0) return huber;
  return std::make_unique<ceres::ScaledLoss>(huber.release(), weight, ceres::TAKE_OWNERSHIP);
}

std::unique_ptr<ceres::Manifold> make_pose_manifold() {
  return std::make_unique<ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>>();
}

PoseBlock PoseBlock::from_T_world_camera(const Eigen::Isometry3d& T_world_camera) {
  const Eigen::Isometry3d T_cw = T_world_camera.inverse();
  PoseBlock b;
  Eigen::Map<Eigen::Quaterniond>(b.x) = Eigen::Quaterniond(T_cw.linear()).normalized();
  Eigen::Map<Eigen::Vector3d>(b.x + 4) = T_cw.translation();
  return b;
}

Eigen::Isometry3d PoseBlock::T_world_camera() const {
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
  T_cw.linear() = Eigen::Map<const Eigen::Quaterniond>(x).normalized().toRotationMatrix();
  T_cw.translation() = Eigen::Map<const Eigen::Vector3d>(x + 4);
  return T_cw.inverse();
}

}  // namespace vkvo::backend
