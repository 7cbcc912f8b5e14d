#pragma once
// Trajectory files: TUM (our output), EuRoC ground-truth CSV, KITTI poses.txt, and positions without orientation.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vkvo::io {

// One pose of a trajectory: the pose of the tracked frame (camera or body) in the world, x_world = pose * x_frame.
struct StampedPose {
  double t = 0;  // seconds
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};
using Trajectory = std::vector<StampedPose>;

enum class TrajectoryFormat {
  automatic,  // detect from the first data line (see detect_trajectory_format)
  tum,        // "t x y z qx qy qz qw", blank separated, seconds
  euroc_csv,  // "timestamp_ns,px,py,pz,qw,qx,qy,qz[,...]", comma separated, '#' header
  kitti,      // 12 numbers per line: the 3x4 row-major pose, one line per frame
  // 4 fields per line, positions without orientation (a total station's prism, GNSS): "t x y z" blank separated
  // with t in seconds, or "timestamp_ns,x,y,z" comma separated. The poses read have identity rotations.
  positions,
};
const char* to_string(TrajectoryFormat format);

// Writes one TUM line per pose and flushes it, so a crash loses nothing that was written. Truncates the file
// unless `append` is set. Throws std::runtime_error naming the file when it cannot be opened or written.
class TumTrajectoryWriter {
 public:
  explicit TumTrajectoryWriter(const std::filesystem::path& file, bool append = false);
  ~TumTrajectoryWriter();
  TumTrajectoryWriter(const TumTrajectoryWriter&) = delete;
  TumTrajectoryWriter& operator=(const TumTrajectoryWriter&) = delete;

  // t in seconds, printed with 9 decimals.
  void write(double t, const Eigen::Isometry3d& pose);
  // Exact nanosecond timestamp (EuRoC epochs lose nanoseconds in a double), printed as seconds with 9 decimals.
  void write_ns(std::int64_t timestamp_ns, const Eigen::Isometry3d& pose);
  const std::filesystem::path& path() const { return path_; }
  std::size_t lines_written() const { return lines_; }

 private:
  void write_line(const std::string& time_text, const Eigen::Isometry3d& pose);
  void write_text(const std::string& line);
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::size_t lines_ = 0;
};

void write_tum(const std::filesystem::path& file, const Trajectory& trajectory);
// One TUM line ("t x y z qx qy qz qw\n") with an exact nanosecond timestamp printed as seconds with 9 decimals.
std::string tum_line_ns(std::int64_t timestamp_ns, const Eigen::Isometry3d& pose);

// Readers throw std::runtime_error naming file:line on malformed lines. Comment ('#') and blank lines are skipped.
Trajectory read_tum(const std::filesystem::path& file);
// EuRoC CSV: state_groundtruth_estimate0/data.csv (17 columns, body pose) or the 8-column cam0 form of
// ORB-SLAM3's EuRoC_left_cam/*_GT.txt. `columns` receives the column count of the data lines.
Trajectory read_euroc_csv(const std::filesystem::path& file, std::size_t* columns = nullptr);
// Positions only (TrajectoryFormat::positions): identity rotations.
Trajectory read_positions(const std::filesystem::path& file);
// KITTI poses.txt. Timestamps from `times` (one per line of the file) or, when empty, index * 0.1 s.
Trajectory read_kitti_poses(const std::filesystem::path& file, const std::vector<double>& times = {});
// KITTI times.txt: one time in seconds per line.
std::vector<double> read_kitti_times(const std::filesystem::path& file);

// From the first data line: comma separated with >= 8 fields -> euroc_csv; 12 numbers -> kitti; 8 -> tum;
// 4 -> positions.
TrajectoryFormat detect_trajectory_format(const std::filesystem::path& file);
// Any format; KITTI timestamps from `kitti_times` or index * 0.1 s.
Trajectory read_trajectory(const std::filesystem::path& file, TrajectoryFormat format = TrajectoryFormat::automatic,
                           const std::vector<double>& kitti_times = {});

// Which frame a ground-truth file describes. EuRoC's state_groundtruth_estimate0 is the body (IMU) pose; our
// estimates are left-camera (cam0) poses.
enum class PoseFrame { automatic, body, camera };

// How a ground-truth file's rotations are read.
enum class GroundTruthOrientation {
  // As written, except ORB-SLAM3's EuRoC ground truth (an 8-column EuRoC CSV in a folder named EuRoC_left_cam,
  // as found beside a sequence): inverse. Those files give cam0's position in the world but the world-to-camera
  // rotation (read as written, every pose is far off after alignment; inverted, the rotation error is the
  // alignment's own and the RPE agrees with the positions-only one: docs/accuracy.md).
  automatic,
  as_written,
  inverse,  // the file's rotation is world-to-frame: use its transpose
  none,     // ignore the rotations: positions only (GroundTruth::has_orientation false)
};

struct GroundTruthOptions {
  // automatic: a 17-column EuRoC CSV (state_groundtruth_estimate0) is the body pose; everything else is taken to
  // be the left-camera pose (TUM, KITTI poses.txt, the 8-column EuRoC_left_cam files).
  PoseFrame frame = PoseFrame::automatic;
  // The left camera's pose in the body frame (T_BS). Takes precedence over sensor_yaml.
  std::optional<Eigen::Isometry3d> T_body_camera;
  // cam0 sensor.yaml giving T_BS. When neither is given, <gt dir>/../cam0/sensor.yaml is tried.
  std::optional<std::filesystem::path> sensor_yaml;
  // KITTI: times.txt. When absent: times.txt next to poses.txt, or ../sequences/<stem>/times.txt (official
  // layout), else 10 Hz nominal.
  std::optional<std::filesystem::path> kitti_times;
  GroundTruthOrientation orientation = GroundTruthOrientation::automatic;
};

struct GroundTruth {
  Trajectory poses;  // left-camera poses in the world when body_to_camera_applied or the file is camera-frame
  TrajectoryFormat format = TrajectoryFormat::automatic;
  PoseFrame frame = PoseFrame::camera;  // the frame of `poses` after conversion
  bool has_orientation = true;          // false: positions only (their rotations are identity)
  bool body_to_camera_applied = false;
  std::optional<std::filesystem::path> sensor_yaml;  // where T_BS came from (unset when given directly)
  std::string note;                                  // a human-readable account of the above
};

// Reads a ground-truth file of any format and expresses it as left-camera poses where it can: body poses are
// composed with cam0's T_BS (T_world_cam = T_world_body * T_BS). Body poses without a sensor.yaml stay body poses
// (frame == body) with a warning: ATE then includes the camera's lever arm. Positions-only files are taken as
// they are (has_orientation false): whatever point they track, its offset from the camera is in the errors.
GroundTruth read_groundtruth(const std::filesystem::path& file, const GroundTruthOptions& options = {});

class StereoDataset;
// The ground truth found with a dataset (StereoDataset::groundtruth_path), as left-camera poses: EuRoC body poses
// are converted with the dataset's left T_body_camera, KITTI poses use the dataset's times.txt. nullopt when the
// dataset has no ground-truth file. Covers the whole sequence (the frame range is not applied).
std::optional<GroundTruth> read_dataset_groundtruth(const StereoDataset& dataset);

}  // namespace vkvo::io
