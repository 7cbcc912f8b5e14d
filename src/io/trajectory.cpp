#include "io/trajectory.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/atomic_file.hpp"
#include "io/dataset.hpp"
#include "io/text_utils.hpp"
#include "io/yaml_utils.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

const char* to_string(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::automatic: return "automatic";
    case TrajectoryFormat::tum: return "tum";
    case TrajectoryFormat::euroc_csv: return "euroc_csv";
    case TrajectoryFormat::kitti: return "kitti";
    case TrajectoryFormat::positions: return "positions";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------------------------- TUM writer

namespace {

std::string tum_text(const std::string& time_text, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d p = pose.translation();
  const Eigen::Quaterniond q(pose.rotation());
  return fmt::format("{} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", time_text, p.x(), p.y(), p.z(), q.x(),
                     q.y(), q.z(), q.w());
}

}  // namespace

TumTrajectoryWriter::TumTrajectoryWriter(const fs::path& file, bool append) : path_(file) {
  create_output_folder(file.parent_path());
  file_ = std::fopen(file.c_str(), append ? "a" : "w");
  if (!file_)
    throw OutputWriteError(fmt::format("{}: cannot open trajectory file ({})", file.string(), std::strerror(errno)));
}

TumTrajectoryWriter::~TumTrajectoryWriter() {
  // Every line was flushed and checked when written; a failure here cannot lose data already reported written.
  if (file_) std::fclose(file_);
}

void TumTrajectoryWriter::write(double t, const Eigen::Isometry3d& pose) { write_line(fmt::format("{:.9f}", t), pose); }

void TumTrajectoryWriter::write_ns(std::int64_t timestamp_ns, const Eigen::Isometry3d& pose) {
  write_text(tum_line_ns(timestamp_ns, pose));
}

void TumTrajectoryWriter::write_line(const std::string& time_text, const Eigen::Isometry3d& pose) {
  write_text(tum_text(time_text, pose));
}

void TumTrajectoryWriter::write_text(const std::string& line) {
  // One fwrite + fflush per pose: the line reaches the OS before the next frame is processed.
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0)
    throw OutputWriteError(fmt::format("{}: write failed ({})", path_.string(), std::strerror(errno)));
  ++lines_;
}

std::string tum_line_ns(std::int64_t timestamp_ns, const Eigen::Isometry3d& pose) {
  const char* sign = timestamp_ns < 0 ? "-" : "";
  const std::uint64_t magnitude =
      timestamp_ns < 0 ? static_cast<std::uint64_t>(-(timestamp_ns + 1)) + 1 : static_cast<std::uint64_t>(timestamp_ns);
  return tum_text(fmt::format("{}{}.{:09d}", sign, magnitude / 1'000'000'000ULL, magnitude % 1'000'000'000ULL), pose);
}

void write_tum(const fs::path& file, const Trajectory& trajectory) {
  TumTrajectoryWriter writer(file);
  for (const auto& stamped : trajectory) writer.write(stamped.t, stamped.pose);
}

// ---------------------------------------------------------------------------------------------- readers

namespace {

Eigen::Isometry3d pose_from(const Eigen::Vector3d& position, Eigen::Quaterniond rotation, const fs::path& file,
                            std::size_t line_number) {
  const double norm = rotation.norm();
  if (std::abs(norm - 1.0) > 1e-2)
    throw std::runtime_error(fmt::format("{}:{}: quaternion norm {:.4f} is not 1", file.string(), line_number, norm));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation.normalized().toRotationMatrix();
  pose.translation() = position;
  return pose;
}

std::vector<double> parse_all(const std::vector<std::string>& fields, const fs::path& file, std::size_t line_number) {
  std::vector<double> values;
  values.reserve(fields.size());
  for (const auto& field : fields) values.push_back(parse_double(field, file, line_number));
  return values;
}

std::string first_data_line(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open file", file.string()));
  std::string line;
  while (std::getline(in, line)) {
    const auto start = line.find_first_not_of(" \t\r");
    if (start != std::string::npos && line[start] != '#') return line;
  }
  throw std::runtime_error(fmt::format("{}: no trajectory data (empty or only comments)", file.string()));
}

}  // namespace

Trajectory read_tum(const fs::path& file) {
  Trajectory trajectory;
  TimestampSequence timestamps(file, "timestamp");
  for_each_data_line(file, [&](const std::string& line, std::size_t line_number) {
    const auto fields = split_numbers(line);
    if (fields.size() != 8)
      throw std::runtime_error(fmt::format("{}:{}: expected 8 numbers 't x y z qx qy qz qw', got {}", file.string(),
                                           line_number, fields.size()));
    const auto v = parse_all(fields, file, line_number);
    timestamps.add(v[0], line_number);
    trajectory.push_back(
        {v[0], pose_from({v[1], v[2], v[3]}, Eigen::Quaterniond(v[7], v[4], v[5], v[6]), file, line_number)});
  });
  return trajectory;
}

