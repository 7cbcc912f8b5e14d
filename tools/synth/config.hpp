#pragma once
// Everything that defines a synthetic sequence: rig, sequence length and rate, scene, trajectory, sensor, events.
// Presets "default" (the demo: ~200 frames, 752x480 at 20 Hz, lights off and on in the middle), "low_texture" (the
// same room with flat surfaces, no posters and more boxes: few corners, many edges; no events) and "small" (tests).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "tools/synth/illumination.hpp"
#include "tools/synth/scene.hpp"
#include "tools/synth/trajectory.hpp"

namespace vkvo::synth {

struct RigParams {
  int width = 752, height = 480;
  double fx = 458.0, fy = 458.0, cx = 375.5, cy = 239.5;  // rectified pinhole, shared by both cameras
  double baseline = 0.11;                                 // metres; cam1 sits at +baseline along cam0's x
};

struct SensorParams {
  double exposure = 230.0;       // digital numbers per unit of scene radiance (albedo x irradiance)
  double read_noise = 1.2;       // DN, Gaussian
  double shot_noise = 0.04;      // variance in DN^2 per DN of signal (photon noise)
  bool motion_blur = false;      // average sub-frame renders over the exposure time
  double exposure_time = 0.015;  // seconds, centred on the frame timestamp
  int blur_samples = 5;
};

struct SynthConfig {
  uint64_t seed = 1;
  int num_frames = 200;
  double rate_hz = 20.0;
  int64_t start_time_ns = 1'000'000'000'000'000'000;  // EuRoC-like absolute timestamps
  RigParams rig;
  SceneParams scene;
  TrajectoryParams trajectory;
  SensorParams sensor;
  std::vector<IlluminationEvent> events;
};

// "default", "low_texture" or "small"; throws std::runtime_error for another name.
SynthConfig synth_preset(std::string_view name);

// Reads optional keys over a base (`preset:` in the section picks it, else "default"): seed, frames, rate_hz,
// width, height, fx, fy, cx, cy, baseline, speed, yaw_rate_deg, yaw_sway_deg, pitch_deg, pitch_sway_deg,
// roll_sway_deg, start_yaw_deg, num_boxes, texels_per_meter, posters_per_wall, plain_surfaces, exposure, read_noise,
// shot_noise, motion_blur, exposure_time, blur_samples, events (list of event specs, see parse_event). Wrong type ->
// std::runtime_error naming the key.
SynthConfig load_synth_params(const YAML::Node& section);

// Throws std::runtime_error naming the parameter when a value cannot render (a resolution below 16x16 or beyond
// 8192 a side, non-positive rate, focal length or baseline, a NaN, ...). write_synthetic_sequence calls it.
void validate_synth_config(const SynthConfig& config);

}  // namespace vkvo::synth
