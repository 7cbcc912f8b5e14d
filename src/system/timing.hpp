#pragma once
// Per-module timing of a run, as in the paper's runtime table: PE point extraction, LE line extraction, PM point
// matching, LM line association + matching, IPE initial pose estimation, BA keyframe processing (stereo
// triangulation, map update) + local bundle adjustment, RL relocalisation (candidates, matching, PnP, refinement,
// and a merge of map segments). Every frame adds one sample per module it ran; a new
// keyframe adds one more to PE (its right image), PM (its stereo matches) and LE (its right-image lines).
#include <array>
#include <chrono>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vkvo::system {

enum class Module { PE, LE, PM, LM, IPE, BA, RL, Frame };
inline constexpr std::array kModules = {Module::PE,  Module::LE, Module::PM, Module::LM,
                                        Module::IPE, Module::BA, Module::RL, Module::Frame};
const char* to_string(Module module);

struct ModuleStats {
  std::size_t samples = 0;
  double mean_ms = 0, median_ms = 0, p95_ms = 0, max_ms = 0;
};

class TimingReport {
 public:
  void add(Module module, double ms) { samples_[static_cast<std::size_t>(module)].push_back(ms); }
  void merge(const TimingReport& other);
  ModuleStats stats(Module module) const;
  // The table printed at the end of a run, one row per module, plus frames/s over `wall_seconds`.
  std::string table(std::size_t frames, double wall_seconds) const;
  nlohmann::json to_json(std::size_t frames, double wall_seconds) const;

 private:
  std::array<std::vector<double>, kModules.size()> samples_;
};

// Milliseconds since construction (ms), or since the previous lap (lap, which starts the next one).
class Stopwatch {
 public:
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return elapsed;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace vkvo::system
