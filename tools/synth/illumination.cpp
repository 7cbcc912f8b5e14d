#include "tools/synth/illumination.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace vkvo::synth {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct KindName {
  std::string_view name;
  EventKind kind;
};
constexpr KindName kKindNames[] = {
    {"lights_off", EventKind::lights_off},
    {"off", EventKind::lights_off},
    {"dim", EventKind::dimming},
    {"dimming", EventKind::dimming},
    {"overexposure", EventKind::overexposure},
    {"overexpose", EventKind::overexposure},
    {"flicker", EventKind::flicker},
    {"spotlight", EventKind::spotlight},
    {"spot", EventKind::spotlight},
    {"stereo_exposure", EventKind::stereo_exposure},
    {"stereo", EventKind::stereo_exposure},
    {"gamma", EventKind::gamma_flicker},
    {"gamma_flicker", EventKind::gamma_flicker},
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

int parse_int(std::string_view text, std::string_view spec) {
  text = trim(text);
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 0)
    throw std::runtime_error(fmt::format("illumination event '{}': bad frame number '{}'", spec, text));
  return value;
}

double parse_double(std::string_view text, std::string_view key, std::string_view spec) {
  const std::string copy(trim(text));
  try {
    size_t used = 0;
    const double value = std::stod(copy, &used);
    if (used == copy.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw std::runtime_error(fmt::format("illumination event '{}': bad value '{}' for '{}'", spec, copy, key));
}

// 0 outside [first, last], 1 inside, with linear ramps of `ramp` frames at both ends (inside the range).
double trapezoid(int frame, int first, int last, int ramp) {
  if (frame < first || frame > last) return 0.0;
  if (ramp <= 0) return 1.0;
  const double in = (frame - first + 1) / static_cast<double>(ramp + 1);
  const double out = (last - frame + 1) / static_cast<double>(ramp + 1);
  return std::min({1.0, in, out});
}

bool applies_to(CameraMask mask, int camera) {
  return mask == CameraMask::both || (mask == CameraMask::left && camera == 0) ||
         (mask == CameraMask::right && camera == 1);
}

}  // namespace

std::string_view kind_name(EventKind kind) {
  switch (kind) {
    case EventKind::lights_off: return "lights_off";
    case EventKind::dimming: return "dim";
    case EventKind::overexposure: return "overexposure";
    case EventKind::flicker: return "flicker";
    case EventKind::spotlight: return "spotlight";
    case EventKind::stereo_exposure: return "stereo_exposure";
    case EventKind::gamma_flicker: return "gamma";
  }
  return "?";
}

IlluminationEvent make_event(EventKind kind, int first_frame, int last_frame) {
  IlluminationEvent event;
  event.kind = kind;
  event.first_frame = first_frame;
  event.last_frame = last_frame;
  switch (kind) {
    case EventKind::lights_off: event.gain = 0.02; break;
    case EventKind::dimming: event.gain = 0.1; break;
    case EventKind::overexposure:
      event.gain = 3.0;
      event.ramp_frames = 2;
      break;
    case EventKind::flicker: event.gain = 1.0; break;
    case EventKind::spotlight: event.gain = 1.6; break;
    case EventKind::stereo_exposure:
      event.gain = 0.5;
      event.cameras = CameraMask::right;
      break;
    case EventKind::gamma_flicker: event.gain = 0.5; break;  // gamma 0.5 / 2.0 on alternate frames
  }
  return event;
}

IlluminationEvent parse_event(std::string_view spec) {
  const std::string_view whole = spec;
  spec = trim(spec);
  const size_t comma = spec.find(',');
  std::string_view head = spec.substr(0, comma);
  std::string_view rest = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);

  const size_t colon = head.find(':');
  const std::string_view name = trim(head.substr(0, colon));
  const auto* found =
      std::find_if(std::begin(kKindNames), std::end(kKindNames), [&](const KindName& k) { return k.name == name; });
  if (found == std::end(kKindNames))
    throw std::runtime_error(
        fmt::format("illumination event '{}': unknown kind '{}' (lights_off, dim, "
                    "overexposure, flicker, spotlight, stereo_exposure, gamma)",
                    whole, name));
  int first = 0, last = -1;
  if (colon != std::string_view::npos) {
    const std::string_view range = trim(head.substr(colon + 1));
    const size_t dash = range.find('-');
    first = parse_int(range.substr(0, dash), whole);
    if (dash == std::string_view::npos)
      last = first;
    else if (!trim(range.substr(dash + 1)).empty())
      last = parse_int(range.substr(dash + 1), whole);
    if (last >= 0 && last < first)
      throw std::runtime_error(fmt::format("illumination event '{}': last frame before first", whole));
  }
  IlluminationEvent event = make_event(found->kind, first, last);

  while (!rest.empty()) {
    const size_t next = rest.find(',');
    const std::string_view item = trim(rest.substr(0, next));
    rest = next == std::string_view::npos ? std::string_view{} : rest.substr(next + 1);
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    if (eq == std::string_view::npos)
      throw std::runtime_error(fmt::format("illumination event '{}': expected key=value, got '{}'", whole, item));
    const std::string_view key = trim(item.substr(0, eq));
    const std::string_view value = trim(item.substr(eq + 1));
    if (key == "gain" || key == "level")
      event.gain = parse_double(value, key, whole);
    else if (key == "ambient")
      event.ambient = parse_double(value, key, whole);
    else if (key == "depth")
      event.depth = parse_double(value, key, whole);
    else if (key == "period")
      event.period_frames = parse_double(value, key, whole);
    else if (key == "sigma")
      event.sigma = parse_double(value, key, whole);
    else if (key == "ramp")
      event.ramp_frames = parse_int(value, whole);
    else if (key == "cam") {
      if (value == "both")
        event.cameras = CameraMask::both;
      else if (value == "left")
        event.cameras = CameraMask::left;
      else if (value == "right")
        event.cameras = CameraMask::right;
      else
        throw std::runtime_error(fmt::format("illumination event '{}': cam must be both|left|right", whole));
    } else {
      throw std::runtime_error(fmt::format("illumination event '{}': unknown key '{}'", whole, key));
    }
  }
  if (event.gain < 0 || event.ambient < 0 || event.sigma <= 0 || event.period_frames <= 0 || event.depth < 0 ||
      event.depth > 1)
    throw std::runtime_error(fmt::format("illumination event '{}': parameter out of range", whole));
  return event;
}

