// `vkvo run`: the stereo VO on a dataset folder (EuRoC/ASL or KITTI), writing the trajectory as it goes, then the
// map, a summary and the timing table; with ground truth next to the dataset, the ATE too.
#include <atomic>
#include <csignal>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "eval/evaluate.hpp"
#include "io/dataset.hpp"
#include "io/trajectory.hpp"
#include "runtime/host.hpp"
#include "system/network_frontend.hpp"
#include "system/pipeline.hpp"
#include "tools/convert/model_locator.hpp"

namespace {

namespace fs = std::filesystem;
std::atomic<bool> g_stop{false};

struct Options {
  fs::path config = "config/euroc.yaml";
  fs::path dataset;
  fs::path out = "vkvo_out";
  std::string matcher;  // overrides the config
  bool no_lines = false;
  fs::path model, superglue;
  std::optional<std::size_t> first, stride;  // unset: the config's dataset section (or the whole sequence)
  std::optional<long long> last;
  bool realtime = false;
  std::string precision;
};

int run(const Options& o) {
  vkvo::system::VoConfig config = vkvo::system::load_vo_config(o.config);
  if (o.no_lines) config.tracking.use_lines = false;
  if (!o.matcher.empty()) config.matcher = o.matcher;
  if (!o.precision.empty()) {  // auto (the device's preferred precision) or one that CLI11 has checked
    config.point_detector.precision = vkvo::rt::parse_precision(o.precision);
    config.point_matcher.precision = config.point_detector.precision;
  }

  vkvo::io::DatasetOptions dataset_options = config.dataset;
  if (o.first) dataset_options.range.first = *o.first;
  if (o.stride) dataset_options.range.stride = *o.stride;
  if (o.last) {
    if (*o.last >= 0) dataset_options.range.last = static_cast<std::size_t>(*o.last);
    else dataset_options.range.last.reset();
  }
  const auto dataset = vkvo::io::open_dataset(o.dataset, dataset_options);
  spdlog::info("dataset {} ({}): {} stereo frames", dataset->name(), vkvo::io::to_string(dataset->kind()),
               dataset->size());

  const auto model_search = vkvo::convert::default_model_search(VKVO_SOURCE_DIR);
  const auto superpoint = vkvo::convert::locate_model(
      "superpoint_v1", o.model.empty() ? config.superpoint_model : o.model, model_search);
  if (!superpoint) throw std::runtime_error(vkvo::convert::superpoint_help());
  spdlog::info("SuperPoint: {} [{}]", superpoint->pack.string(), superpoint->how);
  const auto superpoint_pack = vkvo::io::ModelPack::load(superpoint->pack, vkvo::io::NetworkKind::superpoint);
  std::optional<vkvo::io::ModelPack> superglue_pack;
  if (config.matcher == "superglue") {
    const fs::path explicit_superglue = o.superglue.empty() ? config.superglue_model : o.superglue;
    if (!explicit_superglue.empty()) {
      const auto superglue = vkvo::convert::locate_model("superglue", explicit_superglue, model_search);
      superglue_pack = vkvo::io::ModelPack::load(superglue->pack, vkvo::io::NetworkKind::superglue);
      spdlog::info("SuperGlue: {} [{}]", superglue->pack.string(), superglue->how);
    } else {
      spdlog::warn("no SuperGlue pack configured (models.superglue / --superglue): matching with the "
                   "mutual-nearest-neighbour matcher");
    }
  }

  const vkvo::rt::Context context;
  const std::string host = vkvo::rt::host_cpu().describe();
  spdlog::info("Vulkan device: {} ({}); host: {}", context.caps().name, context.caps().type, host);
  const auto* superglue = superglue_pack ? &*superglue_pack : nullptr;
  auto feature_frontend = vkvo::system::make_network_frontend(context, superpoint_pack, superglue, config);
  auto stereo_frontend = vkvo::system::make_network_frontend(context, superpoint_pack, superglue, config);

  std::signal(SIGINT, [](int) { g_stop = true; });
  vkvo::system::RunOptions run_options;
  run_options.output_dir = o.out;
  run_options.realtime = o.realtime;
  run_options.stop = &g_stop;
  run_options.extra_summary = {{"device", context.caps().name},
                               {"host", host},
                               {"matcher", superglue ? "superglue" : "nn"},
                               {"superpoint_model", superpoint->pack.string()}};
  const auto result = vkvo::system::run_vo(*dataset, config, *feature_frontend, *stereo_frontend, run_options);

  fmt::print("\n{} frames ({} skipped), {} keyframes, {} tracking losses, {} map segment(s), map: {} points, {} lines\n",
             result.frames, result.frames_skipped, result.keyframes, result.tracking_losses, result.segments,
             result.map_points, result.map_lines);
  fmt::print("{}", result.timing.table(result.frames, result.wall_seconds));
  fmt::print("trajectory: {}\nkeyframes:  {}\nsummary:    {}\nmap:        {}\n", result.trajectory.string(),
             result.keyframes_file.string(), result.summary.string(), (o.out / "map.ply").string());
  if (const auto gt = vkvo::io::read_dataset_groundtruth(*dataset)) {
    try {
      vkvo::eval::EvalOptions eval_options;
      eval_options.positions_only = !gt->has_orientation;
      const auto evaluation = vkvo::eval::evaluate(vkvo::io::read_tum(result.trajectory), gt->poses, eval_options);
      fmt::print("ATE RMSE {:.4f} m (SE3 alignment, {} poses) against {}\n", evaluation.ate.translation_m.rmse,
                 evaluation.associated_poses, dataset->groundtruth_path()->string());
    } catch (const std::exception& e) {
      spdlog::warn("evaluation skipped: {}", e.what());
    }
  }
  return g_stop ? 130 : 0;
}

vkvo::app::CommandRegistration registration{
    {"run", "run the stereo VO on an EuRoC/ASL or KITTI folder", [](CLI::App& sub) {
       auto o = std::make_shared<Options>();
       sub.add_option("--config", o->config, "YAML configuration (config/euroc.yaml, kitti.yaml, oivio.yaml, uma_vi.yaml)")
           ->check(CLI::ExistingFile);
       sub.add_option("--dataset", o->dataset, "dataset folder (EuRoC mav0 or its parent; KITTI sequence)")->required();
       sub.add_option("--out", o->out, "output folder");
       sub.add_option("--matcher", o->matcher, "superglue | nn (overrides the config)")
           ->check(CLI::IsMember({"superglue", "nn"}));
       sub.add_flag("--no-lines", o->no_lines, "points only (the paper's w/o-line ablation)");
       sub.add_option("--model", o->model, "SuperPoint pack or ONNX (default: config, $VKVO_MODELS, models/, ../shared/models)");
       sub.add_option("--superglue", o->superglue, "SuperGlue pack or ONNX (default: config models.superglue)");
       sub.add_option("--first", o->first, "first frame index (overrides the config's dataset.first_frame)");
       sub.add_option("--last", o->last, "last frame index, inclusive; -1: to the end (dataset.last_frame)");
       sub.add_option("--stride", o->stride, "use every n-th frame (dataset.stride)")->check(CLI::PositiveNumber);
       sub.add_flag("--realtime", o->realtime, "play the sequence back at its recorded rate");
       sub.add_option("--precision", o->precision, "network precision: auto | fp32 | fp16s | fp16")
           ->check(CLI::IsMember({"auto", "fp32", "fp16s", "fp16"}));
       return std::function<int()>([o] { return run(*o); });
     }}};

}  // namespace
