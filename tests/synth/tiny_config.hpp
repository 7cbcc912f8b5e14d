#pragma once
// A small, fast configuration for the synth tests (2-core CI): 160x120 images, coarse textures.
#include "tools/synth/config.hpp"

namespace vkvo::synth::testing {

inline SynthConfig tiny_config(int frames = 12) {
  SynthConfig config = synth_preset("small");
  config.num_frames = frames;
  config.rig = RigParams{160, 120, 100.0, 100.0, 79.5, 59.5, 0.11};
  config.scene.texels_per_meter = 80.0;
  config.events.clear();
  return config;
}

}  // namespace vkvo::synth::testing
