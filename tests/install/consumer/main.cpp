// Uses the installed headers and libraries of several layers: the io config reader, the parameter loaders of
// geometry, map, backend, features and system (through system::load_vo_config), the runtime's fp16 helpers and
// its device list (which links Vulkan), and the live-input VO (system::StereoOdometry) with a point frontend of
// its own. Needs no GPU and no data: a machine without a Vulkan driver only says so.
// Exits 0 and prints "vkvo consumer: ok" when everything reads back as written.
#include <cstdio>
#include <exception>

#include "io/config.hpp"
#include "runtime/context.hpp"
#include "runtime/half.hpp"
#include "system/stereo_odometry.hpp"
#include "system/vo_config.hpp"

namespace {

// A frontend that sees nothing: the odometry must carry on with predicted, untracked poses.
class BlindFrontend final : public vkvo::system::PointFrontend {
 public:
  vkvo::features::PointFeatures detect(const cv::Mat&) override { return {}; }
  vkvo::features::PointMatches match(const vkvo::features::PointFeatures&,
                                     const vkvo::features::PointFeatures&) override {
    return {};
  }
};

}  // namespace

int main() {
  const auto config = vkvo::io::Config::from_string(
      "tracking:\n  min_num_match: 42\nstereo:\n  max_depth: 33.5\nmap:\n  min_point_observations: 4\n"
      "models:\n  matcher: nn\n",
      "consumer");
  const vkvo::system::VoConfig vo = vkvo::system::load_vo_config(config);
  if (vo.tracking.min_num_match != 42 || vo.triangulation.max_depth != 33.5 || vo.map.min_point_observations != 4 ||
      vo.matcher != "nn") {
    std::fprintf(stderr, "vkvo consumer: the config did not read back\n");
    return 1;
  }
  const auto camera = vkvo::system::load_vo_config(vkvo::io::Config::from_string(
      "camera: {width: 64, height: 48, fx: 50, fy: 50, cx: 32, cy: 24, baseline: 0.1}\n", "consumer camera"));
  BlindFrontend features, keyframes;
  vkvo::system::StereoOdometry odometry(camera, vkvo::system::config_calibration(camera), features, keyframes);
  const cv::Mat black(48, 64, CV_8UC1, cv::Scalar(0));
  for (int frame = 0; frame < 2; ++frame) {
    if (odometry.track(black, black, frame * 50'000'000LL).tracked) {
      std::fprintf(stderr, "vkvo consumer: a blind frontend tracked a black frame\n");
      return 1;
    }
  }
  if (vkvo::rt::half_to_float(vkvo::rt::float_to_half(0.5f)) != 0.5f) {
    std::fprintf(stderr, "vkvo consumer: fp16 round trip failed\n");
    return 1;
  }
  try {
    std::printf("vkvo consumer: %zu Vulkan device(s)\n", vkvo::rt::list_devices().size());
  } catch (const std::exception& e) {
    std::printf("vkvo consumer: no Vulkan devices (%s)\n", e.what());
  }
  std::printf("vkvo consumer: ok\n");
  return 0;
}
