// The robustness benchmark's report: ratios to the clean run, the lines' gain against the run without them, the
// inliers the poses stood on, and a well-formed markdown table even where a run failed.
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "tools/robustness/robustness.hpp"

using vkvo::robustness::ScenarioResult;

namespace {

ScenarioResult result(const std::string& scenario, bool lines, double ate_m, double line_inliers) {
  ScenarioResult r;
  r.scenario = scenario;
  r.lines = lines;
  r.frames = 100;
  r.segments = 1;
  r.ate_m = r.ate_measured_m = ate_m;
  r.point_inliers_median = 180;
  r.line_inliers_median = line_inliers;
  return r;
}

std::vector<std::string> rows_of(const std::string& table) {
  std::vector<std::string> rows;
  std::istringstream in(table);
  for (std::string row; std::getline(in, row);) rows.push_back(row);
  return rows;
}

}  // namespace

TEST(RobustnessTable, AblationGivesTheLinesGainAndTheInliers) {
  std::vector<ScenarioResult> results = {result("clean", true, 0.010, 6), result("clean", false, 0.011, 0),
                                         result("dim 10%", true, 0.030, 4), result("dim 10%", false, 0.040, 0)};
  ScenarioResult failed = result("lights off", true, 0, 0);
  failed.error = "no frame tracked";
  results.push_back(failed);
  results.push_back(result("lights off", false, 0.050, 0));
  const std::string table = vkvo::robustness::format_table(results);
  const auto rows = rows_of(table);
  ASSERT_EQ(rows.size(), 5u) << table;  // header, rule, one row per scenario (the runs without lines are columns)
  // dim: 3x the clean ATE; without lines 0.040 m, so the lines cut the error by (0.040 - 0.030) / 0.040 = 25 %.
  EXPECT_NE(rows[3].find("| dim 10% | 0.0300 | 3.00 |"), std::string::npos) << rows[3];
  EXPECT_NE(rows[3].find("| 180 / 4 | 0.0400 | - | - | +25 % |"), std::string::npos) << rows[3];
  EXPECT_NE(rows[4].find("failed: no frame tracked"), std::string::npos) << rows[4];
  // Every row has the header's number of cells.
  const auto cells = [](const std::string& row) { return std::count(row.begin(), row.end(), '|'); };
  for (const auto& row : rows) EXPECT_EQ(cells(row), cells(rows[0])) << row;

  const auto json = vkvo::robustness::to_json(results);
  ASSERT_EQ(json.size(), results.size());
  EXPECT_EQ(json[2]["line_inliers_median"], 4.0);
  EXPECT_EQ(json[2]["point_inliers_median"], 180.0);
}

TEST(RobustnessTable, TheGainIsMeasuredOverTheFramesBothRunsEstimated) {
  ScenarioResult with = result("clean", true, 0.010, 6), without = result("clean", false, 0.020, 0);
  // Over their 80 common frames the run with lines is worse: (0.006 - 0.009) / 0.006 = -50 %.
  with.frames_paired = without.frames_paired = 80;
  with.ate_paired_m = 0.009;
  without.ate_paired_m = 0.006;
  const auto rows = rows_of(vkvo::robustness::format_table({with, without}));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NE(rows[2].find("| 0.0200 | 80 | 0.0090 / 0.0060 | -50 % |"), std::string::npos) << rows[2];
}

// Two runs compared over their common timestamps only: a run that estimated more frames (here 20 badly, before
// the other run started) is measured on the frames both have.
TEST(RobustnessPairedAte, OnlyTheCommonFramesCount) {
  vkvo::io::Trajectory groundtruth, early_start, late_start;
  for (int i = 0; i < 100; ++i) {
    vkvo::io::StampedPose pose;
    pose.t = 0.05 * i;
    pose.pose.translation() = Eigen::Vector3d(0.1 * i, 0.02 * i * i * 0.01, 0);
    groundtruth.push_back(pose);
    vkvo::io::StampedPose early = pose;
    if (i < 20) early.pose.translation().z() += (i % 2 ? 0.5 : -0.5);  // wrong only where the other run has no pose
    early_start.push_back(early);
    if (i >= 20) {
      vkvo::io::StampedPose late = pose;
      late.pose.translation().z() += (i % 2 ? 0.01 : -0.01);  // alternating: no rigid motion absorbs it
      late_start.push_back(late);
    }
  }
  const vkvo::eval::EvalOptions options;
  EXPECT_GT(vkvo::eval::evaluate(early_start, groundtruth, options).ate.translation_m.rmse, 0.1);
  const auto paired = vkvo::robustness::paired_ate(early_start, late_start, groundtruth, options);
  EXPECT_EQ(paired.frames, 80u);
  EXPECT_NEAR(paired.first_m, 0.0, 1e-9);  // exact over frames 20-99
  // Alternating +-1 cm across a straight-ish path: the best rigid fit leaves close to 1 cm everywhere.
  EXPECT_NEAR(paired.second_m, 0.01, 1e-3);
  // Symmetric: the order only decides which figure is which.
  const auto swapped = vkvo::robustness::paired_ate(late_start, early_start, groundtruth, options);
  EXPECT_EQ(swapped.frames, 80u);
  EXPECT_DOUBLE_EQ(swapped.first_m, paired.second_m);
  EXPECT_THROW(vkvo::robustness::paired_ate(early_start, {}, groundtruth, options), std::runtime_error);
}

TEST(RobustnessTable, WithoutAblationTheRowsHaveTheHeadersCells) {
  ScenarioResult failed = result("flicker", true, 0, 0);
  failed.error = "crashed";
  const auto rows = rows_of(vkvo::robustness::format_table({result("clean", true, 0.010, 6), failed}));
  ASSERT_EQ(rows.size(), 4u);
  const auto cells = [](const std::string& row) { return std::count(row.begin(), row.end(), '|'); };
  for (const auto& row : rows) EXPECT_EQ(cells(row), cells(rows[0])) << row;
  EXPECT_EQ(rows[0].find("lines' gain"), std::string::npos);
}

// The readers accept a wrapper folder around an EuRoC sequence (as the shared clips are laid out); the benchmark's
// perturbed copies are made of the sequence itself, so it resolves the wrapper first.
TEST(RobustnessSequenceFolder, WrapperFoldersResolveToTheSequence) {
  namespace fs = std::filesystem;
  const fs::path wrapper = vkvo::test::temp_dir("robustness_sequence_folder");
  const fs::path sequence = wrapper / "MH_01";
  for (const char* cam : {"cam0", "cam1"}) fs::create_directories(sequence / "mav0" / cam / "data");
  fs::create_directories(wrapper / "groundtruth");
  EXPECT_EQ(vkvo::robustness::sequence_folder(wrapper), sequence);
  EXPECT_EQ(vkvo::robustness::sequence_folder(sequence), sequence);
  EXPECT_EQ(vkvo::robustness::sequence_folder(sequence / "mav0"), sequence);
  const fs::path kitti = wrapper / "kitti_wrapper";
  for (const char* side : {"image_0", "image_1"}) fs::create_directories(kitti / "seq" / side);
  EXPECT_EQ(vkvo::robustness::sequence_folder(kitti), kitti / "seq");
}
