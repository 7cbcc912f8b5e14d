// vkvo.Dataset, vkvo.Odometry and vkvo.run: the VO on pairs handed in one at a time (StereoOdometry, the live
// camera's interface) or on a whole dataset folder (run_vo, as `vkvo run`).
#include <signal.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "io/dataset.hpp"
#include "io/kalibr_camchain.hpp"
#include "python/arrays.hpp"
#include "python/bindings.hpp"
#include "python/common.hpp"
#include "runtime/host.hpp"
#include "system/network_frontend.hpp"
#include "system/pipeline.hpp"
#include "system/stereo_odometry.hpp"
#include "tools/convert/model_locator.hpp"
#include "viz/video_recorder.hpp"

namespace vkvo::python {
namespace {

// What the keyword arguments of Odometry and run change in the config, as `vkvo run`'s options do; unset keeps
// the config's.
struct VoArguments {
  std::optional<fs::path> model, superglue;
  std::optional<std::string> matcher, precision;
  std::optional<bool> lines;
  std::string device;

  system::VoConfig config(const fs::path& file) const {
    system::VoConfig config = system::load_vo_config(existing_path(file, "config"));
    if (lines) config.tracking.use_lines = *lines;
    if (matcher) {
      if (*matcher != "superglue" && *matcher != "nn")
        raise(PyExc_ValueError, fmt::format("matcher '{}': expected superglue or nn", *matcher));
      config.matcher = *matcher;
    }
    if (precision) config.point_detector.precision = config.point_matcher.precision = precision_argument(*precision);
    if (model) config.superpoint_model = existing_path(*model, "SuperPoint model");
    if (superglue) config.superglue_model = existing_path(*superglue, "SuperGlue model");
    return config;
  }
};

// The networks of a VO on one device: SuperPoint (and SuperGlue where the config asks for it and has one) twice,
// for the feature stage and for the keyframes' right images, as `vkvo run` sets them up.
struct VoNetworks {
  std::shared_ptr<const rt::Context> context;
  convert::VoModels models;
  std::unique_ptr<system::PointFrontend> features, keyframes;

  VoNetworks(const system::VoConfig& config, const std::string& device)
      : context(shared_context(device)),
        models(convert::load_vo_models(config.superpoint_model, config.superglue_model, config.matcher == "superglue",
                                       convert::default_model_search(VKVO_SOURCE_DIR))) {
    const io::ModelPack* superglue = models.superglue ? &*models.superglue : nullptr;
    features = system::make_network_frontend(*context, models.superpoint, superglue, config);
    keyframes = system::make_network_frontend(*context, models.superpoint, superglue, config);
  }
};

// The `dataset:` section's frame range with run's first / last / stride arguments applied (last < 0: to the end).
io::DatasetOptions dataset_options(const system::VoConfig& config, std::optional<std::size_t> first,
                                   std::optional<long long> last, std::optional<std::size_t> stride) {
  io::DatasetOptions options = config.dataset;
  if (first) options.range.first = *first;
  if (stride) {
    if (*stride == 0) raise(PyExc_ValueError, "stride: expected a positive number");
    options.range.stride = *stride;
  }
  if (last) {
    if (*last >= 0)
      options.range.last = static_cast<std::size_t>(*last);
    else
      options.range.last.reset();
  }
  return options;
}

// The status of one tracked pair, as a dict (one place to add what OdometryPose gains).
py::dict pose_status(const system::OdometryPose& pose) {
  using namespace py::literals;
  // A merge moves every earlier pose of segment merge["from"] into the world by merge["T_into_from"].
  py::object merge = py::none();
  if (pose.merge)
    merge = py::dict("from"_a = pose.merge->from, "into"_a = pose.merge->into,
                     "T_into_from"_a = Eigen::Matrix4d(pose.merge->T_into_from.matrix()));
  return py::dict("frame_index"_a = pose.frame_index, "timestamp_ns"_a = pose.timestamp_ns, "tracked"_a = pose.tracked,
                  "state"_a = system::to_string(pose.state), "keyframe"_a = pose.keyframe,
                  "new_segment"_a = pose.new_segment, "segment"_a = pose.segment, "merge"_a = merge,
                  "tracked_points"_a = pose.tracked_points, "tracked_lines"_a = pose.tracked_lines,
                  "note"_a = pose.note);
}

// A run's counts and outputs, as a dict (one place to add what RunResult gains).
py::dict run_summary(const system::RunResult& result) {
  using namespace py::literals;
  return py::dict("frames"_a = result.frames, "frames_skipped"_a = result.frames_skipped,
                  "frames_tracked"_a = result.frames_tracked, "untracked_frames"_a = result.untracked_frames,
                  "frames_bridged"_a = result.frames_bridged, "last_frame_tracked"_a = result.last_frame_tracked,
                  "frames_uninitialised"_a = result.frames_uninitialised, "keyframes"_a = result.keyframes,
                  "tracking_losses"_a = result.tracking_losses, "relocalisations"_a = result.relocalisations,
                  "merges"_a = result.merges, "segments_rebuilt"_a = result.segments_rebuilt,
                  "segments"_a = result.segments, "segments_started"_a = result.segments_started,
                  "map_points"_a = result.map_points, "map_lines"_a = result.map_lines,
                  "wall_seconds"_a = result.wall_seconds,
                  "timing"_a = json_to_python(result.timing.to_json(result.frames, result.wall_seconds)),
                  "evaluation"_a = json_to_python(result.evaluation), "trajectory"_a = result.trajectory,
                  "frames_file"_a = result.frames_file, "keyframes_file"_a = result.keyframes_file,
                  "keyframes_refined_file"_a = result.keyframes_refined_file, "summary"_a = result.summary);
}

class DatasetObject {
 public:
  DatasetObject(const fs::path& path, const std::optional<fs::path>& config, std::optional<std::size_t> first,
                std::optional<long long> last, std::optional<std::size_t> stride) {
    const system::VoConfig vo_config =
        config ? system::load_vo_config(existing_path(*config, "config")) : system::VoConfig{};
    existing_path(path, "dataset");
    dataset_ = io::open_dataset(path, dataset_options(vo_config, first, last, stride));
  }

