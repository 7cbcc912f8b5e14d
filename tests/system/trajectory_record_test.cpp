// TrajectoryRecord and its motion model: closed-form motions (a circle at constant speed and turn rate, a straight
// uniform motion) give the expected poses; the files say what the record holds after every frame.
#include "system/trajectory_record.hpp"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/trajectory.hpp"

namespace vkvo::system {
namespace {

constexpr std::int64_t kStepNs = 50'000'000;  // 20 Hz
constexpr double kStep = 0.05;

// Yaw `angle` about z and position (x, y, 0).
Eigen::Isometry3d pose(double angle, double x, double y = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0);
  return T;
}

double yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

// A car on a circle of radius r at speed v, heading along the tangent: at time t, angle w t with w = v / r.
struct Circle {
  double r = 10.0, v = 10.0;
  double w() const { return v / r; }
  Eigen::Isometry3d at(double t) const { return pose(w() * t, r * std::sin(w() * t), r * (1 - std::cos(w() * t))); }
  Velocity velocity(double t) const {
    return {Eigen::Vector3d(v * std::cos(w() * t), v * std::sin(w() * t), 0), Eigen::Vector3d(0, 0, w())};
  }
};

TEST(HermitePose, ExactAtBothEndsAndLinearForAStraightUniformMotion) {
  const Eigen::Isometry3d a = pose(0.2, 1.0, 2.0), b = pose(0.2, 3.0, 2.0);
  const Velocity uniform{Eigen::Vector3d(2.0 / 0.5, 0, 0), Eigen::Vector3d::Zero()};
  for (const double s : {0.0, 0.3, 0.5, 1.0}) {
    const Eigen::Isometry3d T = hermite_pose(a, uniform, b, uniform, 0.5, s);
    EXPECT_NEAR((T.translation() - interpolate_pose(a, b, s).translation()).norm(), 0.0, 1e-12) << s;
    EXPECT_NEAR(yaw(T), 0.2, 1e-12) << s;
  }
  // Any velocities: the ends are the ends.
  const Velocity odd{Eigen::Vector3d(5, -3, 1), Eigen::Vector3d(0.4, 0.1, -2)};
  EXPECT_TRUE(hermite_pose(a, odd, b, odd, 0.5, 0.0).isApprox(a, 1e-12));
  EXPECT_TRUE(hermite_pose(a, odd, b, odd, 0.5, 1.0).isApprox(b, 1e-12));
}

// A second along a circle of 10 m radius at 10 m/s (57 deg of turn): linear interpolation cuts the chord, 1.2 m
// off the arc in the middle; the Hermite curve with the true end velocities stays within 3 cm (the cubic's own
// error against the arc, O(angle^4)) and turns at the true rate.
TEST(HermitePose, FollowsACircularArcThatLinearInterpolationCuts) {
  const Circle circle;
  const double duration = 1.0;
  double hermite_worst = 0, linear_worst = 0;
  for (int k = 1; k < 20; ++k) {
    const double t = duration * k / 20.0;
    const Eigen::Isometry3d truth = circle.at(t);
    const Eigen::Isometry3d h = hermite_pose(circle.at(0), circle.velocity(0), circle.at(duration),
                                             circle.velocity(duration), duration, t / duration);
    const Eigen::Isometry3d l = interpolate_pose(circle.at(0), circle.at(duration), t / duration);
    hermite_worst = std::max(hermite_worst, (h.translation() - truth.translation()).norm());
    linear_worst = std::max(linear_worst, (l.translation() - truth.translation()).norm());
    EXPECT_NEAR(yaw(h), circle.w() * t, 1e-9) << t;  // rotation about one axis at a constant rate: exact
  }
  EXPECT_GT(linear_worst, 1.0);
  EXPECT_LT(hermite_worst, 0.03);
}

FrameRecord frame(int index, const Eigen::Isometry3d& T, PoseState state, int segment = 0) {
  return {.index = static_cast<std::size_t>(index),
          .timestamp_ns = 1'000'000'000'000 + index * kStepNs,
          .T_world_camera = T,
          .state = state,
          .segment = segment};
}

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::istringstream in(test::read_text(file));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

struct RecordFiles {
  std::filesystem::path dir = test::temp_dir("trajectory_record");
  TrajectoryRecord::Files files{dir / "trajectory.txt", dir / "keyframes.txt", dir / "frames.csv"};
};

// The circle's frames 0-4 tracked, 5-14 untracked with predictions far off, 15-19 tracked: the gap is interpolated
// with the measured end velocities and lands within 2 cm of the arc, where the chord is up to 0.3 m off.
TEST(TrajectoryRecord, ClosedGapFollowsTheMotionAtBothEnds) {
  const Circle circle;
  RecordFiles out;
  TrajectoryRecord record(out.files, 200);
  for (int i = 0; i < 20; ++i) {
    const bool tracked = i < 5 || i >= 15;
    record.add(frame(i, tracked ? circle.at(i * kStep) : pose(3.0, 100.0 + i),
                     tracked ? PoseState::tracked : PoseState::lost));
    if (i == 14) {
      EXPECT_EQ(record.frames_bridged(), 0);  // nothing to interpolate towards yet
    }
  }
  EXPECT_EQ(record.frames_bridged(), 10);
  // Written at the closing frame and again as each of the next four frames refines the velocity at the gap's end.
  EXPECT_EQ(record.rewrites(), 5);
  double worst = 0;
  for (int i = 5; i < 15; ++i) {
    const FrameRecord& f = record.frames()[i];
    EXPECT_EQ(f.state, PoseState::bridged);
    worst = std::max(worst, (f.T_world_camera.translation() - circle.at(i * kStep).translation()).norm());
  }
  EXPECT_LT(worst, 0.02);
  const double chord_error = (interpolate_pose(circle.at(4 * kStep), circle.at(15 * kStep), 5.5 / 11).translation() -
                              circle.at(9.5 * kStep).translation())
                                 .norm();
  EXPECT_GT(chord_error, 0.25);

  // The files hold what the record holds, every frame once.
  const io::Trajectory written = io::read_tum(out.files.trajectory);
  ASSERT_EQ(written.size(), 20u);
  for (int i = 0; i < 20; ++i)
    EXPECT_NEAR((written[i].pose.translation() - record.frames()[i].T_world_camera.translation()).norm(), 0.0, 1e-8);
  const auto status = lines_of(out.files.status);
  ASSERT_EQ(status.size(), 21u);
  EXPECT_EQ(status[0], "index,timestamp_ns,state,segment,keyframe,point_inliers,line_inliers,note");
  EXPECT_EQ(status[6], "5,1000250000000,bridged,0,0,0,0,");
  EXPECT_EQ(status[16], "15,1000750000000,tracked,0,0,0,0,");
}

TEST(TrajectoryRecord, TrackedFramesAreAppendedAsTheyCome) {
  RecordFiles out;
  TrajectoryRecord record(out.files, 200);
  for (int i = 0; i < 3; ++i) {
    FrameRecord f = frame(i, pose(0.1 * i, i), PoseState::tracked);
    f.keyframe = i != 1;
    f.point_inliers = 100 + i;
    f.note = i == 2 ? "a note, with \"quotes\"" : "";
    record.add(f);
    EXPECT_EQ(io::read_tum(out.files.trajectory).size(), static_cast<std::size_t>(i + 1));
  }
  EXPECT_EQ(record.rewrites(), 0);
  EXPECT_EQ(io::read_tum(out.files.keyframes).size(), 2u);
  EXPECT_EQ(lines_of(out.files.status).back(), "2,1000100000000,tracked,0,1,102,0,\"a note, with \"\"quotes\"\"\"");
}

// Frames before the map first started have no pose: in the status file only.
TEST(TrajectoryRecord, FramesBeforeTheFirstTrackedOneHaveNoPose) {
  RecordFiles out;
  TrajectoryRecord record(out.files, 200);
  record.add(frame(0, Eigen::Isometry3d::Identity(), PoseState::lost));
  record.add(frame(1, Eigen::Isometry3d::Identity(), PoseState::lost));
  record.add(frame(2, pose(0.0, 1.0), PoseState::tracked));
  EXPECT_EQ(record.frames()[0].state, PoseState::uninitialised);
  EXPECT_EQ(record.frames_bridged(), 0);
  const io::Trajectory written = io::read_tum(out.files.trajectory);
  ASSERT_EQ(written.size(), 1u);
  EXPECT_NEAR(written[0].pose.translation().x(), 1.0, 1e-12);
  EXPECT_EQ(lines_of(out.files.status).size(), 4u);
  EXPECT_EQ(lines_of(out.files.status)[1].substr(0, 30), "0,1000000000000,uninitialised,");
}

// A young segment (1) merged into segment 0 moves every frame of it, and the gap before it is interpolated anew
// between the moved poses.
TEST(TrajectoryRecord, MergeMovesTheYoungSegmentAndItsGap) {
  RecordFiles out;
  TrajectoryRecord record(out.files, 200);
  for (int i = 0; i < 3; ++i) record.add(frame(i, pose(0, 0.1 * i), PoseState::tracked, 0));
  record.add(frame(3, pose(0, 5.0), PoseState::lost, 0));
  // The young segment started at a prediction 5 m off along x: its frames 4-6 are 5 m too far.
  for (int i = 4; i < 7; ++i) record.add(frame(i, pose(0, 5.0 + 0.1 * i), PoseState::tracked, 1));
  const SegmentMerge merge{.from = 1, .into = 0, .T_into_from = pose(0, -5.0)};
  record.add(frame(7, pose(0, 0.7), PoseState::relocalised, 0), merge);
  for (int i = 4; i < 8; ++i) {
    EXPECT_EQ(record.frames()[i].segment, 0);
    EXPECT_NEAR(record.frames()[i].T_world_camera.translation().x(), 0.1 * i, 1e-12) << i;
  }
  EXPECT_EQ(record.frames()[3].state, PoseState::bridged);
  EXPECT_NEAR(record.frames()[3].T_world_camera.translation().x(), 0.3, 1e-9);  // uniform motion: exact
  const io::Trajectory written = io::read_tum(out.files.trajectory);
  ASSERT_EQ(written.size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(written[i].pose.translation().x(), 0.1 * i, 1e-8) << i;
}

TEST(TrajectoryRecord, GapLongerThanTheLimitKeepsItsPredictions) {
  RecordFiles out;
  TrajectoryRecord record(out.files, 2);
  record.add(frame(0, pose(0, 0), PoseState::tracked));
  for (int i = 1; i <= 3; ++i) record.add(frame(i, pose(0, 10.0 * i), PoseState::lost));
  record.add(frame(4, pose(0, 4), PoseState::tracked));
  EXPECT_EQ(record.frames_bridged(), 0);
  EXPECT_EQ(record.frames()[2].state, PoseState::lost);
  EXPECT_NEAR(record.frames()[2].T_world_camera.translation().x(), 20.0, 1e-12);
  // A short gap later is interpolated.
  record.add(frame(5, pose(0, 99), PoseState::lost));
  record.add(frame(6, pose(0, 6), PoseState::tracked));
  EXPECT_EQ(record.frames_bridged(), 1);
  EXPECT_NEAR(record.frames()[5].T_world_camera.translation().x(), 5.0, 1e-9);
}

TEST(TrajectoryRecord, ZeroLimitInterpolatesNothingAndAnOpenGapStaysLost) {
  RecordFiles out;
  TrajectoryRecord record(out.files, 0);
  record.add(frame(0, pose(0, 0), PoseState::tracked));
  record.add(frame(1, pose(0, 9), PoseState::lost));
  record.add(frame(2, pose(0, 2), PoseState::tracked));
  record.add(frame(3, pose(0, 7), PoseState::lost));
  EXPECT_EQ(record.frames_bridged(), 0);
  EXPECT_EQ(record.frames()[1].state, PoseState::lost);
  EXPECT_EQ(record.frames()[3].state, PoseState::lost);
  EXPECT_EQ(io::read_tum(out.files.trajectory).size(), 4u);
}

}  // namespace
}  // namespace vkvo::system
