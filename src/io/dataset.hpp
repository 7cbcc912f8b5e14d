#pragma once
// Stereo datasets on disk: a list of timestamped image pairs, the calibration and, when there is one, the
// ground-truth trajectory. Images are only read when asked for (load_*), so opening a long sequence is cheap.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <opencv2/core.hpp>

#include "io/calibration.hpp"

namespace vkvo::io {

enum class DatasetKind { euroc, kitti };
const char* to_string(DatasetKind kind);

struct StereoFrame {
  std::size_t sequence_index = 0;  // index in the full sequence (before the frame range is applied)
  std::int64_t timestamp_ns = 0;
  double timestamp_s = 0;  // same instant in seconds (loses sub-microsecond digits for EuRoC epochs)
  std::filesystem::path left;
  std::filesystem::path right;
};

struct StereoImages {
  cv::Mat left;   // CV_8UC1
  cv::Mat right;  // CV_8UC1
};

// Which frames of the sequence to use: sequence indices first, first + stride, ... up to `last` (inclusive).
struct FrameRange {
  std::size_t first = 0;
  std::optional<std::size_t> last;  // inclusive; nullopt = to the end
  std::size_t stride = 1;
  // Frames of the sequence left out (inclusive index ranges), e.g. to drop a stretch and see the camera reappear
  // elsewhere (a "kidnap"). The frames left keep their timestamps.
  std::vector<std::pair<std::size_t, std::size_t>> skip;
};
// "A-B" (inclusive) or "A"; throws std::invalid_argument naming the text.
std::pair<std::size_t, std::size_t> parse_frame_span(const std::string& text);

struct DatasetOptions {
  FrameRange range;
  // A `camera:` config section (see io::apply_camera_overrides) applied on top of the dataset's calibration;
  // required for datasets that come without a calibration file.
  YAML::Node camera_overrides;
  std::string config_file;  // where camera_overrides was read, for error messages
  // EuRoC: left/right images whose timestamps differ by more than this are not paired.
  std::int64_t max_stereo_dt_ns = 1'000'000;
};

// Whether a file name has an image extension the readers decode (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff; any case).
bool is_image_file(const std::filesystem::path& file);

// Reads a `dataset:` config section: first_frame (0), last_frame (-1 = to the end, inclusive), stride (1),
// skip (a list of "A-B" frame spans to leave out, []), max_stereo_dt_ms (1.0). `camera` is the `camera:` section kept
// as overrides (may be empty).
DatasetOptions load_dataset_options(const YAML::Node& dataset_section, const YAML::Node& camera_section = {});

class StereoDataset {
 public:
  virtual ~StereoDataset() = default;
  StereoDataset(const StereoDataset&) = delete;
  StereoDataset& operator=(const StereoDataset&) = delete;

  virtual DatasetKind kind() const = 0;
  // Folder the dataset was opened from after normalisation (EuRoC: the `mav0` folder; KITTI: the sequence folder).
  const std::filesystem::path& root() const { return root_; }
  // A short name for logs and summaries: the sequence folder name (e.g. "MH_01_easy", "KITTI_sequence_2").
  const std::string& name() const { return name_; }

  std::size_t size() const { return frames_.size(); }
  bool empty() const { return frames_.empty(); }
  const StereoFrame& frame(std::size_t i) const;
  const std::vector<StereoFrame>& frames() const { return frames_; }

  // Both images of frame i as 8-bit grayscale. Throws std::runtime_error naming the file when it is missing,
  // cannot be decoded, or its size disagrees with the calibration.
  StereoImages load(std::size_t i) const;
  cv::Mat load_left(std::size_t i) const;
  cv::Mat load_right(std::size_t i) const;

  const StereoCalibration& calibration() const { return calibration_; }

  // The ground-truth file found next to the dataset, if any (EuRoC: state_groundtruth_estimate0/data.csv, or a
  // single file in ../groundtruth/EuRoC_left_cam/; KITTI: poses.txt or ../../poses/<seq>.txt).
  const std::optional<std::filesystem::path>& groundtruth_path() const { return groundtruth_path_; }
  // KITTI: the times.txt the timestamps came from (ground truth readers need it too); nullopt otherwise.
  const std::optional<std::filesystem::path>& times_path() const { return times_path_; }

 protected:
  StereoDataset() = default;
  // Called by implementations once frames_ (full sequence) and calibration_ are filled: applies the overrides and
  // the frame range, validates the calibration.
  void finish(const DatasetOptions& options, const std::string& calibration_source);
  // The size of an image file, for calibrations that do not give it; throws naming the file when it cannot be read.
  static cv::Size image_size(const std::filesystem::path& file);

  std::filesystem::path root_;
  std::string name_;
  std::vector<StereoFrame> frames_;
  StereoCalibration calibration_;
  std::optional<std::filesystem::path> groundtruth_path_;
  std::optional<std::filesystem::path> times_path_;

 private:
  cv::Mat load_image(const std::filesystem::path& file, const CameraCalibration& camera) const;
};

// EuRoC / ASL folder: accepts the `mav0` folder, the sequence folder that contains it, or a folder whose only
// sequence child contains it (e.g. .../euroc_mh01_subset). Calibration from cam0/cam1 sensor.yaml, or where they
// are missing from the config's camera section (DatasetOptions::camera_overrides; the image size then comes from
// the first image); stereo pairs from cam0/data.csv and cam1/data.csv matched by timestamp, or without them from
// the images in cam0/data and cam1/data named by their nanosecond timestamps (AirVO's layout).
class EurocDataset final : public StereoDataset {
 public:
  explicit EurocDataset(const std::filesystem::path& path, const DatasetOptions& options = {});
  DatasetKind kind() const override { return DatasetKind::euroc; }
  // The mav0 folder for a path, or nullopt when `path` is not an EuRoC dataset.
  static std::optional<std::filesystem::path> find_root(const std::filesystem::path& path);
};

// KITTI odometry sequence folder: image_0/image_1 (or image_l/image_r), calib.txt with the rectified P0/P1
// (labelled "P0:" or bare 12-number lines), times.txt when present (else 10 Hz nominal).
class KittiDataset final : public StereoDataset {
 public:
  explicit KittiDataset(const std::filesystem::path& path, const DatasetOptions& options = {});
  DatasetKind kind() const override { return DatasetKind::kitti; }
  static std::optional<std::filesystem::path> find_root(const std::filesystem::path& path);
  static constexpr double nominal_frame_period_s = 0.1;
};

// Detects the dataset kind from the folder layout and opens it. Throws std::runtime_error naming the path
// when it is neither kind.
std::unique_ptr<StereoDataset> open_dataset(const std::filesystem::path& path, const DatasetOptions& options = {});

// Parsers exposed for tests and tools.
// EuRoC cam sensor.yaml -> resolution, intrinsics, distortion, T_BS. Throws naming the file and the field that is
// malformed or (unless `present_only`, for callers with another source such as the config) missing; fields left
// out keep CameraCalibration's defaults.
enum class SensorYamlFields { all_required, present_only };
CameraCalibration read_euroc_camera_yaml(const std::filesystem::path& sensor_yaml,
                                         SensorYamlFields fields = SensorYamlFields::all_required);
// KITTI calib.txt -> rectified stereo calibration (width/height left 0: taken from the images).
StereoCalibration read_kitti_calib(const std::filesystem::path& calib_txt);

}  // namespace vkvo::io
