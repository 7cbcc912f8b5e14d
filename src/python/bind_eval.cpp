// vkvo.evaluate: a trajectory file against ground truth, the metrics as `vkvo eval --json` writes them.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "eval/evaluate.hpp"
#include "python/arrays.hpp"
#include "python/bindings.hpp"
#include "python/common.hpp"

namespace vkvo::python {
namespace {

py::object evaluate(const fs::path& estimate, const fs::path& groundtruth, const std::string& align, double max_dt,
                    const std::vector<double>& rpe_lengths, std::size_t rpe_step,
                    const std::optional<fs::path>& body_to_camera, const std::optional<fs::path>& kitti_times) {
  existing_path(estimate, "estimate");
  existing_path(groundtruth, "ground truth");
  io::GroundTruthOptions groundtruth_options;
  if (body_to_camera) {  // as `vkvo eval --body-to-camera`: the ground truth is then the body's
    groundtruth_options.sensor_yaml = existing_path(*body_to_camera, "body_to_camera");
    groundtruth_options.frame = io::PoseFrame::body;
  }
  if (kitti_times) groundtruth_options.kitti_times = existing_path(*kitti_times, "kitti_times");
  eval::EvalOptions options;
  if (align != "none" && align != "se3" && align != "sim3")
    raise(PyExc_ValueError, "align '" + align + "': expected none, se3 or sim3");
  options.alignment = eval::parse_alignment_mode(align);
  if (max_dt <= 0) raise(PyExc_ValueError, "max_dt: expected a positive number of seconds");
  options.max_dt_s = max_dt;
  options.rpe.lengths_m = rpe_lengths;
  options.rpe.step = rpe_step;
  nlohmann::json document;
  {
    const py::gil_scoped_release release;
    document = eval::to_json(eval::evaluate_files(estimate, groundtruth, groundtruth_options, options));
  }
  return json_to_python(document);
}

}  // namespace

void bind_eval(py::module_& m) {
  m.def("evaluate", &evaluate, py::arg("estimate"), py::arg("groundtruth"), py::kw_only(), py::arg("align") = "se3",
        py::arg("max_dt") = eval::EvalOptions{}.max_dt_s, py::arg("rpe_lengths") = std::vector<double>{},
        py::arg("rpe_step") = std::size_t{1}, py::arg("body_to_camera") = py::none(),
        py::arg("kitti_times") = py::none(),
        R"(An estimated trajectory against ground truth, as `vkvo eval`: ATE, RPE and drift.

estimate: TUM, EuRoC CSV, KITTI poses or positions file; groundtruth: the same formats (EuRoC body poses are
turned into left-camera poses with cam0's sensor.yaml next to them, or the one body_to_camera names).
align: "none", "se3" or "sim3"; max_dt: association tolerance in seconds; rpe_lengths: segment lengths in
metres (default 10, 20, ..., 50 % of the path); kitti_times: KITTI times.txt for poses files.
Returns the report as a dict: the document `vkvo eval --json` writes (ate_translation_m["rmse"], ...).)");
}

}  // namespace vkvo::python
