#include "tools/synth/config.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "io/config.hpp"

namespace vkvo::synth {

SynthConfig synth_preset(std::string_view name) {
  SynthConfig config;
  if (name == "default") {
    // Like EuRoC MH_01: 752x480 at 20 Hz, ~0.5 m/s, moderate rotation; the lights go out for half a second
    // in the middle of the 10 s sequence.
    config.events = {make_event(EventKind::lights_off, 95, 104)};
    return config;
  }
  if (name == "low_texture") {
    // The default room with flat surfaces and no posters, twice the boxes: few corners, many edges (lines).
    config.scene.plain_surfaces = true;
    config.scene.posters_per_wall = 0;
    config.scene.num_boxes = 16;
    config.events.clear();
    return config;
  }
  if (name == "small") {
    config.num_frames = 40;
    config.rig = RigParams{320, 240, 200.0, 200.0, 159.5, 119.5, 0.11};
    config.scene.texels_per_meter = 150.0;
    return config;
  }
  throw std::runtime_error(fmt::format("synth: unknown preset '{}' (default, low_texture, small)", name));
}

void validate_synth_config(const SynthConfig& c) {
  auto fail = [](const std::string& problem) { throw std::runtime_error("synth: " + problem); };
  // Images above 8192 px a side (or 64 Mpx) are far beyond any camera the tools model and would take GiBs per frame.
  constexpr int kMaxSide = 8192;
  constexpr long long kMaxPixels = 64LL << 20;
  if (c.rig.width < 16 || c.rig.height < 16 || c.rig.width > kMaxSide || c.rig.height > kMaxSide ||
      static_cast<long long>(c.rig.width) * c.rig.height > kMaxPixels)
    fail(fmt::format("resolution {}x{} is outside 16x16 .. {}x{} (at most {} pixels)", c.rig.width, c.rig.height,
                     kMaxSide, kMaxSide, kMaxPixels));
  if (c.num_frames < 1) fail(fmt::format("frames must be at least 1, got {}", c.num_frames));
  auto positive = [&](const char* name, double value) {
    if (!std::isfinite(value) || value <= 0)
      fail(fmt::format("{} must be a positive finite number, got {}", name, value));
  };
  auto finite = [&](const char* name, double value) {
    if (!std::isfinite(value)) fail(fmt::format("{} must be finite, got {}", name, value));
  };
  positive("rate_hz", c.rate_hz);
  positive("fx", c.rig.fx);
  positive("fy", c.rig.fy);
  finite("cx", c.rig.cx);
  finite("cy", c.rig.cy);
  positive("baseline", c.rig.baseline);
  finite("speed", c.trajectory.speed);
  finite("yaw_rate_deg", c.trajectory.yaw_rate_deg);
  positive("texels_per_meter", c.scene.texels_per_meter);
  positive("exposure", c.sensor.exposure);
  if (c.scene.num_boxes < 0) fail(fmt::format("num_boxes must be at least 0, got {}", c.scene.num_boxes));
  if (c.scene.posters_per_wall < 0)
    fail(fmt::format("posters_per_wall must be at least 0, got {}", c.scene.posters_per_wall));
  if (c.sensor.blur_samples < 1) fail(fmt::format("blur_samples must be at least 1, got {}", c.sensor.blur_samples));
}

SynthConfig load_synth_params(const YAML::Node& section) {
  std::string preset = "default";
  if (section) io::read_param(section, "preset", preset);
  SynthConfig c = synth_preset(preset);
  if (!section) return c;
  io::read_param(section, "seed", c.seed);
  io::read_param(section, "frames", c.num_frames);
  io::read_param(section, "rate_hz", c.rate_hz);
  io::read_param(section, "width", c.rig.width);
  io::read_param(section, "height", c.rig.height);
  io::read_param(section, "fx", c.rig.fx);
  io::read_param(section, "fy", c.rig.fy);
  io::read_param(section, "cx", c.rig.cx);
  io::read_param(section, "cy", c.rig.cy);
  io::read_param(section, "baseline", c.rig.baseline);
  io::read_param(section, "speed", c.trajectory.speed);
  io::read_param(section, "yaw_rate_deg", c.trajectory.yaw_rate_deg);
  io::read_param(section, "yaw_sway_deg", c.trajectory.yaw_sway_deg);
  io::read_param(section, "pitch_deg", c.trajectory.pitch_deg);
  io::read_param(section, "pitch_sway_deg", c.trajectory.pitch_sway_deg);
  io::read_param(section, "roll_sway_deg", c.trajectory.roll_sway_deg);
  io::read_param(section, "start_yaw_deg", c.trajectory.start_yaw_deg);
  io::read_param(section, "num_boxes", c.scene.num_boxes);
  io::read_param(section, "texels_per_meter", c.scene.texels_per_meter);
  io::read_param(section, "posters_per_wall", c.scene.posters_per_wall);
  io::read_param(section, "plain_surfaces", c.scene.plain_surfaces);
  io::read_param(section, "exposure", c.sensor.exposure);
  io::read_param(section, "read_noise", c.sensor.read_noise);
  io::read_param(section, "shot_noise", c.sensor.shot_noise);
  io::read_param(section, "motion_blur", c.sensor.motion_blur);
  io::read_param(section, "exposure_time", c.sensor.exposure_time);
  io::read_param(section, "blur_samples", c.sensor.blur_samples);
  if (section["events"]) {
    std::vector<std::string> specs;
    io::read_param(section, "events", specs);
    c.events = parse_events(specs);
  }
  return c;
}

}  // namespace vkvo::synth
