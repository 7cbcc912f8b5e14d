#pragma once
// SuperGlue's weights as the device kernels take them, prepared on the host from a model pack's unfused fp32
// tensors (the layout of the official export, tools/convert):
// - the keypoint encoder's first layer padded from 3 to 4 inputs (x, y, score, 0), so its GEMM reads whole vec4s;
// - each attentional layer's q, k and v projections stacked into one 3 dim x dim layer, their output channels
//   regrouped from the official dim-major head split (channel d * heads + h) to head-major (h * head_dim + d), so
//   that a head's channels are contiguous for the attention kernel;
// - the merge projection folded into the first message-MLP layer: mlp0(concat(x, merge(m))) equals
//   [W0x | W0m Wmerge] concat(x, m) + (b0 + W0m bmerge), with m's channels head-major as the attention writes them
//   (folded in double precision).
// All weights go into one array (each layer's at an element offset that is a multiple of 4), all biases into
// another (each at a byte offset that is a multiple of kBiasAlignment, so that it can be bound on its own).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "features/superglue.hpp"
#include "io/model_pack.hpp"

namespace vkvo::features {

// One prepared linear layer y = W x + b: W row-major [out][in] at `weight_offset` elements into
// SuperGlueWeights::weights, b (fp32) at `bias_offset` bytes into SuperGlueWeights::biases.
struct PreparedLinear {
  std::uint32_t out = 0, in = 0;
  std::uint32_t weight_offset = 0;
  std::size_t bias_offset = 0;
};

struct SuperGlueWeights {
  static constexpr std::size_t kBiasAlignment = 256;  // bytes: >= minStorageBufferOffsetAlignment everywhere
  struct GnnLayer {
    bool cross = false;
    PreparedLinear qkv, mlp0, mlp1;  // q, k, v stacked head-major; merge folded into mlp0
  };
  std::vector<PreparedLinear> encoder;
  std::vector<GnnLayer> gnn;
  PreparedLinear final_proj;
  std::vector<float> weights, biases;
};

// Reads and checks every tensor `config` names (throws std::runtime_error naming the pack and the tensor when one
// is missing or has the wrong shape) and prepares them as above.
SuperGlueWeights prepare_superglue_weights(const io::ModelPack& pack, const SuperGlueConfig& config);

// The official (dim-major) channel that head-major channel `channel` takes: d * heads + h for channel
// h * head_dim + d.
int head_major_source(int channel, int heads, int head_dim);

}  // namespace vkvo::features