  std::size_t size() const { return dataset_->size(); }

  py::tuple item(long long index) const {
    const auto n = static_cast<long long>(dataset_->size());
    if (index < 0) index += n;
    if (index < 0 || index >= n) raise(PyExc_IndexError, fmt::format("frame {} of a dataset of {}", index, n));
    io::StereoImages images;
    {
      const py::gil_scoped_release release;
      images = dataset_->load(static_cast<std::size_t>(index));
    }
    return py::make_tuple(image_to_python(images.left), image_to_python(images.right),
                          dataset_->frame(static_cast<std::size_t>(index)).timestamp_ns);
  }

  std::vector<std::int64_t> timestamps_ns() const {
    std::vector<std::int64_t> t;
    for (const auto& frame : dataset_->frames()) t.push_back(frame.timestamp_ns);
    return t;
  }

  const io::StereoDataset& dataset() const { return *dataset_; }

 private:
  std::unique_ptr<io::StereoDataset> dataset_;
};

// A calibration argument: None (the config's camera section), a vkvo.Dataset, a dataset folder, or a Kalibr
// camchain file.
io::StereoCalibration calibration_argument(const py::object& calibration, const system::VoConfig& config) {
  if (calibration.is_none()) return system::config_calibration(config);
  if (py::isinstance<DatasetObject>(calibration))
    return calibration.cast<const DatasetObject&>().dataset().calibration();
  const fs::path path = existing_path(calibration.cast<fs::path>(), "calibration");
  if (fs::is_directory(path)) return io::open_dataset(path, config.dataset)->calibration();
  return io::read_kalibr_camchain(path);
}

class OdometryObject {
 public:
  OdometryObject(const fs::path& config, const py::object& calibration, const VoArguments& arguments)
      : config_(arguments.config(config)) {
    const io::StereoCalibration rig = calibration_argument(calibration, config_);
    const py::gil_scoped_release release;
    networks_ = std::make_unique<VoNetworks>(config_, arguments.device);
    odometry_ = std::make_unique<system::StereoOdometry>(config_, rig, *networks_->features, *networks_->keyframes);
  }

  py::tuple track(const py::handle& left, const py::handle& right, std::int64_t timestamp_ns) {
    const ImageArgument l = image_argument(left, "Odometry.track left");
    const ImageArgument r = image_argument(right, "Odometry.track right");
    system::OdometryPose pose;
    {
      const py::gil_scoped_release release;
      const std::lock_guard lock(mutex_);
      pose = odometry_->track(l.mat, r.mat, timestamp_ns);
    }
    return py::make_tuple(Eigen::Matrix4d(pose.T_world_camera.matrix()), pose_status(pose));
  }

  int keyframes() const { return odometry_->keyframes(); }
  int tracking_losses() const { return odometry_->tracking_losses(); }
  int segments() const { return odometry_->segments(); }
  int relocalisations() const { return odometry_->relocalisations(); }
  std::string device() const { return networks_->context->caps().name; }

