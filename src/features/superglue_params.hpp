#pragma once
// SuperGlue's settings and their YAML loader, apart from the network (features/superglue.hpp) so that
// configuration code does not parse the Vulkan headers.
#include <optional>

#include <yaml-cpp/yaml.h>

#include "runtime/precision.hpp"

namespace vkvo::features {

struct SuperGlueParams {
  float match_threshold = 0.2f;            // keep mutual matches whose exp(log-assignment) exceeds this
  int sinkhorn_iterations = 100;           // <= 0: the pack's value
  std::optional<rt::Precision> precision;  // nullopt: the device profile's (rt::DeviceProfile::precision)
  // The fused attention, the score matrix and Sinkhorn through texel buffers (superglue_*_tiled.comp) where the
  // device can; false forces what devices with small texel buffers fall back to: attention as q.k GEMM, softmax
  // and p.v GEMM, storage-buffer scores and Sinkhorn (tests cover both).
  bool texel_kernels = true;
  // Query rows per invocation of the fused attention, 1-16; 0: rt::DeviceProfile::attention_rows.
  int attention_rows = 0;
  // The fused attention's GPU form (superglue_attention_shared.comp: a workgroup of 16 query rows shares each tile of
  // keys and values through shared memory, 4 invocations per row) rather than the register-held rows above, where
  // the fused attention runs and the device has the shared memory. nullopt: the device's choice (GPUs; CPUs keep
  // the register form, faster there); true / false: forced.
  std::optional<bool> shared_attention;
  // All Sinkhorn iterations in one workgroup (superglue_sinkhorn_fused.comp) rather than two dispatches each, where
  // the texel-buffer Sinkhorn runs and both sets have at most 1023 keypoints. nullopt: the device's choice (CPU
  // devices, for small couplings matrices: see superglue.cpp); true: whenever it can; false: never.
  std::optional<bool> fused_sinkhorn;
  // Where Sinkhorn dispatches per half-iteration through texel buffers: a workgroup per line
  // (superglue_sinkhorn_lines.comp) rather than an invocation per line (superglue_sinkhorn_tiled.comp).
  // nullopt: the device's choice (GPUs; CPUs keep an invocation per line); true / false: forced.
  std::optional<bool> sinkhorn_workgroup_per_line;
};

// YAML section `point_matcher`: match_threshold, sinkhorn_iterations, precision (fp32 | fp16s | fp16 | auto).
SuperGlueParams load_superglue_params(const YAML::Node& section);

}  // namespace vkvo::features