std::vector<IlluminationEvent> parse_events(const std::vector<std::string>& specs) {
  std::vector<IlluminationEvent> events;
  for (const auto& spec : specs) events.push_back(parse_event(spec));
  return events;
}

std::string to_string(const IlluminationEvent& e) {
  const std::string last = e.last_frame < 0 ? std::string() : std::to_string(e.last_frame);
  const char* cam = e.cameras == CameraMask::both ? "both" : e.cameras == CameraMask::left ? "left" : "right";
  return fmt::format("{}:{}-{},gain={},ambient={},depth={},period={},sigma={},ramp={},cam={}", kind_name(e.kind),
                     e.first_frame, last, e.gain, e.ambient, e.depth, e.period_frames, e.sigma, e.ramp_frames, cam);
}

double FrameGain::at(double x, double y) const {
  double g = global;
  for (const Beam& b : beams) {
    const double dx = x - b.cx, dy = y - b.cy;
    g *= b.ambient + (b.peak - b.ambient) * std::exp(-(dx * dx + dy * dy) / (2 * b.sigma * b.sigma));
  }
  return g;
}

FrameGain frame_gain(const std::vector<IlluminationEvent>& events, int frame, int camera, int width, int height) {
  FrameGain result;
  for (const auto& e : events) {
    if (!applies_to(e.cameras, camera)) continue;
    const int last = e.last_frame < 0 ? INT_MAX : e.last_frame;
    switch (e.kind) {
      case EventKind::lights_off:
      case EventKind::overexposure:
      case EventKind::stereo_exposure:
        result.global *= 1.0 + (e.gain - 1.0) * trapezoid(frame, e.first_frame, last, e.ramp_frames);
        break;
      case EventKind::dimming: {
        if (frame < e.first_frame) break;
        const double span = std::max(1, last - e.first_frame);
        const double s = last == INT_MAX ? 1.0 : std::min(1.0, (frame - e.first_frame) / span);
        result.global *= 1.0 + (e.gain - 1.0) * s;
        break;
      }
      case EventKind::flicker:
        if (frame < e.first_frame || frame > last) break;
        result.global *= 1.0 - e.depth * 0.5 * (1.0 - std::cos(2 * kPi * (frame - e.first_frame) / e.period_frames));
        break;
      case EventKind::gamma_flicker:
        if (frame < e.first_frame || frame > last) break;
        result.gamma *= (frame - e.first_frame) % 2 == 0 ? e.gain : 1.0 / e.gain;
        break;
      case EventKind::spotlight: {
        if (frame < e.first_frame || frame > last) break;
        // Sweeps from 15% to 85% of the width over the range (one sweep per 100 frames when open-ended), and
        // bobs vertically so the beam crosses different structure.
        const double span = last == INT_MAX ? 100.0 : std::max(1, last - e.first_frame);
        const double s = std::fmod((frame - e.first_frame) / span, 1.0 + 1e-9);
        result.beams.push_back(Beam{e.ambient, e.gain, width * (0.15 + 0.7 * s),
                                    height * (0.5 + 0.2 * std::sin(2 * kPi * s)), e.sigma * width});
        break;
      }
    }
  }
  return result;
}

// Gains first (they model light), then the tone curve (it models the camera's response).
void apply_gain(const FrameGain& gain, cv::Mat& image, double full_scale) {
  CV_Assert(image.type() == CV_32FC1);
  if (gain.is_identity()) return;
  image *= gain.global;
  // Each beam is separable: exp(-(dx^2 + dy^2) / 2s^2) = gx(x) * gy(y).
  std::vector<float> gx(image.cols);
  for (const Beam& b : gain.beams) {
    const double inv = 1.0 / (2 * b.sigma * b.sigma);
    for (int x = 0; x < image.cols; ++x) gx[x] = static_cast<float>(std::exp(-(x - b.cx) * (x - b.cx) * inv));
    const auto ambient = static_cast<float>(b.ambient), swing = static_cast<float>(b.peak - b.ambient);
    for (int y = 0; y < image.rows; ++y) {
      const auto gy = static_cast<float>(std::exp(-(y - b.cy) * (y - b.cy) * inv));
      float* row = image.ptr<float>(y);
      for (int x = 0; x < image.cols; ++x) row[x] *= ambient + swing * gx[x] * gy;
    }
  }
  if (gain.gamma == 1.0) return;
  const auto scale = static_cast<float>(full_scale);
  const auto gamma = static_cast<float>(gain.gamma);
  for (int y = 0; y < image.rows; ++y) {
    float* row = image.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) row[x] = scale * std::pow(std::max(row[x], 0.0f) / scale, gamma);
  }
}

}  // namespace vkvo::synth
