// Line pipeline timings on a 752x480 image: LE = detect + merge + filter (the paper's "line extraction"),
// LM = associate + match (the paper's "line matching"), and the parts. Uses the EuRoC SuperPoint golden pair
// (image + 400 keypoints) when ../shared is present, else a synthetic image with random keypoints.
// Run single-threaded for the one-core figures: OPENCV_FOR_THREADS_NUM=1 / taskset -c 0.
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "features/lines/line_detector.hpp"
#include "features/lines/line_matching.hpp"
#include "features/lines/line_merge.hpp"
#include "features/lines/point_line_association.hpp"
#include "io/npy.hpp"

namespace {

using namespace vkvo::features;
namespace fs = std::filesystem;

struct Frame {
  cv::Mat image;
  std::vector<Eigen::Vector2f> keypoints;
};

std::optional<fs::path> golden_dir() {
  if (const char* env = std::getenv("VKVO_DATA"); env && *env) return fs::path(env) / "golden";
  for (fs::path p : {fs::path("../shared"), fs::path("../../shared")})
    if (fs::exists(p / "golden/superpoint/euroc_0000/image.png")) return p / "golden";
  return std::nullopt;
}

Frame synthetic_frame(uint32_t seed) {
  Frame f;
  f.image = cv::Mat(480, 752, CV_8UC1, cv::Scalar(70));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> ux(0, 751), uy(0, 479), ug(0, 255);
  for (int k = 0; k < 120; ++k)
    cv::line(f.image, {ux(rng), uy(rng)}, {ux(rng), uy(rng)}, cv::Scalar(ug(rng)), 1 + k % 3, cv::LINE_AA);
  std::uniform_real_distribution<float> fx(0, 751), fy(0, 479);
  for (int i = 0; i < 400; ++i) f.keypoints.emplace_back(fx(rng), fy(rng));
  return f;
}

Frame load_frame(const std::string& name, uint32_t seed) {
  const auto dir = golden_dir();
  if (!dir) return synthetic_frame(seed);
  Frame f;
  f.image = cv::imread((*dir / "superpoint" / name / "image.png").string(), cv::IMREAD_GRAYSCALE);
  const auto xy = vkvo::io::read_npy(*dir / "superpoint" / name / "keypoints.npy").to_floats();
  for (size_t i = 0; i + 1 < xy.size(); i += 2) f.keypoints.emplace_back(xy[i], xy[i + 1]);
  return f;
}

const Frame& frame_a() {
  static const Frame f = load_frame("euroc_0000", 1);
  return f;
}
const Frame& frame_b() {
  static const Frame f = load_frame("euroc_0005", 2);
  return f;
}

// Point matches for the pair: SuperGlue golden matches when present, else index identity (synthetic).
const std::vector<int>& point_matches() {
  static const std::vector<int> m = [] {
    if (const auto dir = golden_dir()) {
      const auto v = vkvo::io::read_npy(*dir / "superglue_synthetic/euroc_0000_0005/matches0.npy").to_int32s();
      return std::vector<int>(v.begin(), v.end());
    }
    std::vector<int> identity(frame_a().keypoints.size());
    for (size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<int>(i);
    return identity;
  }();
  return m;
}

void configure_threads(benchmark::State& state) {
  cv::setNumThreads(static_cast<int>(state.range(0)));
  state.counters["threads"] = static_cast<double>(state.range(0));
}

void BM_LE_DetectMergeFilter(benchmark::State& state) {
  configure_threads(state);
  LineDetectorParams params;
  params.method = state.range(1) ? LineDetectorMethod::kLsd : LineDetectorMethod::kFastLineDetector;
  const LineDetector detector(params);
  size_t lines = 0;
  for (auto _ : state) {
    auto result = detector.detect(frame_a().image);
    lines = result.size();
    benchmark::DoNotOptimize(result);
  }
  state.counters["lines"] = static_cast<double>(lines);
  state.SetLabel(state.range(1) ? "lsd" : "fld");
}
BENCHMARK(BM_LE_DetectMergeFilter)->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LE_RawDetectOnly(benchmark::State& state) {
  configure_threads(state);
  const LineDetector detector{LineDetectorParams{}};
  size_t raw = 0;
  for (auto _ : state) {
    auto result = detector.detect_raw(frame_a().image);
    raw = result.size();
    benchmark::DoNotOptimize(result);
  }
  state.counters["raw_segments"] = static_cast<double>(raw);
}
BENCHMARK(BM_LE_RawDetectOnly)->Args({1})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LE_MergeAndFilterOnly(benchmark::State& state) {
  const LineDetectorParams params;
  const auto raw = LineDetector(params).detect_raw(frame_a().image);
  for (auto _ : state) {
    std::vector<LineSegment> segments = raw;
    for (const MergeStage& stage : params.merge_stages) {
      segments = merge_segments(std::move(segments), stage.merge);
      filter_short_segments(segments, stage.min_length_after);
    }
    filter_short_segments(segments, params.min_length);
    benchmark::DoNotOptimize(segments);
  }
  state.counters["raw_segments"] = static_cast<double>(raw.size());
}
BENCHMARK(BM_LE_MergeAndFilterOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

// Association alone, grid vs brute force, on the detected lines (range(0) = 1: grid) and on 300 random lines
// (range(1) = 1), the 400 points x 300 lines case.
void BM_Associate(benchmark::State& state) {
  const bool grid = state.range(0) != 0;
  std::vector<LineSegment> lines;
  if (state.range(1)) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> ux(0, 751), uy(0, 479), ul(30, 300), ua(0, 6.28f);
    for (int l = 0; l < 300; ++l) {
      const Eigen::Vector2f p0(ux(rng), uy(rng));
      const float a = ua(rng);
      lines.push_back({p0, p0 + ul(rng) * Eigen::Vector2f(std::cos(a), std::sin(a))});
    }
  } else {
    lines = LineDetector(LineDetectorParams{}).detect(frame_a().image);
  }
  const AssociationParams params;
  for (auto _ : state) {
    auto a = grid ? associate_points_to_lines(frame_a().keypoints, lines, params)
                  : associate_points_to_lines_brute_force(frame_a().keypoints, lines, params);
    benchmark::DoNotOptimize(a);
  }
  state.counters["lines"] = static_cast<double>(lines.size());
  state.counters["points"] = static_cast<double>(frame_a().keypoints.size());
  state.SetLabel(grid ? "grid" : "brute_force");
}
BENCHMARK(BM_Associate)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond)->UseRealTime();

// LM: associate both frames + match, lines detected beforehand (outside the timing).
void BM_LM_AssociateAndMatch(benchmark::State& state) {
  const LinePipelineParams params;
  const LineDetector detector(params.detector);
  const auto lines_a = detector.detect(frame_a().image), lines_b = detector.detect(frame_b().image);
  size_t matched = 0;
  for (auto _ : state) {
    const auto assoc_a = associate_points_to_lines(frame_a().keypoints, lines_a, params.association);
    const auto assoc_b = associate_points_to_lines(frame_b().keypoints, lines_b, params.association);
    const auto matches = match_lines(assoc_a, assoc_b, point_matches(), params.matching);
    matched = 0;
    for (int m : matches) matched += m >= 0;
    benchmark::DoNotOptimize(matches);
  }
  state.counters["line_matches"] = static_cast<double>(matched);
}
BENCHMARK(BM_LM_AssociateAndMatch)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
