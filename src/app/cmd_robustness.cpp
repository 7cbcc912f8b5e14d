// `vkvo robustness`: the robustness benchmark (tools/robustness): a sequence clean and under a fixed set of
// photometric events, each run evaluated against the ground truth, as a table, JSON and a plot.
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/exit_codes.hpp"
#include "app/vo_frontends.hpp"
#include "io/dataset.hpp"
#include "tools/robustness/robustness.hpp"

namespace {

namespace fs = std::filesystem;

struct Options {
  fs::path config = "config/euroc.yaml";
  fs::path dataset;
  fs::path out = "vkvo_robustness";
  std::string matcher;
  fs::path model, superglue, feature_cache;
  std::vector<std::string> scenarios;
  vkvo::app::DeviceSelection device;
  bool ablate_lines = false, keep_sequences = false, list = false;
};

int run(const Options& o) {
  vkvo::system::VoConfig config = vkvo::system::load_vo_config(o.config);
  if (!o.matcher.empty()) config.matcher = o.matcher;
  if (const auto precision = o.device.chosen_precision()) {
    config.point_detector.precision = precision;
    config.point_matcher.precision = precision;
  }
  // The events are placed on the whole sequence: the benchmark runs all of it.
  config.dataset.range = {};
  const auto dataset = vkvo::io::open_dataset(o.dataset, config.dataset);
  if (dataset->size() < 2)
    throw std::runtime_error(fmt::format("{}: too few frames for a benchmark", o.dataset.string()));
  const double duration = dataset->frame(dataset->size() - 1).timestamp_s - dataset->frame(0).timestamp_s;
  const double rate = static_cast<double>(dataset->size() - 1) / duration;
  const auto all = vkvo::robustness::standard_scenarios(static_cast<int>(dataset->size()), rate);
  if (o.list) {
    for (const auto& s : all) fmt::print("{:<16} {}\n", s.name, s.description);
    return 0;
  }
  const auto scenarios = vkvo::robustness::select_scenarios(all, o.scenarios);

  vkvo::app::FrontendOptions frontend_options{
      .superpoint = o.model, .superglue = o.superglue, .device = o.device.context_options(), .cache_in_memory = true};
  if (!o.feature_cache.empty()) frontend_options.feature_cache = o.feature_cache;
  vkvo::app::VoFrontends frontends(config, frontend_options);
  const auto results = vkvo::robustness::run_benchmark(
      o.dataset, config, scenarios, frontends.feature(), frontends.stereo(),
      {.out_dir = o.out, .ablate_lines = o.ablate_lines, .keep_sequences = o.keep_sequences});
  fmt::print("\n{} ({} frames at {:.1f} Hz), {}\n\n{}\ntable: {}\nplot:  {}\n", dataset->name(), dataset->size(), rate,
             frontends.description()["device"].get<std::string>(), vkvo::robustness::format_table(results),
             (o.out / "robustness.md").string(), (o.out / "robustness.png").string());
  // A run the events defeated is a result; a run that could not be made or evaluated is not.
  std::size_t untracked_runs = 0;
  for (const auto& r : results) {
    if (r.error == vkvo::robustness::kNoFrameTracked)
      ++untracked_runs;
    else if (!r.error.empty())
      return vkvo::app::kExitBadInput;
  }
  if (untracked_runs == results.size()) return vkvo::app::kExitNoResult;
  return vkvo::app::kExitOk;
}

vkvo::app::CommandRegistration registration{
    {"robustness",
     "the robustness benchmark: a sequence clean and under lights-off, dimming, flicker and exposure events",
     [](CLI::App& sub) {
       auto o = std::make_shared<Options>();
       sub.add_option("--config", o->config, "YAML configuration")->check(CLI::ExistingFile);
       sub.add_option("--dataset", o->dataset, "sequence with ground truth (EuRoC/ASL or KITTI folder)");
       sub.add_option("--out", o->out, "output folder (one run per scenario, robustness.md/.json/.png)");
       sub.add_option("--matcher", o->matcher, "superglue | nn (overrides the config)")
           ->check(CLI::IsMember({"superglue", "nn"}));
       sub.add_option("--model", o->model, "SuperPoint pack or ONNX");
       sub.add_option("--superglue", o->superglue, "SuperGlue pack or ONNX");
       sub.add_option("--scenarios", o->scenarios, "run only these scenarios (names as --list shows them)");
       sub.add_flag("--ablate-lines", o->ablate_lines, "run every scenario without lines too");
       sub.add_flag("--keep-sequences", o->keep_sequences, "keep the perturbed copies of the sequence");
       sub.add_option("--feature-cache", o->feature_cache,
                      "keep SuperPoint's features in this folder across benchmark runs");
       sub.add_flag("--list", o->list, "list the scenarios for this sequence and stop");
       vkvo::app::add_precision_option(sub, o->device);
       vkvo::app::add_device_option(sub, o->device);
       sub.callback([o, &sub] {
         if (!o->list && o->dataset.empty()) throw CLI::RequiredError("--dataset");
       });
       return std::function<int()>([o] { return run(*o); });
     }}};

}  // namespace
