#pragma once
// JSON output for run summaries and evaluation reports.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "io/calibration.hpp"
#include "io/dataset.hpp"

namespace vkvo::io {

// Pretty-prints `document` to `file` (parent folders created) through a temporary file and a rename, so an
// interrupted run leaves the previous summary intact. Throws std::runtime_error naming the file on failure.
void write_json_file(const std::filesystem::path& file, const nlohmann::json& document);

// Building blocks for a run summary.
nlohmann::json to_json(const CameraCalibration& camera);
nlohmann::json to_json(const StereoCalibration& calibration);
// kind, name, root, frame count, first/last timestamps, calibration, ground-truth path.
nlohmann::json describe_dataset(const StereoDataset& dataset);

}  // namespace vkvo::io
