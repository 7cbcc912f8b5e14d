#include "system/timing.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

namespace vkvo::system {

const char* to_string(Module module) {
  switch (module) {
    case Module::PE: return "PE";
    case Module::LE: return "LE";
    case Module::PM: return "PM";
    case Module::LM: return "LM";
    case Module::IPE: return "IPE";
    case Module::BA: return "BA";
    case Module::RL: return "RL";
    case Module::Frame: return "frame";
  }
  return "?";
}

void TimingReport::merge(const TimingReport& other) {
  for (std::size_t m = 0; m < samples_.size(); ++m)
    samples_[m].insert(samples_[m].end(), other.samples_[m].begin(), other.samples_[m].end());
}

ModuleStats TimingReport::stats(Module module) const {
  auto values = samples_[static_cast<std::size_t>(module)];
  ModuleStats s;
  s.samples = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.mean_ms = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  const auto quantile = [&](double q) {  // nearest rank
    const auto rank = static_cast<std::size_t>(std::ceil(q * double(values.size())));
    return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
  };
  s.median_ms =
      values.size() % 2 ? values[values.size() / 2] : 0.5 * (values[values.size() / 2 - 1] + values[values.size() / 2]);
  s.p95_ms = quantile(0.95);
  s.max_ms = values.back();
  return s;
}

std::string TimingReport::table(std::size_t frames, double wall_seconds) const {
  std::string out = fmt::format("{:<6} {:>8} {:>10} {:>10} {:>10} {:>10}\n", "module", "samples", "mean ms",
                                "median ms", "p95 ms", "max ms");
  for (Module m : kModules) {
    const auto s = stats(m);
    out += fmt::format("{:<6} {:>8} {:>10.2f} {:>10.2f} {:>10.2f} {:>10.2f}\n", to_string(m), s.samples, s.mean_ms,
                       s.median_ms, s.p95_ms, s.max_ms);
  }
  out += fmt::format("{} frames in {:.2f} s: {:.2f} frames/s\n", frames, wall_seconds,
                     wall_seconds > 0 ? double(frames) / wall_seconds : 0.0);
  return out;
}

nlohmann::json TimingReport::to_json(std::size_t frames, double wall_seconds) const {
  nlohmann::json modules = nlohmann::json::object();
  for (Module m : kModules) {
    const auto s = stats(m);
    modules[to_string(m)] = {{"samples", s.samples},
                             {"mean_ms", s.mean_ms},
                             {"median_ms", s.median_ms},
                             {"p95_ms", s.p95_ms},
                             {"max_ms", s.max_ms}};
  }
  return {{"modules", modules},
          {"frames", frames},
          {"wall_seconds", wall_seconds},
          {"frames_per_second", wall_seconds > 0 ? double(frames) / wall_seconds : 0.0}};
}

}  // namespace vkvo::system
