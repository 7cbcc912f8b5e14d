// KITTI odometry sequence reader: image_0/image_1 (or image_l/image_r), calib.txt, times.txt.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <Eigen/Core>

#include "io/dataset.hpp"
#include "io/text_utils.hpp"
#include "io/trajectory.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

namespace {

struct ImageFolders {
  fs::path left, right;
};

std::optional<ImageFolders> image_folders(const fs::path& dir) {
  for (const auto& [l, r] : {std::pair{"image_0", "image_1"}, std::pair{"image_l", "image_r"}})
    if (fs::is_directory(dir / l) && fs::is_directory(dir / r)) return ImageFolders{dir / l, dir / r};
  return std::nullopt;
}

}  // namespace

StereoCalibration read_kitti_calib(const fs::path& calib_txt) {
  std::optional<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> P[2];
  std::size_t P_line[2] = {0, 0};
  std::size_t unlabelled = 0;
  for_each_data_line(calib_txt, [&](const std::string& line, std::size_t line_number) {
    auto fields = split_numbers(line);
    int slot = -1;
    if (!fields.empty() && fields.front().back() == ':') {  // "P0: ..." as in the official files
      const std::string label = fields.front().substr(0, fields.front().size() - 1);
      fields.erase(fields.begin());
      if (label == "P0")
        slot = 0;
      else if (label == "P1")
        slot = 1;
      else
        return;  // P2, P3, Tr: colour cameras and velodyne, not used
    } else {
      if (unlabelled >= 2) return;
      slot = static_cast<int>(unlabelled++);
    }
    if (fields.size() != 12)
      throw std::runtime_error(
          fmt::format("{}:{}: P{} needs 12 numbers, got {}", calib_txt.string(), line_number, slot, fields.size()));
    Eigen::Matrix<double, 3, 4, Eigen::RowMajor> matrix;
    for (int k = 0; k < 12; ++k) matrix(k / 4, k % 4) = parse_double(fields[k], calib_txt, line_number);
    P[slot] = matrix;
    P_line[slot] = line_number;
  });
  for (int slot = 0; slot < 2; ++slot)
    if (!P[slot]) throw std::runtime_error(fmt::format("{}: missing field 'P{}'", calib_txt.string(), slot));

  StereoCalibration calibration;
  calibration.rectified = true;
  for (int slot = 0; slot < 2; ++slot) {
    CameraCalibration& camera = slot == 0 ? calibration.left : calibration.right;
    camera.fx = (*P[slot])(0, 0);
    camera.fy = (*P[slot])(1, 1);
    camera.cx = (*P[slot])(0, 2);
    camera.cy = (*P[slot])(1, 2);
    camera.distortion = DistortionModel::none;
    camera.set_origin({"fx", "fy", "cx", "cy", "T_body_camera"},
                      {calib_txt.string(), fmt::format("P{}", slot), static_cast<int>(P_line[slot])});
  }
  if (!(calibration.left.fx > 0))
    throw std::runtime_error(fmt::format("{}: P0 has a non-positive focal length", calib_txt.string()));
  // P_i = K [I | t_i] with the x offset in P(0,3) = fx * t_x: camera 1 sits at +baseline along x of camera 0.
  const double baseline = ((*P[0])(0, 3) - (*P[1])(0, 3)) / calibration.left.fx;
  calibration.right.T_body_camera = Eigen::Isometry3d(Eigen::Translation3d(baseline, 0, 0));
  return calibration;
}

std::optional<fs::path> KittiDataset::find_root(const fs::path& path) {
  if (!fs::is_directory(path)) return std::nullopt;
  if (image_folders(path)) return path;
  std::optional<fs::path> found;
  for (const auto& entry : fs::directory_iterator(path)) {
    if (!entry.is_directory() || !image_folders(entry.path())) continue;
    if (found) return std::nullopt;  // several sequences: ambiguous
    found = entry.path();
  }
  return found;
}

KittiDataset::KittiDataset(const fs::path& path, const DatasetOptions& options) {
  const auto root = find_root(path);
  if (!root)
    throw std::runtime_error(
        fmt::format("{}: not a KITTI sequence (no image_0/image_1 or image_l/image_r folders, or several sequences)",
                    path.string()));
  root_ = *root;
  name_ = root_.filename().string();
  const ImageFolders folders = *image_folders(root_);

  std::vector<fs::path> left_images;
  for (const auto& entry : fs::directory_iterator(folders.left))
    if (entry.is_regular_file() && is_image_file(entry.path())) left_images.push_back(entry.path());
  std::sort(left_images.begin(), left_images.end());
  if (left_images.empty()) throw std::runtime_error(fmt::format("{}: no images", folders.left.string()));

  std::vector<double> times;
  if (fs::is_regular_file(root_ / "times.txt")) {
    times_path_ = root_ / "times.txt";
    times = read_kitti_times(*times_path_);
    if (times.size() < left_images.size())
      throw std::runtime_error(
          fmt::format("{}: {} timestamps for {} images", times_path_->string(), times.size(), left_images.size()));
  }

  // Timestamps are indexed by position in the full image list, so a missing right image does not shift them.
  std::size_t unpaired = 0;
  for (std::size_t k = 0; k < left_images.size(); ++k) {
    const fs::path right = folders.right / left_images[k].filename();
    if (!fs::exists(right)) {
      ++unpaired;
      continue;
    }
    StereoFrame frame;
    frame.sequence_index = frames_.size();
    frame.timestamp_s = times.empty() ? static_cast<double>(k) * nominal_frame_period_s : times[k];
    frame.timestamp_ns = static_cast<std::int64_t>(std::llround(frame.timestamp_s * 1e9));
    frame.left = left_images[k];
    frame.right = right;
    frames_.push_back(std::move(frame));
  }
  if (unpaired > 0) spdlog::warn("{}: {} left images have no right image and are skipped", root_.string(), unpaired);
  if (times.empty())
    spdlog::info("{}: no times.txt, using the nominal {:.0f} Hz frame rate", root_.string(),
                 1.0 / nominal_frame_period_s);

  std::string source = (root_ / "calib.txt").string();
  if (fs::is_regular_file(root_ / "calib.txt"))
    calibration_ = read_kitti_calib(root_ / "calib.txt");
  else
    source += " (missing)";
  // calib.txt has no image size: take it from the first image.
  if (!frames_.empty()) {
    const cv::Size size = image_size(frames_.front().left);
    calibration_.left.width = calibration_.right.width = size.width;
    calibration_.left.height = calibration_.right.height = size.height;
  }

  if (fs::is_regular_file(root_ / "poses.txt"))
    groundtruth_path_ = root_ / "poses.txt";
  else if (const fs::path official = root_.parent_path().parent_path() / "poses" / (name_ + ".txt");
           fs::is_regular_file(official))
    groundtruth_path_ = official;

  finish(options, source);
}

}  // namespace vkvo::io
