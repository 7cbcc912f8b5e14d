// `vkvo synth`: renders a synthetic stereo sequence (EuRoC/ASL layout + ground truth), or applies illumination
// events to an existing ASL/KITTI sequence (--perturb).
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "app/command.hpp"
#include "io/config.hpp"
#include "io/yaml_utils.hpp"
#include "tools/synth/config.hpp"
#include "tools/synth/perturb.hpp"
#include "tools/synth/sequence_writer.hpp"

namespace {

struct SynthOptions {
  std::string out;
  std::string preset = "default";
  std::string config;
  std::string perturb;
  std::vector<std::string> events;
  bool no_default_events = false;
  int64_t seed = -1;
  int frames = -1;
  double speed = -1, yaw_rate = -1e9, baseline = -1, rate = -1;
  std::vector<int> resolution;
  std::vector<double> intrinsics;
  bool motion_blur = false;
  double perturb_noise = 0.0;
};

int run_synth(const SynthOptions& o) {
  using namespace vkvo::synth;
  const std::vector<IlluminationEvent> extra_events = parse_events(o.events);
  if (!o.perturb.empty()) {
    PerturbOptions options;
    options.noise_sigma = o.perturb_noise;
    if (o.seed >= 0) options.seed = static_cast<uint64_t>(o.seed);
    for (const auto& e : extra_events) spdlog::info("event {}", to_string(e));
    perturb_sequence(o.perturb, o.out, extra_events, options);
    return 0;
  }

  SynthConfig config;
  if (!o.config.empty()) {
    YAML::Node root = vkvo::io::load_yaml_file(o.config);
    const bool nested = root["synth"].IsDefined();
    YAML::Node section = nested ? root["synth"] : root;
    if (!section["preset"]) section["preset"] = o.preset;
    const vkvo::io::KeyReadLog key_log;
    config = load_synth_params(section);
    key_log.require_all_read(section, nested ? "synth" : "", o.config);
  } else {
    config = synth_preset(o.preset);
  }
  if (o.no_default_events) config.events.clear();
  config.events.insert(config.events.end(), extra_events.begin(), extra_events.end());
  if (o.seed >= 0) config.seed = static_cast<uint64_t>(o.seed);
  if (o.frames > 0) config.num_frames = o.frames;
  if (o.speed >= 0) config.trajectory.speed = o.speed;
  if (o.yaw_rate > -1e8) config.trajectory.yaw_rate_deg = o.yaw_rate;
  if (o.baseline > 0) config.rig.baseline = o.baseline;
  if (o.rate > 0) config.rate_hz = o.rate;
  if (o.resolution.size() == 2) {
    // Keep the field of view: scale the intrinsics with the width unless they are given too.
    const double scale = o.resolution[0] / static_cast<double>(config.rig.width);
    config.rig.fx *= scale, config.rig.fy *= scale;
    config.rig.width = o.resolution[0];
    config.rig.height = o.resolution[1];
    config.rig.cx = (config.rig.width - 1) / 2.0;
    config.rig.cy = (config.rig.height - 1) / 2.0;
  }
  if (o.intrinsics.size() == 4) {
    config.rig.fx = o.intrinsics[0], config.rig.fy = o.intrinsics[1];
    config.rig.cx = o.intrinsics[2], config.rig.cy = o.intrinsics[3];
  }
  if (o.motion_blur) config.sensor.motion_blur = true;

  spdlog::info("synth: {} frames {}x{} at {} Hz, seed {}, baseline {} m -> {}", config.num_frames, config.rig.width,
               config.rig.height, config.rate_hz, config.seed, config.rig.baseline, o.out);
  for (const auto& e : config.events) spdlog::info("event {}", to_string(e));
  write_synthetic_sequence(config, o.out, [](int done, int total) {
    if (done % 20 == 0 || done == total) spdlog::info("synth: {}/{} frames", done, total);
  });
  return 0;
}

vkvo::app::CommandRegistration reg{
    {"synth", "render a synthetic stereo sequence, or perturb the lighting of one", [](CLI::App& sub) {
       auto o = std::make_shared<SynthOptions>();
       sub.add_option("--out", o->out, "output folder (EuRoC/ASL layout + ground truth)")->required();
       sub.add_option("--preset", o->preset,
                      "default (200 frames 752x480, lights off in the middle) | low_texture (flat surfaces: few "
                      "corners, many edges) | small")
           ->check(CLI::IsMember({"default", "low_texture", "small"}));
       sub.add_option("--config", o->config, "YAML with synth parameters (top level or a `synth:` section)")
           ->check(CLI::ExistingFile);
       sub.add_option("--events", o->events,
                      "illumination events, e.g. lights_off:95-104 dim:50-150,gain=0.1 overexposure:20-40,gain=3 "
                      "flicker:0-,depth=0.6,period=3.7 spotlight:0-199,sigma=0.25 stereo:0-,gain=0.5,cam=right");
       sub.add_flag("--no-default-events", o->no_default_events, "drop the preset's events (e.g. for a clean default)");
       sub.add_option("--perturb", o->perturb, "apply --events to this ASL or KITTI sequence instead of rendering")
           ->check(CLI::ExistingDirectory);
       sub.add_option("--perturb-noise", o->perturb_noise, "Gaussian noise (DN) added to perturbed frames");
       sub.add_option("--seed", o->seed, "random seed (scene, trajectory phases, noise)");
       sub.add_option("--frames", o->frames, "number of stereo frames");
       sub.add_option("--speed", o->speed, "mean camera speed, m/s");
       sub.add_option("--yaw-rate", o->yaw_rate, "steady heading turn, deg/s");
       sub.add_option("--baseline", o->baseline, "stereo baseline, m");
       sub.add_option("--rate", o->rate, "frame rate, Hz");
       sub.add_option("--resolution", o->resolution, "W H (intrinsics scale with it)")->expected(2);
       sub.add_option("--intrinsics", o->intrinsics, "fx fy cx cy")->expected(4);
       sub.add_flag("--motion-blur", o->motion_blur, "average sub-frame renders over the exposure time");
       return std::function<int()>([o] { return run_synth(*o); });
     }}};

}  // namespace
