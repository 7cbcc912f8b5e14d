// `vkvo run`: the stereo VO on a dataset folder (EuRoC/ASL or KITTI), writing the trajectory as it goes, then the
// map, a summary and the timing table; with ground truth next to the dataset, the ATE too; with --video, the
// overlay video of the frames and a top-down picture of the map.
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/exit_codes.hpp"
#include "app/vo_frontends.hpp"
#include "io/dataset.hpp"
#include "system/pipeline.hpp"
#include "viz/video_recorder.hpp"

namespace {

namespace fs = std::filesystem;
std::atomic<bool> g_stop{false};
volatile std::sig_atomic_t g_signal = 0;

// SIGINT, SIGTERM (docker stop, systemd, timeout) and SIGHUP end the run after the current frame with every output
// written; a second signal exits at once.
void on_stop_signal(int signal) {
  if (g_signal != 0) std::_Exit(128 + signal);
  g_signal = signal;
  g_stop = true;
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal, &action, nullptr);
}

struct Options {
  fs::path config = "config/euroc.yaml";
  fs::path dataset;
  fs::path out = "vkvo_out";
  std::string matcher;  // overrides the config
  bool no_lines = false;
  fs::path model, superglue;
  std::optional<std::size_t> first, stride;  // unset: the config's dataset section (or the whole sequence)
  std::optional<long long> last;
  std::vector<std::string> skip;
  bool realtime = false;
  vkvo::app::DeviceSelection device;
  fs::path feature_cache;
  fs::path video;  // empty: none
};

int run(const Options& o) {
  vkvo::system::VoConfig config = vkvo::system::load_vo_config(o.config);
  if (o.no_lines) config.tracking.use_lines = false;
  if (!o.matcher.empty()) config.matcher = o.matcher;
  if (const auto precision = o.device.chosen_precision()) {
    config.point_detector.precision = precision;
    config.point_matcher.precision = precision;
  }

  vkvo::io::DatasetOptions dataset_options = config.dataset;
  if (o.first) dataset_options.range.first = *o.first;
  if (o.stride) dataset_options.range.stride = *o.stride;
  for (const std::string& span : o.skip) dataset_options.range.skip.push_back(vkvo::io::parse_frame_span(span));
  if (o.last) {
    if (*o.last >= 0)
      dataset_options.range.last = static_cast<std::size_t>(*o.last);
    else
      dataset_options.range.last.reset();
  }
  const auto dataset = vkvo::io::open_dataset(o.dataset, dataset_options);
  spdlog::info("dataset {} ({}): {} stereo frames", dataset->name(), vkvo::io::to_string(dataset->kind()),
               dataset->size());

  // Opened before the networks load, so that a path it cannot write fails at once.
  std::optional<vkvo::viz::VideoRecorder> video;
  if (!o.video.empty()) video.emplace(o.video, vkvo::viz::video_format(*dataset));

  vkvo::app::FrontendOptions frontend_options{
      .superpoint = o.model, .superglue = o.superglue, .device = o.device.context_options()};
  if (!o.feature_cache.empty()) frontend_options.feature_cache = o.feature_cache;
  vkvo::app::VoFrontends frontends(config, frontend_options);

  install_stop_handlers();
  vkvo::system::RunOptions run_options;
  run_options.output_dir = o.out;
  run_options.realtime = o.realtime;
  run_options.stop = &g_stop;
  run_options.extra_summary = frontends.description();
  run_options.observer = video ? &*video : nullptr;
  const auto result = vkvo::system::run_vo(*dataset, config, frontends.feature(), frontends.stereo(), run_options);
  if (const auto& cache = frontends.cache())
    spdlog::info("feature cache {}: {} image(s) came from it", cache->folder() ? cache->folder()->string() : "(memory)",
                 cache->hits());

  fmt::print(
      "\n{} frames ({} skipped), {} keyframes, {} tracking losses, {} relocalisation(s), {} map segment(s) "
      "at the end ({} started, {} merged, {} rebuilt), map: {} points ({} mono), {} lines ({} mono)\n",
      result.frames, result.frames_skipped, result.keyframes, result.tracking_losses, result.relocalisations,
      result.segments, result.segments_started, result.merges, result.segments_rebuilt, result.map_points,
      result.map_mono_points, result.map_lines, result.map_mono_lines);
  fmt::print("{}", result.timing.table(result.frames, result.wall_seconds));
  fmt::print("trajectory: {}\nframes:     {}\nkeyframes:  {} (refined: {})\nsummary:    {}\nmap:        {}\n",
             result.trajectory.string(), result.frames_file.string(), result.keyframes_file.string(),
             result.keyframes_refined_file.string(), result.summary.string(), (o.out / "map.ply").string());
  if (video) {
    video->close();
    const auto stats = video->stats();
    const double frames = static_cast<double>(std::max<std::size_t>(1, stats.frames));
    fmt::print("video:      {} ({} frames; per frame {:.1f} ms drawing, {:.1f} ms encoding, on its own thread)\n",
               video->file().string(), stats.frames, stats.draw_ms / frames, stats.encode_ms / frames);
    fmt::print("top-down:   {}\n", video->topdown_file().string());
  }
  // A run that never tracked a frame has no trajectory worth an ATE; say so and fail (docs/bad-input.md).
  const bool usable = result.frames_tracked > 0;
  if (const auto& e = result.evaluation; usable && !e.is_null()) {
    const auto rmse = [&](const char* key, const char* stats) -> std::string {
      if (!e.contains(key)) return "n/a";
      const auto& s = e[key][stats];
      return s["count"].get<std::size_t>()
                 ? fmt::format("{:.4f} m ({} poses)", s["rmse"].get<double>(), s["count"].get<std::size_t>())
                 : std::string("none");
    };
    fmt::print(
        "ATE RMSE against {} (SE3 alignment):\n  every frame      {}\n  tracked frames   {}\n"
        "  bridged frames   {}\n  refined keyframes {}\n",
        e["groundtruth"].get<std::string>(), rmse("trajectory", "ate_translation_m"),
        rmse("trajectory_by_state", "measured_translation_m"), rmse("trajectory_by_state", "bridged_translation_m"),
        rmse("keyframes_refined", "ate_translation_m"));
  }
  if (g_signal != 0) return 128 + g_signal;
  if (result.frames == 0) {
    spdlog::error("no frame could be used ({} of them skipped as unreadable or of the wrong size): nothing to report",
                  result.frames_skipped);
    return vkvo::app::kExitNoResult;
  }
  if (!usable) {
    spdlog::error("no frame was tracked ({} processed, {} before tracking started): the trajectory is empty",
                  result.frames, result.frames_uninitialised);
    return vkvo::app::kExitNoResult;
  }
  return vkvo::app::kExitOk;
}

