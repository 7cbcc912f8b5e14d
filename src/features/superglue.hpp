#pragma once
// SuperGlue on the device: keypoint normalisation, keypoint encoder, the attentional GNN, final projection, score
// matrix with dustbins, log-space Sinkhorn and mutual-max match extraction, recorded into one Sequence and submitted
// once per call; only the matches and their scores (and, on request, the dense log-assignment) come back.
//
// Data layout on the device (row-major, rows = keypoints of image 0 then image 1, R = N + M rows):
//   state  R x 2D  [x | message]: the attention writes its heads into the right half, so the MLP's first layer reads
//                  concat(x, message) as one matrix; the merge projection is folded into that layer at load time.
//   qkv    R x 3D  q, k and v of both sets from one GEMM (the weights are shared by the two sets in every layer);
//                  channels are regrouped head-major at load time (SuperGlue splits dim-major: c = d * heads + h).
//   attention scores per head and set, softmaxed in place, then multiplied by v into the message columns.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#include "features/point_matcher.hpp"
#include "features/superglue_params.hpp"
#include "io/model_pack.hpp"
#include "runtime/context.hpp"
#include "runtime/sequence.hpp"

namespace vkvo::features {

// The network's hyper-parameters as read from a pack.
struct SuperGlueConfig {
  int descriptor_dim = 256;
  int heads = 4;
  std::vector<int> encoder_widths;  // hidden widths of the keypoint encoder, e.g. 32 64 128 256
  std::vector<bool> cross_layers;   // per attentional layer: cross (true) or self
  float bin_score = 1.0f;
  int sinkhorn_iterations = 100;
};
SuperGlueConfig read_superglue_config(const io::ModelPack& pack);

class SuperGlue final : public PointMatcher {
 public:
  SuperGlue(const rt::Context& context, const io::ModelPack& pack, const SuperGlueParams& params = {});
  ~SuperGlue() override;
  SuperGlue(const SuperGlue&) = delete;
  SuperGlue& operator=(const SuperGlue&) = delete;

  // Keypoints are normalised by each set's own image_width / image_height (must be positive when non-empty).
  PointMatches match(const PointFeatures& a, const PointFeatures& b) override;
  // Same, and fills `log_assignment` ((N+1) x (M+1), dustbins last) when not null; empty when N or M is 0.
  PointMatches match(const PointFeatures& a, const PointFeatures& b, Eigen::MatrixXf* log_assignment);

  rt::Precision precision() const;
  const SuperGlueConfig& config() const;
  // The attention's form where qkv fits a texel view: "shared" (superglue_attention_shared.comp), "registers"
  // (superglue_attention_tiled.comp) or "three-pass" (q.k GEMM, softmax, p.v GEMM).
  std::string attention_form() const;
  // Per-dispatch GPU times of the last call: empty unless profiling is on (and the device has timestamps), or
  // when N or M was 0. Off by default: a timestamp after each of the ~300 dispatches costs lavapipe a few percent
  // of a call (rt::Sequence). Takes effect at the next match().
  void set_profiling(bool on);
  std::vector<rt::CommandTiming> last_timings() const;
  // Arithmetic of one call with n0 and n1 keypoints (multiply-adds count 2).
  double flops(std::size_t n0, std::size_t n1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vkvo::features
