// EuRoC / ASL folder reader: mav0/cam{0,1}/{data.csv, data/, sensor.yaml}. Folders extracted from other
// datasets' bags (OIVIO, UMA-VI) often lack data.csv or sensor.yaml: images named by their timestamps and the
// calibration in the config's camera section stand in for them (config/oivio.yaml, config/uma_vi.yaml).
#include <algorithm>
#include <cctype>
#include <fstream>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/dataset.hpp"
#include "io/text_utils.hpp"
#include "io/yaml_utils.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

namespace {

// A camera folder lists its images in data.csv or, without one, holds them in data/ named by timestamp.
bool is_camera_folder(const fs::path& cam_dir) {
  return fs::is_regular_file(cam_dir / "data.csv") || fs::is_directory(cam_dir / "data");
}

bool is_mav0(const fs::path& dir) { return is_camera_folder(dir / "cam0") && is_camera_folder(dir / "cam1"); }

struct CameraEntry {
  std::int64_t timestamp_ns;
  fs::path image;
};

// cam<i>/data.csv: "#timestamp [ns],filename", CRLF or LF lines.
std::vector<CameraEntry> read_camera_csv(const fs::path& cam_dir) {
  const fs::path csv = cam_dir / "data.csv";
  std::vector<CameraEntry> entries;
  TimestampSequence timestamps(csv);
  for_each_data_line(csv, [&](const std::string& line, std::size_t line_number) {
    const auto fields = split_fields(line, ',');
    if (fields.size() < 2)
      throw std::runtime_error(fmt::format("{}:{}: expected 'timestamp,filename'", csv.string(), line_number));
    const std::int64_t timestamp_ns = parse_timestamp_ns(fields[0], csv, line_number);
    timestamps.add(static_cast<long double>(timestamp_ns), line_number);
    require_path_inside(fields[1], csv, line_number);
    entries.push_back({timestamp_ns, cam_dir / "data" / fields[1]});
  });
  return entries;
}

// cam<i>/data/ without a data.csv: every image named "<timestamp in ns>.<ext>", as AirVO's reader expects and
// bag-extraction tools write them.
std::vector<CameraEntry> read_camera_folder(const fs::path& cam_dir) {
  std::vector<CameraEntry> entries;
  for (const auto& entry : fs::directory_iterator(cam_dir / "data")) {
    if (!entry.is_regular_file() || !is_image_file(entry.path())) continue;
    std::int64_t timestamp_ns = 0;
    try {
      timestamp_ns = parse_timestamp_ns(entry.path().stem().string(), entry.path(), 0);
    } catch (const std::runtime_error&) {
      throw std::runtime_error(fmt::format("{}: without {} every image must be named by its timestamp in nanoseconds",
                                           entry.path().string(), (cam_dir / "data.csv").string()));
    }
    entries.push_back({timestamp_ns, entry.path()});
  }
  if (entries.empty())
    throw std::runtime_error(
        fmt::format("{}: no data.csv and no images in {}", cam_dir.string(), (cam_dir / "data").string()));
  return entries;
}

// The camera's images sorted by timestamp, from data.csv where there is one.
std::vector<CameraEntry> read_camera_images(const fs::path& cam_dir) {
  auto entries = fs::is_regular_file(cam_dir / "data.csv") ? read_camera_csv(cam_dir) : read_camera_folder(cam_dir);
  std::sort(entries.begin(), entries.end(),
            [](const CameraEntry& a, const CameraEntry& b) { return a.timestamp_ns < b.timestamp_ns; });
  return entries;
}

// ORB-SLAM3 style cam0 ground truth next to the sequence: <parent>/groundtruth/EuRoC_left_cam/MH01_GT.txt.
std::optional<fs::path> find_left_cam_groundtruth(const fs::path& sequence_dir) {
  const fs::path dir = sequence_dir.parent_path() / "groundtruth" / "EuRoC_left_cam";
  if (!fs::is_directory(dir)) return std::nullopt;
  std::string key;  // "MH_01_easy" -> "MH01", "V1_02_medium" -> "V102"
  for (char c : sequence_dir.filename().string())
    if (std::isalnum(static_cast<unsigned char>(c)) && key.size() < 4) key += c;
  std::vector<fs::path> candidates;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".txt") candidates.push_back(entry.path());
  for (const auto& candidate : candidates)
    if (!key.empty() && candidate.filename().string().rfind(key, 0) == 0) return candidate;
  if (candidates.size() == 1) return candidates.front();
  return std::nullopt;
}

}  // namespace

