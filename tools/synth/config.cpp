#include "tools/synth/config.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace vkvo::synth {
namespace {

template <typename T>
void read(const YAML::Node& section, const char* key, T& value) {
  const YAML::Node node = section[key];
  if (!node) return;
  try {
    value = node.as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(fmt::format("synth config: key '{}' has the wrong type", key));
  }
}

}  // namespace

SynthConfig synth_preset(std::string_view name) {
  SynthConfig config;
  if (name == "default") {
    // Like EuRoC MH_01: 752x480 at 20 Hz, ~0.5 m/s, moderate rotation; the lights go out for half a second
    // in the middle of the 10 s sequence.
    config.events = {make_event(EventKind::lights_off, 95, 104)};
    return config;
  }
  if (name == "small") {
    config.num_frames = 40;
    config.rig = RigParams{320, 240, 200.0, 200.0, 159.5, 119.5, 0.11};
    config.scene.texels_per_meter = 150.0;
    return config;
  }
  throw std::runtime_error(fmt::format("synth: unknown preset '{}' (default, small)", name));
}

SynthConfig load_synth_params(const YAML::Node& section) {
  std::string preset = "default";
  if (section) read(section, "preset", preset);
  SynthConfig c = synth_preset(preset);
  if (!section) return c;
  read(section, "seed", c.seed);
  read(section, "frames", c.num_frames);
  read(section, "rate_hz", c.rate_hz);
  read(section, "width", c.rig.width);
  read(section, "height", c.rig.height);
  read(section, "fx", c.rig.fx);
  read(section, "fy", c.rig.fy);
  read(section, "cx", c.rig.cx);
  read(section, "cy", c.rig.cy);
  read(section, "baseline", c.rig.baseline);
  read(section, "speed", c.trajectory.speed);
  read(section, "yaw_rate_deg", c.trajectory.yaw_rate_deg);
  read(section, "yaw_sway_deg", c.trajectory.yaw_sway_deg);
  read(section, "pitch_deg", c.trajectory.pitch_deg);
  read(section, "pitch_sway_deg", c.trajectory.pitch_sway_deg);
  read(section, "roll_sway_deg", c.trajectory.roll_sway_deg);
  read(section, "start_yaw_deg", c.trajectory.start_yaw_deg);
  read(section, "num_boxes", c.scene.num_boxes);
  read(section, "texels_per_meter", c.scene.texels_per_meter);
  read(section, "exposure", c.sensor.exposure);
  read(section, "read_noise", c.sensor.read_noise);
  read(section, "shot_noise", c.sensor.shot_noise);
  read(section, "motion_blur", c.sensor.motion_blur);
  read(section, "exposure_time", c.sensor.exposure_time);
  read(section, "blur_samples", c.sensor.blur_samples);
  if (section["events"]) {
    std::vector<std::string> specs;
    read(section, "events", specs);
    c.events = parse_events(specs);
  }
  return c;
}

}  // namespace vkvo::synth
