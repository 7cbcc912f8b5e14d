// vkvo_bench_synth: time to render one stereo pair of the default preset (752x480) on one core, with and without
// the sensor model, and the cost of perturbing one image.
#include <memory>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>

#include "tools/synth/perturb.hpp"
#include "tools/synth/renderer.hpp"

namespace {

using namespace vkvo::synth;

const StereoRenderer& default_renderer() {
  static const StereoRenderer renderer(synth_preset("default"));
  return renderer;
}

// Full pipeline per frame: ray casting with edge anti-aliasing for both cameras, events, noise, quantisation.
void BM_RenderStereoPair(benchmark::State& state) {
  cv::setNumThreads(1);
  const StereoRenderer& renderer = default_renderer();
  int frame = 0;
  for (auto _ : state) {
    StereoFrame f = renderer.render(frame);
    benchmark::DoNotOptimize(f.left.data);
    frame = (frame + 7) % renderer.frame_count();
  }
  state.counters["pixels/s"] = benchmark::Counter(2.0 * renderer.config().rig.width * renderer.config().rig.height,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_RenderStereoPair)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// Ray casting alone (one camera), with and without anti-aliasing.
void BM_RayCastOneView(benchmark::State& state) {
  cv::setNumThreads(1);
  const StereoRenderer& renderer = default_renderer();
  RenderOptions options;
  options.anti_alias = state.range(0) != 0;
  int frame = 0;
  for (auto _ : state) {
    cv::Mat radiance = renderer.render_clean(frame, 0, nullptr, options);
    benchmark::DoNotOptimize(radiance.data);
    frame = (frame + 7) % renderer.frame_count();
  }
}
BENCHMARK(BM_RayCastOneView)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MinTime(1.0);

void BM_PerturbImage(benchmark::State& state) {
  cv::Mat image(480, 752, CV_8UC1);
  cv::randu(image, 0, 255);
  const auto events = parse_events({"spotlight:0-10", "flicker:0-10"});
  const FrameGain gain = frame_gain(events, 3, 0, image.cols, image.rows);
  for (auto _ : state) benchmark::DoNotOptimize(perturb_image(image, gain, 1.0, 42).data);
}
BENCHMARK(BM_PerturbImage)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