CameraCalibration read_euroc_camera_yaml(const fs::path& sensor_yaml, SensorYamlFields fields) {
  if (!fs::is_regular_file(sensor_yaml))
    throw std::runtime_error(fmt::format("{}: calibration file is missing", sensor_yaml.string()));
  const YAML::Node root = load_yaml_file(sensor_yaml);
  if (!root.IsMap()) throw std::runtime_error(fmt::format("{}: expected a YAML map", sensor_yaml.string()));

  // A field is read where it is present; an absent one is an error unless the caller has another source for it.
  const auto should_read = [&](const char* field) {
    const YAML::Node node = root[field];
    return (node.IsDefined() && !node.IsNull()) || fields == SensorYamlFields::all_required;
  };
  CameraCalibration camera;
  const auto model = root["camera_model"];
  if (model.IsDefined() && model.as<std::string>() != "pinhole")
    throw std::runtime_error(fmt::format("{}: camera_model '{}' is not supported (pinhole only)", sensor_yaml.string(),
                                         model.as<std::string>()));
  if (should_read("resolution")) {
    std::tie(camera.width, camera.height) = required_resolution(root["resolution"], sensor_yaml, "resolution");
    camera.set_origin({"width", "height"}, origin_of(root["resolution"], sensor_yaml, "resolution"));
  }
  if (should_read("intrinsics")) {
    const auto intrinsics = required_numbers(root["intrinsics"], sensor_yaml, "intrinsics", 4);
    camera.fx = intrinsics[0];
    camera.fy = intrinsics[1];
    camera.cx = intrinsics[2];
    camera.cy = intrinsics[3];
    camera.set_origin({"fx", "fy", "cx", "cy"}, origin_of(root["intrinsics"], sensor_yaml, "intrinsics"));
  }
  if (should_read("distortion_model")) {
    const std::string distortion = required_string(root["distortion_model"], sensor_yaml, "distortion_model");
    try {
      camera.distortion = parse_distortion_model(distortion);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("{}: field 'distortion_model': {}", sensor_yaml.string(), e.what()));
    }
  }
  if (should_read("distortion_coefficients")) {
    camera.distortion_coeffs =
        required_numbers(root["distortion_coefficients"], sensor_yaml, "distortion_coefficients", 0);
    camera.set_origin({"distortion_coeffs"},
                      origin_of(root["distortion_coefficients"], sensor_yaml, "distortion_coefficients"));
  }
  if (should_read("T_BS")) {
    const YAML::Node T_BS = root["T_BS"];
    if (!T_BS.IsDefined() || !T_BS.IsMap())
      throw std::runtime_error(fmt::format("{}: missing field 'T_BS'", sensor_yaml.string()));
    try {
      camera.T_body_camera = isometry_from_row_major(required_numbers(T_BS["data"], sensor_yaml, "T_BS.data", 16));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("{}: field 'T_BS': {}", sensor_yaml.string(), e.what()));
    }
    camera.set_origin({"T_body_camera"}, origin_of(T_BS["data"], sensor_yaml, "T_BS.data"));
  }
  return camera;
}

