// Back-end timings on a synthetic window like the paper's (module times IPE 4 ms, BA 264 ms on a Jetson Xavier):
// 12 keyframes (10 optimised, 2 fixed), 2000 points, 300 lines, 0.5 px noise, one thread (ceres num_threads = 1).
// IPE: one frame's matches (up to 400 points, as EuRoC's max_keypoints, plus its lines, 20% outliers), prior
// 2 cm / 0.01 rad off. BA: landmarks and window poses perturbed before every run.
#include <random>

#include <benchmark/benchmark.h>

#include "backend/local_ba.hpp"
#include "backend/pose_estimation.hpp"
#include "backend/scene_fixture.hpp"

namespace {

using namespace vkvo;

const test::Scene& bench_scene() {
  static const test::Scene scene = [] {
    test::SceneSpec spec;
    spec.num_keyframes = 12;
    spec.num_points = 2000;
    spec.num_lines = 300;
    spec.step = 0.15;
    spec.pixel_noise = 0.5;
    spec.seed = 7;
    return test::make_scene(spec);
  }();
  return scene;
}

void BM_InitialPoseEstimation(benchmark::State& state) {
  const test::Scene& s = bench_scene();
  const int k = 11;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<backend::PointMatch> points;
  std::vector<backend::LineMatch> lines;
  for (const auto& o : s.point_obs[k]) {
    if (points.size() >= 400) break;
    backend::PointMatch m{s.points[o.point], {o.pixel, o.right_x}};
    if (u01(rng) < 0.2) m.measurement.pixel += Eigen::Vector2d(40, -25);
    points.push_back(m);
  }
  for (const auto& o : s.line_obs[k])
    lines.push_back(
        {geometry::PlueckerLine::from_points(s.segments[o.line].first, s.segments[o.line].second), {o.left, o.right}});
  const Eigen::Isometry3d prior = test::perturb(s.T_world_camera[k], rng, 0.02, 0.01);
  backend::OptimizationParams params;
  params.num_threads = 1;
  int inliers = 0;
  for (auto _ : state) {
    const auto est = backend::estimate_pose(s.stereo, prior, points, lines, params);
    inliers = est.num_point_inliers + est.num_line_inliers;
    benchmark::DoNotOptimize(est.T_world_camera);
  }
  state.counters["points"] = static_cast<double>(points.size());
  state.counters["lines"] = static_cast<double>(lines.size());
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_InitialPoseEstimation)->Unit(benchmark::kMillisecond)->Repetitions(7)->ReportAggregatesOnly(true);

void BM_LocalBundleAdjustment(benchmark::State& state) {
  const test::Scene& s = bench_scene();
  const test::SceneMap base = test::make_scene_map(s);
  backend::OptimizationParams params;
  params.num_threads = 1;
  params.window_size = 10;
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0.0, 1.0);
  backend::LocalBAResult last;
  for (auto _ : state) {
    state.PauseTiming();
    test::SceneMap sm = base;
    for (map::Id id = 2; id < 12; ++id) {
      auto* kf = sm.map.keyframe(id);
      kf->T_world_camera = test::perturb(kf->T_world_camera, rng, 0.02, 0.005);
    }
    for (const auto& [id, p] : sm.map.points())
      sm.map.point(id)->position += 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    state.ResumeTiming();
    last = backend::local_bundle_adjustment(sm.map, 11, s.stereo, params);
    benchmark::DoNotOptimize(last.final_cost);
  }
  state.counters["keyframes"] = static_cast<double>(last.window.size());
  state.counters["fixed"] = static_cast<double>(last.fixed.size());
  state.counters["points"] = last.num_points;
  state.counters["lines"] = last.num_lines;
  state.counters["point_obs"] = last.point_observations;
  state.counters["line_obs"] = last.line_observations;
}
BENCHMARK(BM_LocalBundleAdjustment)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
