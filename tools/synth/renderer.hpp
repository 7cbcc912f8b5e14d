#pragma once
// The synthetic stereo camera: ray-cast radiance of both rectified cameras at each frame's pose, then the sensor
// model in the order light takes: motion blur (exposure-time average), illumination events (gain on irradiance),
// exposure to digital numbers, shot + read noise, clipping and 8-bit quantisation. Deterministic for a seed:
// the noise of pixel (x, y) of camera c at frame k is a hash of (seed, k, c, x, y), independent of threading.
#include <cstdint>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "io/calibration.hpp"
#include "tools/synth/config.hpp"
#include "tools/synth/raycaster.hpp"
#include "tools/synth/scene.hpp"
#include "tools/synth/trajectory.hpp"

namespace vkvo::synth {

struct StereoFrame {
  int index = 0;
  int64_t timestamp_ns = 0;
  Eigen::Isometry3d T_world_cam0 = Eigen::Isometry3d::Identity();
  cv::Mat left, right;  // CV_8UC1
};

class StereoRenderer {
 public:
  // Generates the scene from config.scene and config.seed.
  explicit StereoRenderer(SynthConfig config);
  // Renders a given scene (tests build their own, e.g. with a marker).
  StereoRenderer(SynthConfig config, std::shared_ptr<const Scene> scene);

  int frame_count() const { return config_.num_frames; }
  int64_t timestamp_ns(int frame) const;
  double time_s(int frame) const { return frame / config_.rate_hz; }  // since the first frame
  Eigen::Isometry3d T_world_cam0(int frame) const { return trajectory_.pose(time_s(frame)); }
  Eigen::Isometry3d T_world_cam1(int frame) const { return T_world_cam0(frame) * T_cam0_cam1(); }
  Eigen::Vector3d velocity(int frame) const { return trajectory_.velocity(time_s(frame)); }
  Eigen::Isometry3d T_cam0_cam1() const;  // translation by the baseline along +x
  PinholeCamera camera() const;
  io::StereoCalibration calibration() const;  // rectified, body = cam0

  StereoFrame render(int frame, const RenderOptions& options = {}) const;
  // Sensor irradiance in DN before events and noise (CV_32F): the "clean" image; optionally with depth.
  cv::Mat render_clean(int frame, int camera, cv::Mat* depth = nullptr, const RenderOptions& options = {}) const;

  const SynthConfig& config() const { return config_; }
  const Scene& scene() const { return *scene_; }

 private:
  cv::Mat expose(int frame, int camera, cv::Mat irradiance) const;  // events, noise, quantisation -> CV_8UC1

  SynthConfig config_;
  std::shared_ptr<const Scene> scene_;
  RayCaster caster_;
  SmoothTrajectory trajectory_;
};

}  // namespace vkvo::synth