std::optional<fs::path> EurocDataset::find_root(const fs::path& path) {
  if (!fs::is_directory(path)) return std::nullopt;
  if (is_mav0(path)) return path;
  if (is_mav0(path / "mav0")) return path / "mav0";
  std::optional<fs::path> found;
  for (const auto& entry : fs::directory_iterator(path)) {
    if (!entry.is_directory() || !is_mav0(entry.path() / "mav0")) continue;
    if (found) return std::nullopt;  // several sequences: ambiguous, the caller must pick one
    found = entry.path() / "mav0";
  }
  return found;
}

EurocDataset::EurocDataset(const fs::path& path, const DatasetOptions& options) {
  const auto mav0 = find_root(path);
  if (!mav0)
    throw std::runtime_error(fmt::format(
        "{}: not an EuRoC dataset (no mav0/cam0 and mav0/cam1 with data.csv or data/, or several sequences)",
        path.string()));
  root_ = *mav0;
  name_ = root_.filename() == "mav0" ? root_.parent_path().filename().string() : root_.filename().string();

  const auto left = read_camera_images(root_ / "cam0");
  const auto right = read_camera_images(root_ / "cam1");

  // sensor.yaml, or where it is missing the config's camera section (validated in finish()) with the image size
  // taken from the first image.
  const bool config_gives_cameras = options.camera_overrides.IsDefined() && !options.camera_overrides.IsNull();
  std::string source = (root_ / "cam{0,1}" / "sensor.yaml").string();
  const auto read_calibration = [&](const char* cam, const std::vector<CameraEntry>& images) {
    const fs::path sensor_yaml = root_ / cam / "sensor.yaml";
    CameraCalibration camera;
    if (fs::is_regular_file(sensor_yaml)) {
      // With the cameras in the config, a sensor.yaml may be partial: the config fills in what it leaves out.
      camera = read_euroc_camera_yaml(
          sensor_yaml, config_gives_cameras ? SensorYamlFields::present_only : SensorYamlFields::all_required);
    } else if (config_gives_cameras) {
      source += fmt::format(" ({} missing)", cam);
    } else {
      throw std::runtime_error(
          fmt::format("{}: calibration file is missing (or give the cameras in the config's camera section)",
                      sensor_yaml.string()));
    }
    if (camera.width <= 0 || camera.height <= 0) {
      if (images.empty()) throw std::runtime_error(fmt::format("{}: lists no images", (root_ / cam).string()));
      const cv::Size size = image_size(images.front().image);
      camera.width = size.width;
      camera.height = size.height;
    }
    return camera;
  };
  calibration_.left = read_calibration("cam0", left);
  calibration_.right = read_calibration("cam1", right);
  calibration_.rectified = false;
  // Pair by timestamp (both lists sorted): the VI-sensor triggers both cameras together, but a dropped frame on
  // one side must not shift all later pairs.
  std::size_t i = 0, j = 0, unpaired = 0;
  while (i < left.size() && j < right.size()) {
    const std::int64_t dt = left[i].timestamp_ns - right[j].timestamp_ns;
    if (std::abs(dt) <= options.max_stereo_dt_ns) {
      StereoFrame frame;
      frame.sequence_index = frames_.size();
      frame.timestamp_ns = left[i].timestamp_ns;
      frame.timestamp_s = static_cast<double>(frame.timestamp_ns) * 1e-9;
      frame.left = left[i].image;
      frame.right = right[j].image;
      frames_.push_back(std::move(frame));
      ++i;
      ++j;
    } else if (dt < 0) {
      ++i, ++unpaired;
    } else {
      ++j, ++unpaired;
    }
  }
  unpaired += (left.size() - i) + (right.size() - j);
  if (unpaired > 0)
    spdlog::warn("{}: {} camera images have no stereo partner and are skipped", root_.string(), unpaired);

  if (fs::is_regular_file(root_ / "state_groundtruth_estimate0" / "data.csv"))
    groundtruth_path_ = root_ / "state_groundtruth_estimate0" / "data.csv";
  else
    groundtruth_path_ = find_left_cam_groundtruth(root_.parent_path());

  finish(options, source);
}

}  // namespace vkvo::io
