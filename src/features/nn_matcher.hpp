#pragma once
// Fallback point matcher when no SuperGlue pack is configured: mutual nearest neighbours of the (L2-normalised)
// descriptors, on the device: one GEMM for all cosine similarities, row/column best on the device, then the
// cosine-distance gate and the optional ratio test. fp32 throughout (the GEMM is small next to SuperGlue).
#include <memory>

#include <yaml-cpp/yaml.h>

#include "features/nn_matcher_params.hpp"
#include "features/point_matcher.hpp"
#include "runtime/context.hpp"
#include "runtime/sequence.hpp"

namespace vkvo::features {

class NnMatcher final : public PointMatcher {
 public:
  explicit NnMatcher(const rt::Context& context, const NnMatcherParams& params = {});
  ~NnMatcher() override;
  NnMatcher(const NnMatcher&) = delete;
  NnMatcher& operator=(const NnMatcher&) = delete;

  // scores0 holds the cosine similarity of each kept match.
  PointMatches match(const PointFeatures& a, const PointFeatures& b) override;
  // GPU time of each dispatch of the last match(): empty unless profiling is on (as for SuperPoint and SuperGlue).
  void set_profiling(bool on);
  std::vector<rt::CommandTiming> last_timings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vkvo::features
