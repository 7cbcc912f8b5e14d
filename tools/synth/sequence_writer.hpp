#pragma once
// Writes a rendered sequence like a real dataset, so `vkvo run` / `vkvo eval` read it as they read EuRoC:
//   DIR/mav0/cam{0,1}/data/<ns>.png, data.csv ("#timestamp [ns],filename"), sensor.yaml (EuRoC format:
//   T_BS 4x4 row-major, intrinsics [fu, fv, cu, cv], radial-tangential with zero coefficients, resolution, rate_hz)
//   DIR/mav0/state_groundtruth_estimate0/data.csv  EuRoC ground truth of the body (= cam0) pose and velocity
//   DIR/groundtruth_tum.txt                        TUM "t x y z qx qy qz qw" of cam0 (seconds)
//   DIR/synth.yaml                                 the parameters it was made with (seed, rig, events)
//   DIR/scene_boxes.csv                            the scene's room and boxes (every surface is one of their faces)
#include <filesystem>
#include <functional>

#include "tools/synth/config.hpp"
#include "tools/synth/renderer.hpp"

namespace vkvo::synth {

// Called after each frame is written with (frames done, total).
using ProgressCallback = std::function<void(int, int)>;

void write_asl_sequence(const StereoRenderer& renderer, const std::filesystem::path& out_dir,
                        const ProgressCallback& progress = {});
// Generates the scene from config and writes the sequence.
void write_synthetic_sequence(const SynthConfig& config, const std::filesystem::path& out_dir,
                              const ProgressCallback& progress = {});

// The sensor.yaml text of one camera (exposed for tests and for perturbed copies).
std::string euroc_sensor_yaml(const io::CameraCalibration& camera, double rate_hz, const std::string& comment);

}  // namespace vkvo::synth
