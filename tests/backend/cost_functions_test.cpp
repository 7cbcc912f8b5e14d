// Automatic derivatives of the residuals against central numeric differences; residual values against direct
// geometry; the orthonormal line manifold (Plus / Minus invariants, Jacobians).
#include <random>

#include <gtest/gtest.h>

#include "backend/cost_functions.hpp"
#include "scene_fixture.hpp"

namespace vkvo::backend {
namespace {

using test::scene_camera;

// Evaluates residuals and Jacobians (row-major, one per block) of a cost function.
struct Eval {
  std::vector<double> r;
  std::vector<std::vector<double>> J;
};
Eval evaluate(const ceres::CostFunction& f, double* const* blocks) {
  Eval e;
  e.r.resize(f.num_residuals());
  const auto& sizes = f.parameter_block_sizes();
  e.J.resize(sizes.size());
  std::vector<double*> jac;
  for (size_t i = 0; i < sizes.size(); ++i) {
    e.J[i].resize(f.num_residuals() * sizes[i]);
    jac.push_back(e.J[i].data());
  }
  EXPECT_TRUE(f.Evaluate(blocks, e.r.data(), jac.data()));
  return e;
}

void expect_jacobians_match(const ceres::CostFunction& analytic, const ceres::CostFunction& numeric,
                            double* const* blocks) {
  const Eval a = evaluate(analytic, blocks), n = evaluate(numeric, blocks);
  for (size_t i = 0; i < a.r.size(); ++i) EXPECT_NEAR(a.r[i], n.r[i], 1e-12);
  for (size_t b = 0; b < a.J.size(); ++b)
    for (size_t i = 0; i < a.J[b].size(); ++i)
      EXPECT_NEAR(a.J[b][i], n.J[b][i], 1e-5 * std::max(1.0, std::abs(a.J[b][i]))) << "block " << b << " entry " << i;
}

TEST(CostFunctions, PointResidualsAndDerivatives) {
  const auto stereo = scene_camera();
  std::mt19937 rng(21);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry3d T_wc = test::perturb(Eigen::Isometry3d::Identity(), rng, 0.5, 0.3);
    const Eigen::Vector3d X = T_wc * Eigen::Vector3d(0.4 * (trial % 5) - 0.8, 0.3, 3.0 + 0.2 * trial);
    PoseBlock pose = PoseBlock::from_T_world_camera(T_wc);
    Eigen::Vector3d Xb = X;
    double* blocks[2] = {pose.data(), Xb.data()};
    const Eigen::Vector3d p = T_wc.inverse() * X;
    const Eigen::Vector2d px = stereo.camera.project(p) + Eigen::Vector2d(0.8, -0.4);
    for (const bool is_stereo : {false, true}) {
      const PointMeasurement m{px, is_stereo ? stereo.project_right(p).x() - 1.6 : -1.0};
      const auto cost = make_point_cost(stereo, m, 0.8);
      ASSERT_EQ(cost->num_residuals(), is_stereo ? 3 : 2);
      const Eval e = evaluate(*cost, blocks);
      EXPECT_NEAR(e.r[0], -0.8 / 0.8, 1e-9);  // whitened: (predicted - observed) / sigma
      EXPECT_NEAR(e.r[1], 0.4 / 0.8, 1e-9);
      if (is_stereo) {
        EXPECT_NEAR(e.r[2], 1.6 / 0.8, 1e-9);
      }
      expect_jacobians_match(*cost, *make_numeric_point_cost(stereo, m, 0.8), blocks);
    }
  }
}

TEST(CostFunctions, LineResidualsAndDerivatives) {
  const auto stereo = scene_camera();
  std::mt19937 rng(22);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry3d T_wc = test::perturb(Eigen::Isometry3d::Identity(), rng, 0.5, 0.3);
    const Eigen::Vector3d A(-0.5 + 0.05 * trial, -0.4, 3.0), B(0.6, 0.5 - 0.03 * trial, 4.5);
    const geometry::PlueckerLine L = geometry::PlueckerLine::from_points(T_wc * A, T_wc * B);
    PoseBlock pose = PoseBlock::from_T_world_camera(T_wc);
    Eigen::Matrix<double, 6, 1> Lb = L.vector();
    double* blocks[2] = {pose.data(), Lb.data()};
    // Observed endpoints: on the true projection, then moved 1 px along the image normal of the line.
    const Eigen::Vector2d a = stereo.camera.project(A), b = stereo.camera.project(B);
    const Eigen::Vector2d normal = Eigen::Vector2d(a.y() - b.y(), b.x() - a.x()).normalized();
    const Eigen::Vector2d ra = stereo.project_right(A), rb = stereo.project_right(B);
    for (const bool is_stereo : {false, true}) {
      LineMeasurement m{geometry::Segment2d(a.x() + normal.x(), a.y() + normal.y(), b.x(), b.y()), std::nullopt};
      if (is_stereo) m.right = geometry::Segment2d(ra.x(), ra.y(), rb.x(), rb.y());
      const auto cost = make_line_cost(stereo, m, 0.8);
      ASSERT_EQ(cost->num_residuals(), is_stereo ? 4 : 2);
      const Eval e = evaluate(*cost, blocks);
      EXPECT_NEAR(std::abs(e.r[0]), 1.0 / 0.8, 1e-7);  // the moved endpoint is 1 px off the line
      EXPECT_NEAR(e.r[1], 0.0, 1e-7);
      if (is_stereo) {
        EXPECT_NEAR(e.r[2], 0.0, 1e-7);
        EXPECT_NEAR(e.r[3], 0.0, 1e-7);
      }
      expect_jacobians_match(*cost, *make_numeric_line_cost(stereo, m, 0.8), blocks);
    }
  }
}

