#include "io/run_summary.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/yaml_utils.hpp"

namespace vkvo::io {

namespace fs = std::filesystem;

void write_json_file(const fs::path& file, const nlohmann::json& document) {
  write_file_atomically(file, [&](std::ostream& out) { out << document.dump(2) << '\n'; });
}

nlohmann::json to_json(const CameraCalibration& camera) {
  const Eigen::Matrix4d T = camera.T_body_camera.matrix();
  std::vector<double> row_major;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) row_major.push_back(T(r, c));
  return {{"width", camera.width},
          {"height", camera.height},
          {"fx", camera.fx},
          {"fy", camera.fy},
          {"cx", camera.cx},
          {"cy", camera.cy},
          {"distortion_model", to_string(camera.distortion)},
          {"distortion_coeffs", camera.distortion_coeffs},
          {"T_body_camera", row_major}};
}

nlohmann::json to_json(const StereoCalibration& calibration) {
  return {{"left", to_json(calibration.left)},
          {"right", to_json(calibration.right)},
          {"rectified", calibration.rectified},
          {"baseline_m", calibration.baseline()}};
}

nlohmann::json describe_dataset(const StereoDataset& dataset) {
  nlohmann::json description = {{"kind", to_string(dataset.kind())},
                                {"name", dataset.name()},
                                {"root", dataset.root().string()},
                                {"frames", dataset.size()},
                                {"calibration", to_json(dataset.calibration())}};
  if (!dataset.empty()) {
    description["first_timestamp_ns"] = dataset.frame(0).timestamp_ns;
    description["last_timestamp_ns"] = dataset.frame(dataset.size() - 1).timestamp_ns;
    description["first_sequence_index"] = dataset.frame(0).sequence_index;
  }
  description["groundtruth"] =
      dataset.groundtruth_path() ? nlohmann::json(dataset.groundtruth_path()->string()) : nlohmann::json(nullptr);
  return description;
}

}  // namespace vkvo::io
