#pragma once
// Illumination events as a photometric model: each event multiplies the linear image irradiance of a frame by a
// gain (global, or spatially varying for the spotlight) over a frame range. The renderer applies the gain before
// sensor noise and quantisation; perturb_sequence() applies it to the pixels of an existing sequence. Gains of
// several events multiply, so events combine freely.
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

namespace vkvo::synth {

enum class EventKind {
  lights_off,       // frames drop to `gain` (near black) inside the range, back to normal after it
  dimming,          // gain ramps linearly from 1 at first_frame to `gain` at last_frame and stays there
  overexposure,     // gain `gain` (> 1) inside the range, ramping in/out over `ramp_frames`; bright parts clip
  flicker,          // gain 1 - depth * (1 - cos(2 pi (k - first) / period)) / 2 inside the range
  spotlight,        // beam of gain `gain` over `ambient`, Gaussian of width sigma * image width, sweeping left->right
  stereo_exposure,  // the cameras in `cameras` (default: right only) get exposure gain `gain`
  gamma_flicker,    // tone curve v' = v^g on normalised intensities, g alternating between `gain` and 1/`gain`
};

enum class CameraMask { both, left, right };

struct IlluminationEvent {
  EventKind kind = EventKind::lights_off;
  int first_frame = 0;
  int last_frame = -1;         // inclusive; -1: until the end of the sequence
  double gain = 0.02;          // see EventKind for its meaning per kind
  double ambient = 0.3;        // spotlight: gain outside the beam
  double depth = 0.6;          // flicker: fraction of light lost at the darkest point
  double period_frames = 3.7;  // flicker period in frames (non-integer so the phase wanders like mains flicker)
  double sigma = 0.25;         // spotlight: beam standard deviation as a fraction of the image width
  int ramp_frames = 0;         // lights_off / overexposure / stereo_exposure: linear transition length
  CameraMask cameras = CameraMask::both;
};

// An event of `kind` over [first, last] with that kind's reference parameters.
IlluminationEvent make_event(EventKind kind, int first_frame, int last_frame);

// Parses "kind[:first[-last]][,key=value...]", e.g. "lights_off:95-104", "dim:50-120,gain=0.1",
// "spotlight:0-199,sigma=0.2,ambient=0.25", "stereo:0-,gain=0.5,cam=right". Kinds: lights_off|off, dim|dimming,
// overexposure|overexpose, flicker, spotlight|spot, stereo_exposure|stereo, gamma|gamma_flicker. Keys: gain, ambient,
// depth, period, sigma, ramp, cam (both|left|right). Throws std::runtime_error naming the spec and the problem.
IlluminationEvent parse_event(std::string_view spec);
std::vector<IlluminationEvent> parse_events(const std::vector<std::string>& specs);
std::string to_string(const IlluminationEvent& event);
std::string_view kind_name(EventKind kind);

// A spotlight in the image: gain ambient + (peak - ambient) * exp(-|p - centre|^2 / (2 sigma^2)), in pixels.
struct Beam {
  double ambient = 1.0, peak = 1.0;
  double cx = 0, cy = 0, sigma = 1;
};

// The gain field one frame of one camera sees: a global factor times the product of its beams.
struct FrameGain {
  double global = 1.0;
  std::vector<Beam> beams;
  double gamma = 1.0;  // tone curve applied after the gains (gamma_flicker)

  bool is_identity() const { return beams.empty() && global == 1.0 && gamma == 1.0; }
  double at(double x, double y) const;  // gain at pixel (x, y)
};

// Combined gain of all events at frame `frame` (0-based) for camera 0 (left) or 1 (right) of a width x height image.
FrameGain frame_gain(const std::vector<IlluminationEvent>& events, int frame, int camera, int width, int height);

// Multiplies a single-channel CV_32F image of linear intensities by the gain field, then applies the tone curve
// (gamma) relative to `full_scale` (255 for 8-bit data), in place.
void apply_gain(const FrameGain& gain, cv::Mat& linear_image, double full_scale = 255.0);

}  // namespace vkvo::synth
