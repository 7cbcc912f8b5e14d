// Evaluation against hand-computed cases: association, SE3/Sim3 alignment, ATE, RPE, drift, plot, report.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_support.hpp"
#include "eval/association.hpp"
#include "eval/evaluate.hpp"
#include "eval/metrics.hpp"
#include "eval/plot.hpp"

using namespace vkvo;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

Isometry3d make_pose(const Vector3d& axis_angle, const Vector3d& translation) {
  Isometry3d pose = Isometry3d::Identity();
  if (axis_angle.norm() > 0)
    pose.linear() = Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

// A 3D loop with changing orientation, 20 Hz, about 25 m long.
io::Trajectory helix(int n) {
  io::Trajectory trajectory;
  for (int k = 0; k < n; ++k) {
    const double s = 0.05 * k;
    trajectory.push_back({100.0 + s, make_pose(Vector3d(0.1 * std::sin(s), 0.2, 0.3 * s),
                                               Vector3d(3 * std::cos(s), 2 * std::sin(s), 0.3 * s))});
  }
  return trajectory;
}

// A straight path along x with 1 m between poses.
std::vector<Isometry3d> straight_line(int n) {
  std::vector<Isometry3d> poses;
  for (int k = 0; k < n; ++k) poses.push_back(make_pose(Vector3d::Zero(), Vector3d(k, 0, 0)));
  return poses;
}

}  // namespace

// Ground truth without orientations (positions-only files) is measured on positions alone.
TEST(EvalOptions, PositionsOnlyWhereTheGroundTruthHasNoOrientation) {
  vkvo::io::GroundTruth with_rotations, positions;
  positions.has_orientation = false;
  EXPECT_FALSE(vkvo::eval::eval_options_for(with_rotations).positions_only);
  EXPECT_TRUE(vkvo::eval::eval_options_for(positions).positions_only);
}