TEST(CostFunctions, LineManifoldInvariantsAndJacobian) {
  const auto manifold = make_line_manifold();
  ASSERT_EQ(manifold->AmbientSize(), 6);
  ASSERT_EQ(manifold->TangentSize(), 4);
  std::mt19937 rng(23);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const geometry::PlueckerLine L = geometry::PlueckerLine::from_points(Eigen::Vector3d(n(rng), n(rng), 4 + n(rng)),
                                                                         Eigen::Vector3d(n(rng), n(rng), 5 + n(rng)));
    const Eigen::Matrix<double, 6, 1> x = L.vector();
    const Eigen::Vector4d delta = 0.1 * Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng));
    Eigen::Matrix<double, 6, 1> y, zero_step;
    ASSERT_TRUE(manifold->Plus(x.data(), Eigen::Vector4d::Zero().eval().data(), zero_step.data()));
    EXPECT_LT((zero_step - x).norm(), 1e-12);  // Plus(x, 0) = x
    ASSERT_TRUE(manifold->Plus(x.data(), delta.data(), y.data()));
    // Plus agrees with the reference orthonormal update of geometry/.
    const geometry::PlueckerLine ref = geometry::OrthonormalLine::from_pluecker(L).plus(delta).to_pluecker();
    EXPECT_LT((y.head<3>() - ref.n).norm(), 1e-12);
    EXPECT_LT((y.tail<3>() - ref.v).norm(), 1e-12);
    EXPECT_NEAR(y.head<3>().dot(y.tail<3>()), 0.0, 1e-12);  // still a valid Pluecker vector
    Eigen::Vector4d back;
    ASSERT_TRUE(manifold->Minus(y.data(), x.data(), back.data()));
    EXPECT_LT((back - delta).norm(), 1e-9);  // Minus(Plus(x, d), x) = d
    // PlusJacobian against central differences of Plus at delta = 0.
    Eigen::Matrix<double, 6, 4, Eigen::RowMajor> J;
    ASSERT_TRUE(manifold->PlusJacobian(x.data(), J.data()));
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector4d d = Eigen::Vector4d::Zero();
      Eigen::Matrix<double, 6, 1> yp, ym;
      d[k] = 1e-6;
      manifold->Plus(x.data(), d.data(), yp.data());
      d[k] = -1e-6;
      manifold->Plus(x.data(), d.data(), ym.data());
      EXPECT_LT(((yp - ym) / 2e-6 - J.col(k)).norm(), 1e-6);
    }
  }
}

TEST(CostFunctions, PoseBlockRoundTrip) {
  std::mt19937 rng(24);
  const Eigen::Isometry3d T = test::perturb(Eigen::Isometry3d::Identity(), rng, 2.0, 1.0);
  const PoseBlock b = PoseBlock::from_T_world_camera(T);
  EXPECT_LT((b.T_world_camera().matrix() - T.matrix()).norm(), 1e-12);
  const Eigen::Vector3d X(1, 2, 3);
  const Eigen::Vector3d p = Eigen::Map<const Eigen::Quaterniond>(b.x) * X + Eigen::Map<const Eigen::Vector3d>(b.x + 4);
  EXPECT_LT((p - T.inverse() * X).norm(), 1e-12);
}

}  // namespace
}  // namespace vkvo::backend