 private:
  system::VoConfig config_;
  std::unique_ptr<VoNetworks> networks_;  // before the odometry, which uses them until destroyed
  std::unique_ptr<system::StereoOdometry> odometry_;
  std::mutex mutex_;
};

// Ctrl-C during a run: Python's handler cannot run while the GIL is released, so for the run's duration (on the
// main thread) SIGINT ends the run cleanly after the current frame, as in `vkvo run`, and KeyboardInterrupt is
// raised once its outputs are written.
class InterruptScope {
 public:
  InterruptScope() {
    const py::module_ threading = py::module_::import("threading");
    if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return;
    flag().store(false);
    struct sigaction action {};
    action.sa_handler = [](int) { flag().store(true); };
    sigemptyset(&action.sa_mask);
    installed_ = sigaction(SIGINT, &action, &previous_) == 0;
  }
  ~InterruptScope() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  static std::atomic<bool>& flag() {
    static std::atomic<bool> interrupted{false};
    return interrupted;
  }
  bool interrupted() const { return installed_ && flag().load(); }

 private:
  struct sigaction previous_ {};
  bool installed_ = false;
};

py::dict run(const fs::path& config_file, const fs::path& dataset_path, const fs::path& out,
             std::optional<std::size_t> first, std::optional<long long> last, std::optional<std::size_t> stride,
             const VoArguments& arguments, bool realtime, bool progress, const std::optional<fs::path>& video) {
  const system::VoConfig config = arguments.config(config_file);
  existing_path(dataset_path, "dataset");
  const io::DatasetOptions options = dataset_options(config, first, last, stride);
  InterruptScope interrupt;
  system::RunResult result;
  std::optional<fs::path> video_file, topdown_file;
  std::size_t video_frames = 0;
  {
    const py::gil_scoped_release release;
    const auto dataset = io::open_dataset(dataset_path, options);
    std::optional<viz::VideoRecorder> recorder;  // opened before the networks load: a bad path fails at once
    if (video) recorder.emplace(*video, viz::video_format(*dataset));
    const VoNetworks networks(config, arguments.device);
    system::RunOptions run_options;
    run_options.output_dir = out;
    run_options.realtime = realtime;
    run_options.progress = progress;
    run_options.stop = &InterruptScope::flag();
    run_options.observer = recorder ? &*recorder : nullptr;
    run_options.extra_summary = {{"device", networks.context->caps().name},
                                 {"host", rt::host_cpu().describe()},
                                 {"matcher", networks.models.superglue ? "superglue" : "nn"},
                                 {"superpoint_model", networks.models.superpoint_file.pack.string()}};
    result = system::run_vo(*dataset, config, *networks.features, *networks.keyframes, run_options);
    if (recorder) {
      recorder->close();
      video_file = recorder->file();
      topdown_file = recorder->topdown_file();
      video_frames = recorder->stats().frames;
    }
  }
  if (interrupt.interrupted())
    raise(PyExc_KeyboardInterrupt, fmt::format("run stopped after {} frames; its "
                                               "outputs are in {}",
                                               result.frames, out.string()));
  py::dict summary = run_summary(result);
  if (video_file) {
    summary["video"] = *video_file;
    summary["topdown"] = *topdown_file;
    summary["video_frames"] = video_frames;
  }
  return summary;
}

VoArguments vo_arguments(const std::optional<fs::path>& model, const std::optional<fs::path>& superglue,
                         const std::optional<std::string>& matcher, const std::optional<bool>& lines,
                         const std::optional<std::string>& precision, const py::object& device) {
  return {.model = model,
          .superglue = superglue,
          .matcher = matcher,
          .precision = precision,
          .lines = lines,
          .device = device_argument(device)};
}

}  // namespace

void bind_odometry(py::module_& m) {
  py::class_<DatasetObject>(m, "Dataset", R"(A stereo dataset folder (EuRoC/ASL or KITTI), read lazily.

config: a VO config whose dataset/camera sections apply (frame range, calibration overrides); first, last
(inclusive, < 0: to the end) and stride override its range. ds[i] is (left, right, timestamp_ns), the images
uint8 (H, W) grey as the files hold them (unrectified); len(ds) frames; iterable.)")
      .def(py::init<const fs::path&, const std::optional<fs::path>&, std::optional<std::size_t>,
                    std::optional<long long>, std::optional<std::size_t>>(),
           py::arg("path"), py::kw_only(), py::arg("config") = py::none(), py::arg("first") = py::none(),
           py::arg("last") = py::none(), py::arg("stride") = py::none())
      .def("__len__", &DatasetObject::size)
      .def("__getitem__", &DatasetObject::item, py::arg("index"))
      .def_property_readonly("timestamps_ns", &DatasetObject::timestamps_ns)
      .def_property_readonly("name", [](const DatasetObject& d) { return d.dataset().name(); })
      .def_property_readonly("kind", [](const DatasetObject& d) { return io::to_string(d.dataset().kind()); })
      .def_property_readonly("root", [](const DatasetObject& d) { return d.dataset().root(); })
      .def_property_readonly(
          "groundtruth", [](const DatasetObject& d) { return d.dataset().groundtruth_path(); },
          "The ground-truth file found next to the dataset (for vkvo.evaluate), or None.");

  py::class_<OdometryObject>(m, "Odometry", R"(The stereo VO for pairs handed in one at a time (a live camera).

config: a VO config file (config/euroc.yaml, ...). calibration: None (the config's camera section), a
vkvo.Dataset or dataset folder (its calibration), or a Kalibr camchain file. model, superglue: SuperPoint /
SuperGlue pack or ONNX (default: the config's models section, then where `vkvo run` looks); matcher
("superglue" | "nn"), lines (False: points only), precision ("auto" | "fp32" | "fp16s" | "fp16") override the
config; device as for vkvo.SuperPoint.)")
      .def(py::init([](const fs::path& config, const py::object& calibration, const std::optional<fs::path>& model,
                       const std::optional<fs::path>& superglue, const std::optional<std::string>& matcher,
                       const std::optional<bool>& lines, const std::optional<std::string>& precision,
                       const py::object& device) {
             return std::make_unique<OdometryObject>(config, calibration,
                                                     vo_arguments(model, superglue, matcher, lines, precision, device));
           }),
           py::arg("config"), py::arg("calibration") = py::none(), py::kw_only(), py::arg("model") = py::none(),
           py::arg("superglue") = py::none(), py::arg("matcher") = py::none(), py::arg("lines") = py::none(),
           py::arg("precision") = py::none(), py::arg("device") = py::none())
      .def("track", &OdometryObject::track, py::arg("left"), py::arg("right"), py::arg("timestamp_ns"),
           R"(One raw (unrectified) stereo pair, uint8 grey or BGR at the calibration's size.

Returns (pose, status): pose the 4 x 4 float64 T_world_camera of the left camera (world: the left camera at
the first frame); status a dict: frame_index, timestamp_ns, tracked (False: predicted at the last velocity),
state ("tracked", "relocalised" or "lost"), keyframe, new_segment, segment, merge, tracked_points,
tracked_lines, note. merge, when not None, says that this frame joined map segment merge["from"] to
merge["into"]: every earlier pose of segment "from" maps into the world by merge["T_into_from"] (4 x 4).)")
      .def_property_readonly("keyframes", &OdometryObject::keyframes)
      .def_property_readonly("tracking_losses", &OdometryObject::tracking_losses)
      .def_property_readonly("segments", &OdometryObject::segments)
      .def_property_readonly("relocalisations", &OdometryObject::relocalisations)
      .def_property_readonly("device", &OdometryObject::device);

  m.def(
      "run",
      [](const fs::path& config, const fs::path& dataset, const fs::path& out, std::optional<std::size_t> first,
         std::optional<long long> last, std::optional<std::size_t> stride, const std::optional<fs::path>& model,
         const std::optional<fs::path>& superglue, const std::optional<std::string>& matcher,
         const std::optional<bool>& lines, const std::optional<std::string>& precision, const py::object& device,
         bool realtime, bool progress, const std::optional<fs::path>& video) {
        return run(config, dataset, out, first, last, stride,
                   vo_arguments(model, superglue, matcher, lines, precision, device), realtime, progress, video);
      },
      py::arg("config"), py::arg("dataset"), py::arg("out"), py::kw_only(), py::arg("first") = py::none(),
      py::arg("last") = py::none(), py::arg("stride") = py::none(), py::arg("model") = py::none(),
      py::arg("superglue") = py::none(), py::arg("matcher") = py::none(), py::arg("lines") = py::none(),
      py::arg("precision") = py::none(), py::arg("device") = py::none(), py::arg("realtime") = false,
      py::arg("progress") = true, py::arg("video") = py::none(),
      R"(The VO on a dataset folder, as `vkvo run`: writes trajectory.txt (TUM), keyframes.txt, map.ply and
summary.json into `out` as it goes. first / last (inclusive; < 0: to the end) / stride select frames; the
other keywords as for vkvo.Odometry. video: a .mp4 or .avi file for the overlay video of the frames (as
`vkvo run --video`; docs/video.md), with <stem>_topdown.png beside it. Returns the run's counts and output
paths as a dict (with video: "video", "topdown", "video_frames"). Ctrl-C ends the
run after the current frame, keeps its outputs and raises KeyboardInterrupt.)");
}

}  // namespace vkvo::python