Trajectory read_euroc_csv(const fs::path& file, std::size_t* columns) {
  Trajectory trajectory;
  std::size_t column_count = 0;
  TimestampSequence timestamps(file, "timestamp");
  for_each_data_line(file, [&](const std::string& line, std::size_t line_number) {
    const auto fields = split_fields(line, ',');
    if (fields.size() < 8)
      throw std::runtime_error(fmt::format("{}:{}: expected 'timestamp_ns,px,py,pz,qw,qx,qy,qz', got {} fields",
                                           file.string(), line_number, fields.size()));
    if (column_count == 0) column_count = fields.size();
    const std::int64_t ns = parse_timestamp_ns(fields[0], file, line_number);
    timestamps.add(static_cast<long double>(ns), line_number);
    const auto v = parse_all(std::vector<std::string>(fields.begin() + 1, fields.begin() + 8), file, line_number);
    trajectory.push_back(
        {static_cast<double>(ns) * 1e-9,
         pose_from({v[0], v[1], v[2]}, Eigen::Quaterniond(v[3], v[4], v[5], v[6]), file, line_number)});
  });
  if (columns) *columns = column_count;
  return trajectory;
}

Trajectory read_positions(const fs::path& file) {
  Trajectory trajectory;
  for_each_data_line(file, [&](const std::string& line, std::size_t line_number) {
    const bool comma = line.find(',') != std::string::npos;
    const auto fields = comma ? split_fields(line, ',') : split_numbers(line);
    if (fields.size() != 4)
      throw std::runtime_error(fmt::format("{}:{}: expected 4 fields, 't x y z' or 'timestamp_ns,x,y,z', got {}",
                                           file.string(), line_number, fields.size()));
    const double t = comma ? static_cast<double>(parse_timestamp_ns(fields[0], file, line_number)) * 1e-9
                           : parse_double(fields[0], file, line_number);
    const auto v = parse_all(std::vector<std::string>(fields.begin() + 1, fields.end()), file, line_number);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    trajectory.push_back({t, pose});
  });
  return trajectory;
}

std::vector<double> read_kitti_times(const fs::path& file) {
  std::vector<double> times;
  TimestampSequence sequence(file);
  for_each_data_line(file, [&](const std::string& line, std::size_t line_number) {
    times.push_back(parse_double(line, file, line_number));
    sequence.add(times.back(), line_number);
  });
  return times;
}

Trajectory read_kitti_poses(const fs::path& file, const std::vector<double>& times) {
  Trajectory trajectory;
  for_each_data_line(file, [&](const std::string& line, std::size_t line_number) {
    const auto fields = split_numbers(line);
    if (fields.size() != 12)
      throw std::runtime_error(
          fmt::format("{}:{}: expected 12 numbers (3x4 pose), got {}", file.string(), line_number, fields.size()));
    const std::size_t index = trajectory.size();
    if (!times.empty() && index >= times.size())
      throw std::runtime_error(fmt::format("{}: more poses than the {} timestamps given", file.string(), times.size()));
    Eigen::Isometry3d pose;
    try {
      pose = isometry_from_row_major(parse_all(fields, file, line_number));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("{}:{}: {}", file.string(), line_number, e.what()));
    }
    const double t = times.empty() ? static_cast<double>(index) * KittiDataset::nominal_frame_period_s : times[index];
    trajectory.push_back({t, pose});
  });
  return trajectory;
}

TrajectoryFormat detect_trajectory_format(const fs::path& file) {
  const std::string line = first_data_line(file);
  const auto fields = split_numbers(line);
  if (line.find(',') != std::string::npos && fields.size() >= 8) return TrajectoryFormat::euroc_csv;
  if (fields.size() == 12) return TrajectoryFormat::kitti;
  if (fields.size() == 8) return TrajectoryFormat::tum;
  if (fields.size() == 4) return TrajectoryFormat::positions;
  throw std::runtime_error(
      fmt::format("{}: unknown trajectory format ({} fields on the first line; expected TUM "
                  "(8), KITTI (12), EuRoC CSV or positions 't x y z' (4))",
                  file.string(), fields.size()));
}

Trajectory read_trajectory(const fs::path& file, TrajectoryFormat format, const std::vector<double>& kitti_times) {
  if (format == TrajectoryFormat::automatic) format = detect_trajectory_format(file);
  switch (format) {
    case TrajectoryFormat::tum: return read_tum(file);
    case TrajectoryFormat::euroc_csv: return read_euroc_csv(file);
    case TrajectoryFormat::kitti: return read_kitti_poses(file, kitti_times);
    case TrajectoryFormat::positions: return read_positions(file);
    case TrajectoryFormat::automatic: break;
  }
  throw std::logic_error("read_trajectory: unresolved format");
}

// ---------------------------------------------------------------------------------------------- ground truth