vkvo::app::CommandRegistration registration{
    {"run", "run the stereo VO on an EuRoC/ASL or KITTI folder", [](CLI::App& sub) {
       auto o = std::make_shared<Options>();
       sub.add_option("--config", o->config,
                      "YAML configuration (config/euroc.yaml, kitti.yaml, oivio.yaml, uma_vi.yaml)")
           ->check(CLI::ExistingFile);
       sub.add_option("--dataset", o->dataset, "dataset folder (EuRoC mav0 or its parent; KITTI sequence)")->required();
       sub.add_option("--out", o->out, "output folder");
       sub.add_option("--matcher", o->matcher, "superglue | nn (overrides the config)")
           ->check(CLI::IsMember({"superglue", "nn"}));
       sub.add_flag("--no-lines", o->no_lines, "points only (the paper's w/o-line ablation)");
       sub.add_option("--model", o->model,
                      "SuperPoint pack or ONNX (default: config, $VKVO_MODELS, models/, ../shared/models)");
       sub.add_option("--superglue", o->superglue, "SuperGlue pack or ONNX (default: config models.superglue)");
       sub.add_option("--first", o->first, "first frame index (overrides the config's dataset.first_frame)");
       sub.add_option("--last", o->last, "last frame index, inclusive; -1: to the end (dataset.last_frame)");
       sub.add_option("--skip", o->skip, "leave out frames A-B of the sequence (repeatable; dataset.skip)");
       sub.add_option("--stride", o->stride, "use every n-th frame (dataset.stride)")->check(CLI::PositiveNumber);
       sub.add_flag("--realtime", o->realtime, "play the sequence back at its recorded rate");
       sub.add_option("--feature-cache", o->feature_cache,
                      "keep SuperPoint's features of every image in this folder and reuse them in later runs "
                      "(the same weights, detector settings and device)");
       sub.add_option("--video", o->video,
                      "write the frames with their keypoints, lines and tracking state to this video (.mp4 or "
                      ".avi), and a top-down picture of the map beside it (<stem>_topdown.png)");
       vkvo::app::add_precision_option(sub, o->device);
       vkvo::app::add_device_option(sub, o->device);
       return std::function<int()>([o] { return run(*o); });
     }}};

}  // namespace