TEST(Stats, HandComputed) {
  const auto stats = eval::compute_stats({1, 2, 3, 4});
  EXPECT_EQ(stats.count, 4u);
  EXPECT_DOUBLE_EQ(stats.mean, 2.5);
  EXPECT_DOUBLE_EQ(stats.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(stats.median, 2.5);
  EXPECT_DOUBLE_EQ(stats.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(stats.max, 4);
  EXPECT_DOUBLE_EQ(eval::compute_stats({5, 1, 3}).median, 3);
  EXPECT_NEAR(eval::rotation_angle_deg(Eigen::AngleAxisd(1e-7, Vector3d::UnitY()).toRotationMatrix()),
              1e-7 * 180 / M_PI, 1e-15);
  EXPECT_NEAR(eval::rotation_angle_deg(Eigen::AngleAxisd(3.0, Vector3d::UnitX()).toRotationMatrix()), 3.0 * 180 / M_PI,
              1e-9);
}

TEST(Association, NearestWithinToleranceOneToOne) {
  io::Trajectory gt, est;
  for (int k = 0; k < 100; ++k) gt.push_back({0.01 * k, make_pose(Vector3d::Zero(), Vector3d(k, 0, 0))});
  est.push_back({0.203, Isometry3d::Identity()});   // nearest gt: 0.20 (k = 20)
  est.push_back({0.206, Isometry3d::Identity()});   // nearest gt: 0.21 (k = 21)
  est.push_back({0.2095, Isometry3d::Identity()});  // also 0.21 but further: 0.206 is 0.004 away, this 0.0005 -> wins
  est.push_back({5.0, Isometry3d::Identity()});     // beyond the gt: |dt| = 4.01 > tolerance
  const auto pairs = eval::associate(est, gt, 0.02);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_DOUBLE_EQ(pairs.t[0], 0.203);
  EXPECT_DOUBLE_EQ(pairs.groundtruth[0].translation().x(), 20);
  EXPECT_DOUBLE_EQ(pairs.t[1], 0.2095);
  EXPECT_DOUBLE_EQ(pairs.groundtruth[1].translation().x(), 21);
  EXPECT_EQ(eval::associate(est, gt, 0.0001).size(), 0u);
}

TEST(Alignment, Se3RecoversRigidTransformAndAteEqualsNoiseRms) {
  const io::Trajectory gt = helix(400);
  // estimate = S^-1 * gt + noise: aligning must recover S, and ATE must equal the injected noise.
  const Isometry3d S = make_pose(Vector3d(0.3, -1.2, 0.7), Vector3d(5, -3, 2));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  io::Trajectory est;
  double noise_sq = 0;
  for (const auto& p : gt) {
    const Vector3d n(noise(rng), noise(rng), noise(rng));
    noise_sq += n.squaredNorm();
    Isometry3d pose = S.inverse() * p.pose;
    pose.translation() += n;
    est.push_back({p.t + 0.001, pose});
  }
  const double noise_rms = std::sqrt(noise_sq / gt.size());

  const auto result = eval::evaluate(est, gt, {eval::AlignmentMode::se3, 0.02, {}});
  EXPECT_EQ(result.associated_poses, 400u);
  const auto& a = result.ate.alignment;
  EXPECT_DOUBLE_EQ(a.scale, 1.0);
  // Tolerances: 400 poses with 2 cm noise over a ~6 m wide loop -> the fit is good to a few mm / 0.1 deg.
  EXPECT_LT(eval::rotation_angle_deg(a.rotation.transpose() * S.linear()), 0.1);
  EXPECT_LT((a.translation - S.translation()).norm(), 0.01);
  // The 6 fitted parameters absorb a little of the noise: the ATE is within 2% below the noise RMS.
  EXPECT_NEAR(result.ate.translation_m.rmse, noise_rms, 0.02 * noise_rms);
  EXPECT_LE(result.ate.translation_m.rmse, noise_rms);
  EXPECT_LT(result.ate.rotation_deg.max, 0.1);  // orientation had no noise; only the fitted rotation's error

  // Without alignment the error is the transform itself.
  const auto raw = eval::evaluate(est, gt, {eval::AlignmentMode::none, 0.02, {}});
  EXPECT_GT(raw.ate.translation_m.rmse, 1.0);
}

TEST(Alignment, NoiselessSe3IsExact) {
  const io::Trajectory gt = helix(50);
  const Isometry3d S = make_pose(Vector3d(2.0, 0.1, -0.4), Vector3d(-1, 7, 0.5));
  io::Trajectory est;
  for (const auto& p : gt) est.push_back({p.t, S * p.pose});
  const auto result = eval::evaluate(est, gt, {eval::AlignmentMode::se3, 0.02, {}});
  EXPECT_LT(result.ate.translation_m.max, 1e-9);
  EXPECT_LT(result.ate.rotation_deg.max, 1e-6);
  EXPECT_LT(result.rpe.translation_percent, 1e-7);
  EXPECT_LT(result.drift.percent, 1e-7);
}

TEST(Alignment, Sim3RecoversScale) {
  const io::Trajectory gt = helix(300);
  const double scale = 0.4;  // estimate in units 2.5x larger than metres
  const Isometry3d S = make_pose(Vector3d(-0.5, 0.2, 1.0), Vector3d(1, 2, 3));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  io::Trajectory est;
  for (const auto& p : gt) {
    // x_gt = scale * R x_est + t  <=>  x_est = R^T (x_gt - t) / scale
    Isometry3d pose = S.inverse() * p.pose;
    pose.translation() = pose.translation() / scale + Vector3d(noise(rng), noise(rng), noise(rng));
    est.push_back({p.t, pose});
  }
  const auto result = eval::evaluate(est, gt, {eval::AlignmentMode::sim3, 0.02, {}});
  EXPECT_NEAR(result.ate.alignment.scale, scale, 0.002);  // 0.5% with 1 cm noise on a ~15 m loop
  EXPECT_LT(eval::rotation_angle_deg(result.ate.alignment.rotation.transpose() * S.linear()), 0.1);
  // The noise was added in estimate units, so it is scaled by 0.4 in metres: RMS about 0.4 * 0.01 * sqrt(3).
  EXPECT_NEAR(result.ate.translation_m.rmse, 0.4 * 0.01 * std::sqrt(3.0), 0.15 * 0.4 * 0.01 * std::sqrt(3.0));

  const auto se3 = eval::evaluate(est, gt, {eval::AlignmentMode::se3, 0.02, {}});  // scale error stays
  EXPECT_GT(se3.ate.translation_m.rmse, 10 * result.ate.translation_m.rmse);
}

TEST(Alignment, TooFewPosesAndStaticSim3AreErrors) {
  std::vector<Vector3d> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(eval::align_positions(two, two, eval::AlignmentMode::se3), std::runtime_error);
  std::vector<Vector3d> still(5, Vector3d(1, 1, 1)), moving{{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {3, 0, 1}, {0, 5, 0}};
  EXPECT_THROW(eval::align_positions(still, moving, eval::AlignmentMode::sim3), std::runtime_error);
  io::Trajectory a = helix(10), b = helix(10);
  for (auto& p : b) p.t += 1000;  // different clocks
  try {
    eval::evaluate(a, b);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("associate"), std::string::npos) << e.what();
  }
}

TEST(Rpe, ScaleErrorGivesExactTranslationPercent) {
  const auto gt = straight_line(11);  // 10 m path
  std::vector<Isometry3d> est;
  for (const auto& p : gt) est.push_back(make_pose(Vector3d::Zero(), 1.1 * p.translation()));
  const auto rpe = eval::compute_rpe(est, gt);  // lengths 10%..50% of 10 m = 1..5 m
  ASSERT_EQ(rpe.segments.size(), 5u);
  EXPECT_DOUBLE_EQ(rpe.segments[0].length_m, 1.0);
  EXPECT_DOUBLE_EQ(rpe.segments[4].length_m, 5.0);
  EXPECT_EQ(rpe.segments[0].count, 10u);  // starts 0..9
  EXPECT_EQ(rpe.segments[4].count, 6u);   // starts 0..5
  for (const auto& segment : rpe.segments) {
    EXPECT_NEAR(segment.translation_percent, 10.0, 1e-9);
    EXPECT_NEAR(segment.rotation_deg_per_m, 0.0, 1e-9);
  }
  EXPECT_EQ(rpe.count, 10u + 9 + 8 + 7 + 6);
  EXPECT_NEAR(rpe.translation_percent, 10.0, 1e-9);

  eval::RpeOptions fixed;
  fixed.lengths_m = {2.0, 50.0};
  fixed.step = 2;
  const auto fixed_rpe = eval::compute_rpe(est, gt, fixed);
  EXPECT_EQ(fixed_rpe.segments[0].count, 5u);  // starts 0, 2, 4, 6, 8
  EXPECT_EQ(fixed_rpe.segments[1].count, 0u);  // longer than the path
}

TEST(Rpe, HeadingRateErrorGivesExactDegreesPerMetre) {
  // The estimate turns 0.01 rad about z per metre more than the truth; positions are right.
  const auto gt = straight_line(21);
  std::vector<Isometry3d> est;
  for (int k = 0; k < 21; ++k) est.push_back(make_pose(Vector3d(0, 0, 0.01 * k), gt[k].translation()));
  eval::RpeOptions options;
  options.lengths_m = {4.0};
  const auto rpe = eval::compute_rpe(est, gt, options);
  EXPECT_EQ(rpe.segments[0].count, 17u);
  EXPECT_NEAR(rpe.rotation_deg_per_m, 0.01 * 180 / M_PI, 1e-9);
}

namespace {

// The 10 m straight line and an estimate of it that lives in another frame (`offset`) and ends 0.5 m off
// sideways; with `positions_only` the estimate's rotations are dropped.
eval::AssociatedPoses drifting_estimate(const Isometry3d& offset, bool positions_only) {
  const auto gt = straight_line(11);
  eval::AssociatedPoses poses;
  for (int k = 0; k < 11; ++k) {
    Isometry3d truth = gt[k];
    if (k == 10) truth.translation().y() += 0.5;
    Isometry3d estimate = offset * truth;
    if (positions_only) estimate.linear().setIdentity();
    poses.t.push_back(k);
    poses.groundtruth.push_back(gt[k]);
    poses.estimate.push_back(estimate);
  }
  return poses;
}

}  // namespace

TEST(Drift, FinalErrorOverPathLengthAfterFirstPoseAnchor) {
  const auto poses = drifting_estimate(make_pose(Vector3d(0, 0, 0.8), Vector3d(3, 4, 5)), false);
  const auto drift = eval::compute_drift(poses);
  EXPECT_NEAR(drift.path_length_m, 10.0, 1e-12);
  EXPECT_NEAR(drift.final_error_m, 0.5, 1e-12);
  EXPECT_NEAR(drift.percent, 5.0, 1e-10);
}

TEST(Plot, ChoosesWidestAxesAndDrawsBothCurves) {
  std::vector<Vector3d> gt, est;
  for (int k = 0; k <= 100; ++k) {
    const double s = 0.0628 * k;
    gt.emplace_back(10 * std::cos(s), 0.1 * s, 6 * std::sin(s));  // spread in x and z
    est.emplace_back(10.5 * std::cos(s), 0.1 * s, 6 * std::sin(s));
  }
  const auto axes = eval::choose_plot_axes(est, gt);
  EXPECT_EQ(axes.horizontal, 0);
  EXPECT_EQ(axes.vertical, 2);

  const cv::Mat image = eval::render_trajectory_plot(est, gt, {640, 480, "test", "estimate", "ground truth"});
  ASSERT_EQ(image.size(), cv::Size(640, 480));
  const auto count_near = [&](const cv::Scalar& colour) {
    int count = 0;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const auto p = image.at<cv::Vec3b>(y, x);
        if (std::abs(p[0] - colour[0]) + std::abs(p[1] - colour[1]) + std::abs(p[2] - colour[2]) < 30) ++count;
      }
    return count;
  };
  // Each curve is ~1300 px long on screen at this size; both must be visible (the legend adds ~90 px each).
  EXPECT_GT(count_near(eval::kEstimateColour), 1000);
  EXPECT_GT(count_near(eval::kGroundTruthColour), 1000);

  const auto png = test::temp_dir("plot") / "plot.png";
  eval::write_trajectory_plot(png, est, gt);
  const cv::Mat loaded = cv::imread(png.string());
  EXPECT_EQ(loaded.cols, 1000);
  EXPECT_EQ(loaded.rows, 800);
}

TEST(Report, JsonAndTableCarryTheNumbers) {
  const io::Trajectory gt = helix(100);
  io::Trajectory est = gt;
  for (auto& p : est) p.pose.translation().x() += 0.1;  // a constant offset: se3 removes it exactly
  const auto result = eval::evaluate(est, gt);
  EXPECT_LT(result.ate.translation_m.rmse, 1e-9);
  const auto json = eval::to_json(result);
  EXPECT_EQ(json["poses"]["associated"], 100);
  EXPECT_EQ(json["alignment"]["mode"], "se3");
  EXPECT_EQ(json["rpe"]["segments"].size(), 5u);
  EXPECT_TRUE(json["drift"].contains("percent"));
  const std::string table = eval::format_table(result);
  EXPECT_NE(table.find("ATE trans [m]"), std::string::npos);
  EXPECT_NE(table.find("100 associated"), std::string::npos);
}

TEST(Report, OptionsFromConfigSection) {
  const auto options =
      eval::load_eval_options(YAML::Load("align: sim3\nmax_dt_s: 0.005\nrpe_lengths_m: [1.5, 3]\nrpe_step: 10\n"));
  EXPECT_EQ(options.alignment, eval::AlignmentMode::sim3);
  EXPECT_DOUBLE_EQ(options.max_dt_s, 0.005);
  EXPECT_EQ(options.rpe.lengths_m, (std::vector<double>{1.5, 3.0}));
  EXPECT_EQ(options.rpe.step, 10u);
  EXPECT_EQ(eval::load_eval_options(YAML::Node()).alignment, eval::AlignmentMode::se3);
  try {
    eval::load_eval_options(YAML::Load("align: affine"));
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'align'"), std::string::npos) << e.what();
  }
}

// Positions-only ground truth (a total station, GNSS): the same helix with its orientations dropped gives the same
// position ATE as the full poses; rotation errors are absent; a rigid copy has no RPE and no drift.
TEST(PositionsOnly, AteMatchesFullPosesWithoutRotationErrors) {
  const io::Trajectory gt = helix(300);
  const Isometry3d S = make_pose(Vector3d(0.2, -0.9, 0.4), Vector3d(2, -1, 3));
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  io::Trajectory est, rigid, gt_positions;
  for (const auto& p : gt) {
    Isometry3d pose = S.inverse() * p.pose;
    rigid.push_back({p.t, pose});
    pose.translation() += Vector3d(noise(rng), noise(rng), noise(rng));
    est.push_back({p.t, pose});
    Isometry3d position = Isometry3d::Identity();
    position.translation() = p.pose.translation();
    gt_positions.push_back({p.t, position});
  }
  eval::EvalOptions options;
  const auto full = eval::evaluate(est, gt, options);
  options.positions_only = true;
  const auto positions = eval::evaluate(est, gt_positions, options);
  EXPECT_NEAR(positions.ate.translation_m.rmse, full.ate.translation_m.rmse, 1e-12);
  EXPECT_EQ(positions.ate.rotation_deg.count, 0u);
  EXPECT_DOUBLE_EQ(positions.rpe.rotation_deg_per_m, 0.0);
  EXPECT_GT(positions.rpe.translation_percent, 0.0);
  const auto json = eval::to_json(positions);
  EXPECT_TRUE(json["ate_rotation_deg"].is_null());
  EXPECT_TRUE(json["rpe"]["rotation_deg_per_m"].is_null());
  EXPECT_TRUE(json["poses"]["positions_only"].get<bool>());
  EXPECT_NE(eval::format_table(positions).find("n/a"), std::string::npos);

  // Noise-free rigid copy: alignment recovers S, every displacement matches, and the drift anchor (the ATE
  // rotation at the first position) leaves no final error, although the first pose's orientation is unknown.
  const auto exact = eval::evaluate(rigid, gt_positions, options);
  EXPECT_LT(exact.ate.translation_m.max, 1e-9);
  EXPECT_LT(exact.rpe.translation_percent, 1e-9);
  EXPECT_LT(exact.drift.final_error_m, 1e-9);
  EXPECT_GT(exact.rpe.count, 0u);
}

// Hand-computed RPE on displacements: a straight 1 m-step path, one estimate position 0.1 m off sideways. Of the
// 8 segments of 2 m, the two that start or end at that pose are 0.1 m off (5 %), the rest exact: mean 1.25 %.
TEST(PositionsOnly, RpeOnDisplacementsHandComputed) {
  const auto gt = straight_line(10);
  auto est = gt;
  est[5].translation().y() += 0.1;
  eval::RpeOptions options;
  options.lengths_m = {2.0};
  options.positions_only = true;
  const auto rpe = eval::compute_rpe(est, gt, options);
  ASSERT_EQ(rpe.segments.size(), 1u);
  EXPECT_EQ(rpe.count, 8u);
  EXPECT_NEAR(rpe.translation_percent, 1.25, 1e-12);
  EXPECT_DOUBLE_EQ(rpe.rotation_deg_per_m, 0.0);
}

// Drift without orientations: the estimate (another frame, turned 0.8 rad) is turned back by the given rotation and
// anchored at the first position; it ends 0.5 m off sideways over 10 m.
TEST(PositionsOnly, DriftAnchoredAtTheFirstPosition) {
  const Isometry3d offset = make_pose(Vector3d(0, 0, 0.8), Vector3d(3, 4, 5));
  const auto poses = drifting_estimate(offset, true);
  const auto drift = eval::compute_drift(poses, 1.0, Eigen::Matrix3d(offset.linear().transpose()));
  EXPECT_NEAR(drift.final_error_m, 0.5, 1e-12);
  EXPECT_NEAR(drift.percent, 5.0, 1e-10);
}