namespace {

std::optional<fs::path> find_kitti_times(const fs::path& poses_file) {
  const fs::path beside = poses_file.parent_path() / "times.txt";
  if (fs::is_regular_file(beside)) return beside;
  const fs::path official = poses_file.parent_path().parent_path() / "sequences" / poses_file.stem() / "times.txt";
  if (fs::is_regular_file(official)) return official;
  return std::nullopt;
}

}  // namespace

GroundTruth read_groundtruth(const fs::path& file, const GroundTruthOptions& options) {
  GroundTruth gt;
  gt.format = detect_trajectory_format(file);
  PoseFrame frame = options.frame;
  bool orbslam3_euroc = false;  // ORB-SLAM3's EuRoC ground truth (see GroundTruthOrientation::automatic)
  switch (gt.format) {
    case TrajectoryFormat::euroc_csv: {
      std::size_t columns = 0;
      gt.poses = read_euroc_csv(file, &columns);
      // state_groundtruth_estimate0 has p, q, v, b_w, b_a (17 columns); the 8-column form is the cam0 pose.
      if (frame == PoseFrame::automatic) frame = columns >= 17 ? PoseFrame::body : PoseFrame::camera;
      gt.note = fmt::format("EuRoC CSV with {} columns", columns);
      orbslam3_euroc = columns == 8 && file.parent_path().filename() == "EuRoC_left_cam";
      break;
    }
    case TrajectoryFormat::kitti: {
      const auto times_file = options.kitti_times ? options.kitti_times : find_kitti_times(file);
      gt.poses = read_kitti_poses(file, times_file ? read_kitti_times(*times_file) : std::vector<double>{});
      gt.note = times_file ? fmt::format("KITTI poses, times from {}", times_file->string())
                           : std::string("KITTI poses, nominal 10 Hz timestamps");
      break;
    }
    case TrajectoryFormat::positions:
      if (frame == PoseFrame::body)
        throw std::runtime_error(
            fmt::format("{}: positions only: body poses cannot be converted to the camera "
                        "without their orientation",
                        file.string()));
      gt.poses = read_positions(file);
      gt.has_orientation = false;
      frame = PoseFrame::camera;  // the tracked point's frame is unknown; nothing to convert without rotations
      gt.note =
          "positions only (no orientation): ATE on positions, RPE on displacements, no rotation errors; "
          "the tracked point's offset from the camera is in the errors";
      break;
    default:
      gt.poses = read_tum(file);
      gt.note = "TUM";
      break;
  }
  GroundTruthOrientation orientation = options.orientation;
  if (orientation == GroundTruthOrientation::automatic)
    orientation = orbslam3_euroc ? GroundTruthOrientation::inverse : GroundTruthOrientation::as_written;
  if (orientation == GroundTruthOrientation::inverse) {  // before a body-to-camera conversion, which needs them
    for (auto& stamped : gt.poses) stamped.pose.linear() = stamped.pose.linear().transpose().eval();
    gt.note += "; rotations inverted (the file gives world-to-frame rotations)";
  }
  if (frame == PoseFrame::automatic) frame = PoseFrame::camera;
  gt.frame = frame;
  if (frame == PoseFrame::body) {
    std::optional<Eigen::Isometry3d> T_body_camera = options.T_body_camera;
    const fs::path guess = file.parent_path().parent_path() / "cam0" / "sensor.yaml";
    if (!T_body_camera) {
      if (options.sensor_yaml)
        gt.sensor_yaml = options.sensor_yaml;
      else if (fs::is_regular_file(guess))
        gt.sensor_yaml = guess;
      if (gt.sensor_yaml) T_body_camera = read_euroc_camera_yaml(*gt.sensor_yaml).T_body_camera;
    }
    if (T_body_camera) {
      for (auto& stamped : gt.poses) stamped.pose = stamped.pose * *T_body_camera;
      gt.frame = PoseFrame::camera;
      gt.body_to_camera_applied = true;
      gt.note += fmt::format("; body poses converted to cam0 with T_BS from {}",
                             gt.sensor_yaml ? gt.sensor_yaml->string() : std::string("the calibration"));
    } else {
      gt.note += "; body (IMU) poses, no cam0 sensor.yaml found: errors include the camera lever arm";
      spdlog::warn(
          "{}: ground truth is the body pose and no cam0 sensor.yaml was found (pass one to convert it to "
          "the camera frame); errors will include the body-camera lever arm",
          file.string());
    }
  }
  if (orientation == GroundTruthOrientation::none && gt.has_orientation) {  // after the conversion, which used them
    for (auto& stamped : gt.poses) stamped.pose.linear().setIdentity();
    gt.has_orientation = false;
    gt.note += "; rotations ignored (positions only)";
  }
  return gt;
}

std::optional<GroundTruth> read_dataset_groundtruth(const StereoDataset& dataset) {
  if (!dataset.groundtruth_path()) return std::nullopt;
  GroundTruthOptions options;
  options.T_body_camera = dataset.calibration().left.T_body_camera;
  if (dataset.times_path()) options.kitti_times = dataset.times_path();
  return read_groundtruth(*dataset.groundtruth_path(), options);
}

}  // namespace vkvo::io
