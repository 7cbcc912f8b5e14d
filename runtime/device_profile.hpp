#pragma once
// Every per-device choice vkvo makes, made once from the device's caps (Context::profile()): the default precision,
// which of two kernels computing the same thing runs, and their tile sizes. Each was measured on lavapipe and on an
// NVIDIA H200 (docs/performance-history.md): a CPU driver runs a workgroup as a few wide threads, where barriers,
// dispatches and texel fetches are expensive and a thread can hold many accumulators; a GPU wants many invocations,
// shared memory and small register footprints. Callers may still force a form (SuperGlueParams, SuperPointParams,
// GemmKernel); the profile is what `automatic` means.
#include <cstddef>
#include <cstdint>

#include "runtime/precision.hpp"

namespace vkvo::rt {

struct DeviceCaps;

struct DeviceProfile {
  // Storage precision of the networks when none is asked for. fp16 math is never the default: every kernel
  // accumulates in fp32 and it bought no speed on a GPU, while it takes SuperPoint's dense scores past the golden
  // tolerance; CPU devices emulate fp16 and save no bandwidth that matters by halving the storage, so they get fp32.
  Precision precision = Precision::fp32;
  // GemmKernel::automatic runs gemm_tiled_wide (8 x 16 blocks of C: fewer fetches of A per multiply-add on a CPU)
  // rather than gemm_tiled (4 x 8: fewer registers per invocation on a GPU).
  bool wide_gemm_tile = false;
  // SuperPoint: 3x3 layers by Winograd F(m x m, 3x3) where they can (fp32, the tiled kernels); 1x1 layers as tiled
  // GEMMs over the planes rather than conv1x1_tiled (which fetches one pixel per texel).
  bool winograd = false;
  bool conv1x1_as_gemm = false;
  // SuperGlue's fused attention: superglue_attention_shared (a workgroup shares key and value tiles through shared
  // memory) rather than superglue_attention_tiled (a few whole query rows per invocation, `attention_rows` of them).
  bool shared_attention = false;
  std::uint32_t attention_rows = 4;
  // SuperGlue's Sinkhorn: a workgroup per line (superglue_sinkhorn_lines) rather than an invocation per line, and
  // every iteration in one workgroup (superglue_sinkhorn_fused) while Z has at most this many entries (0: never).
  bool sinkhorn_workgroup_per_line = false;
  std::size_t fused_sinkhorn_max_cells = 0;
  // Tensor cores: GEMMs and SuperPoint's 3x3 layers run the cooperative-matrix kernels (gemm_coopmat,
  // conv3x3_coopmat: fp16 operands, fp32 accumulation) at the 16-bit storage precisions. Only where the device
  // reports kCoopmatKernelShape with 16-bit storage and arithmetic, and VKVO_COOPERATIVE_MATRIX is not 0
  // (effective_caps); docs/tensor-cores.md.
  bool cooperative_matrix = false;
};

// Whether the tensor-core kernels can run on a device with these caps (the profile's cooperative_matrix): the
// shape, 16-bit storage and arithmetic, and room for their workgroups (kCoopmatSubgroups, kCoopmatSharedBytes).
bool supports_coopmat_kernels(const DeviceCaps& caps);

DeviceProfile make_device_profile(const DeviceCaps& caps);

}  // namespace vkvo::rt
