#include "tools/synth/renderer.hpp"

#include <cmath>

#include <opencv2/core/utility.hpp>

#include "tools/synth/noise.hpp"

namespace vkvo::synth {

StereoRenderer::StereoRenderer(SynthConfig config)
    : StereoRenderer(config, std::make_shared<const Scene>(generate_indoor_scene(config.scene, config.seed))) {}

StereoRenderer::StereoRenderer(SynthConfig config, std::shared_ptr<const Scene> scene)
    : config_(std::move(config)),
      scene_(std::move(scene)),
      caster_(*scene_),
      trajectory_(config_.trajectory, config_.seed) {}

int64_t StereoRenderer::timestamp_ns(int frame) const {
  return config_.start_time_ns + std::llround(frame * 1e9 / config_.rate_hz);
}

Eigen::Isometry3d StereoRenderer::T_cam0_cam1() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = config_.rig.baseline;
  return T;
}

PinholeCamera StereoRenderer::camera() const {
  const RigParams& r = config_.rig;
  return PinholeCamera{r.width, r.height, r.fx, r.fy, r.cx, r.cy};
}

io::StereoCalibration StereoRenderer::calibration() const {
  io::CameraCalibration cam;
  const RigParams& r = config_.rig;
  cam.width = r.width;
  cam.height = r.height;
  cam.fx = r.fx, cam.fy = r.fy, cam.cx = r.cx, cam.cy = r.cy;
  cam.distortion = io::DistortionModel::radtan;
  cam.distortion_coeffs = {0.0, 0.0, 0.0, 0.0};
  io::StereoCalibration stereo;
  stereo.left = cam;
  stereo.right = cam;
  stereo.right.T_body_camera = T_cam0_cam1();
  stereo.rectified = true;
  return stereo;
}

cv::Mat StereoRenderer::render_clean(int frame, int cam, cv::Mat* depth, const RenderOptions& options) const {
  const Eigen::Isometry3d T_cam0_camc = cam == 0 ? Eigen::Isometry3d::Identity() : T_cam0_cam1();
  cv::Mat radiance;
  const SensorParams& sensor = config_.sensor;
  if (!sensor.motion_blur || sensor.blur_samples < 2) {
    caster_.render(camera(), T_world_cam0(frame) * T_cam0_camc, radiance, depth, options);
  } else {
    // Box-filter the exposure: sub-frame poses evenly spread over [t - T/2, t + T/2].
    radiance = cv::Mat::zeros(config_.rig.height, config_.rig.width, CV_32F);
    cv::Mat sub;
    for (int i = 0; i < sensor.blur_samples; ++i) {
      const double t = time_s(frame) + sensor.exposure_time * (i / (sensor.blur_samples - 1.0) - 0.5);
      caster_.render(camera(), trajectory_.pose(t) * T_cam0_camc, sub, i == sensor.blur_samples / 2 ? depth : nullptr,
                     options);
      radiance += sub;
    }
    radiance /= sensor.blur_samples;
  }
  radiance *= sensor.exposure;
  return radiance;
}

cv::Mat StereoRenderer::expose(int frame, int cam, cv::Mat irradiance) const {
  apply_gain(frame_gain(config_.events, frame, cam, irradiance.cols, irradiance.rows), irradiance);
  const SensorParams& sensor = config_.sensor;
  const float read_var = static_cast<float>(sensor.read_noise * sensor.read_noise);
  const auto shot = static_cast<float>(sensor.shot_noise);
  const uint64_t stream = noise_stream(config_.seed, frame, cam);
  cv::Mat out(irradiance.size(), CV_8UC1);
  for (int y = 0; y < irradiance.rows; ++y) {
    const float* in = irradiance.ptr<float>(y);
    uint8_t* o = out.ptr<uint8_t>(y);
    const uint64_t row = hash64(stream + static_cast<uint64_t>(y));
    for (int x = 0; x < irradiance.cols; ++x) {
      const float signal = std::max(in[x], 0.f);
      const float sigma = std::sqrt(read_var + shot * signal);
      const float value = signal + sigma * standard_normal(hash64(row + static_cast<uint64_t>(x)));
      o[x] = cv::saturate_cast<uint8_t>(value);  // rounds to nearest, clips to [0, 255]
    }
  }
  return out;
}

StereoFrame StereoRenderer::render(int frame, const RenderOptions& options) const {
  StereoFrame result;
  result.index = frame;
  result.timestamp_ns = timestamp_ns(frame);
  result.T_world_cam0 = T_world_cam0(frame);
  result.left = expose(frame, 0, render_clean(frame, 0, nullptr, options));
  result.right = expose(frame, 1, render_clean(frame, 1, nullptr, options));
  return result;
}

}  // namespace vkvo::synth
