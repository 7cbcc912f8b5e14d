// The complete VO on the shared real clips (EuRoC MH_01 subset, KITTI 01 clip) with the real SuperPoint weights
// and the NN matcher, clean and under photometric stress (gain dropped to 25%, black frames, gamma flicker).
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "eval/evaluate.hpp"
#include "io/dataset.hpp"
#include "io/model_pack.hpp"
#include "io/trajectory.hpp"
#include "system/network_frontend.hpp"
#include "system/pipeline.hpp"
#include "tools/convert/convert.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

struct VoRun {
  RunResult result;
  eval::EvaluationResult evaluation;
};

// The SuperPoint pack converted once per process from the shared ONNX.
const io::ModelPack& superpoint_pack(const fs::path& shared) {
  static const io::ModelPack pack = [&] {
    const fs::path out = fs::temp_directory_path() / "vkvo_tests" / "superpoint_v1.vkvopack";
    fs::create_directories(out.parent_path());
    convert::convert_file(shared / "models" / "superpoint_v1.onnx", out);
    return io::ModelPack::load(out, io::NetworkKind::superpoint);
  }();
  return pack;
}

VoRun run_sequence(const fs::path& shared, const fs::path& dataset_dir, const char* config_name, const fs::path& out) {
  const VoConfig config = load_vo_config(test::source_dir() / "config" / config_name);
  const auto dataset = io::open_dataset(dataset_dir);
  auto features = make_network_frontend(test::gpu(), superpoint_pack(shared), nullptr, config);
  auto stereo = make_network_frontend(test::gpu(), superpoint_pack(shared), nullptr, config);
  RunOptions options;
  options.output_dir = out;
  options.progress = false;
  VoRun run;
  run.result = run_vo(*dataset, config, *features, *stereo, options);
  const auto groundtruth = io::read_dataset_groundtruth(*dataset);
  if (!groundtruth) throw std::runtime_error("no ground truth next to " + dataset_dir.string());
  run.evaluation = eval::evaluate(io::read_tum(run.result.trajectory), groundtruth->poses);
  spdlog::info("{}: {} frames, {} keyframes, {} losses, ATE RMSE {:.4f} m over {:.2f} m of path\n{}",
               dataset_dir.filename().string(), run.result.frames, run.result.keyframes, run.result.tracking_losses,
               run.evaluation.ate.translation_m.rmse, run.evaluation.drift.path_length_m,
               run.result.timing.table(run.result.frames, run.result.wall_seconds));
  return run;
}

// Gain 25% for a stretch, three black frames, and a gamma 0.5/2.0 flicker, spread over the clip.
std::vector<synth::IlluminationEvent> stress_events(int frames) {
  std::vector<synth::IlluminationEvent> events;
  events.push_back(synth::parse_event(fmt::format("off:{}-{},gain=0.25", frames / 5, frames / 5 + 10)));
  events.push_back(synth::make_event(synth::EventKind::lights_off, frames / 2, frames / 2 + 2));  // black
  events.push_back(synth::parse_event(fmt::format("gamma:{}-{},gain=0.5", 2 * frames / 3, 2 * frames / 3 + 9)));
  return events;
}

void check_clean_and_stressed(const fs::path& shared, const fs::path& sequence, const char* config, double max_ate,
                              bool relative_to_path) {
  const auto dir = test::temp_dir("vo");
  const VoRun clean = run_sequence(shared, sequence, config, dir / "clean");
  const double bound = relative_to_path ? max_ate * clean.evaluation.drift.path_length_m : max_ate;
  EXPECT_EQ(clean.result.tracking_losses, 0);
  EXPECT_EQ(clean.result.frames_skipped, 0u);
  EXPECT_LE(clean.evaluation.ate.translation_m.rmse, bound) << "clean run";

  const auto frames = static_cast<int>(io::open_dataset(sequence)->size());
  synth::perturb_sequence(sequence, dir / "stressed_sequence", stress_events(frames));
  const VoRun stressed = run_sequence(shared, dir / "stressed_sequence", config, dir / "stressed");
  EXPECT_EQ(stressed.result.frames + stressed.result.frames_skipped, clean.result.frames) << "every frame processed";
  EXPECT_LE(stressed.evaluation.ate.translation_m.rmse, 1.5 * std::max(clean.evaluation.ate.translation_m.rmse, 0.01))
      << "stressed run (clean ATE " << clean.evaluation.ate.translation_m.rmse << " m)";
}

TEST(VoData, EurocMh01SubsetWithinThreeCentimetres) {
  VKVO_REQUIRE_DATA(shared, "models/superpoint_v1.onnx");
  const fs::path sequence = *shared_root / "datasets" / "euroc_mh01_subset" / "MH_01_easy";
  check_clean_and_stressed(*shared_root, sequence, "euroc.yaml", 0.03, false);
}

TEST(VoData, Kitti01ClipWithinTwoPercentOfPath) {
  VKVO_REQUIRE_DATA(shared, "models/superpoint_v1.onnx");
  const fs::path sequence = *shared_root / "datasets" / "kitti_seq01_f000-050" / "KITTI_sequence_2";
  check_clean_and_stressed(*shared_root, sequence, "kitti.yaml", 0.02, true);
}

}  // namespace
}  // namespace vkvo::system
