// DeviceProfile: the per-device choices, pinned for a described CPU device (lavapipe) and a described discrete GPU
// (an H200), so that a change to any of them is a deliberate one (docs/performance-history.md has the figures).
#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "runtime/context.hpp"
#include "runtime/device_profile.hpp"

namespace vkvo::rt {
namespace {

DeviceCaps lavapipe() {
  return {.name = "llvmpipe (LLVM 15.0.6, 256 bits)",
          .type = "cpu",
          .float16_arithmetic = true,
          .storage_16bit = true,
          .int64 = true,
          .subgroup_size = 8,
          .max_shared_memory_bytes = 32768};
}

DeviceCaps h200() {
  return {.name = "NVIDIA H200",
          .type = "discrete",
          .float16_arithmetic = true,
          .storage_16bit = true,
          .int64 = true,
          .subgroup_size = 32,
          .max_shared_memory_bytes = 49152};
}

// Every field of `profile` as `expected` has it.
void expect_choices(const DeviceProfile& profile, const DeviceProfile& expected) {
  EXPECT_EQ(profile.precision, expected.precision);
  EXPECT_EQ(profile.wide_gemm_tile, expected.wide_gemm_tile);
  EXPECT_EQ(profile.winograd, expected.winograd);
  EXPECT_EQ(profile.conv1x1_as_gemm, expected.conv1x1_as_gemm);
  EXPECT_EQ(profile.shared_attention, expected.shared_attention);
  EXPECT_EQ(profile.attention_rows, expected.attention_rows);
  EXPECT_EQ(profile.sinkhorn_workgroup_per_line, expected.sinkhorn_workgroup_per_line);
  EXPECT_EQ(profile.fused_sinkhorn_max_cells, expected.fused_sinkhorn_max_cells);
}

// fp32 (fp16 math is emulated, 16-bit storage gains nothing), the wide GEMM tile, Winograd and 1x1 layers as GEMMs,
// the register attention with 8 rows, an invocation per Sinkhorn line and the fused Sinkhorn up to 48 Ki couplings.
TEST(DeviceProfile, CpuDeviceChoices) {
  expect_choices(make_device_profile(lavapipe()), {.precision = Precision::fp32,
                                                   .wide_gemm_tile = true,
                                                   .winograd = true,
                                                   .conv1x1_as_gemm = true,
                                                   .shared_attention = false,
                                                   .attention_rows = 8,
                                                   .sinkhorn_workgroup_per_line = false,
                                                   .fused_sinkhorn_max_cells = 48 * 1024});
}

// 16-bit storage with fp32 math, the 4 x 8 GEMM tile, direct convolutions, the shared-memory attention and a
// workgroup per Sinkhorn line, never the fused Sinkhorn.
TEST(DeviceProfile, DiscreteGpuChoices) {
  expect_choices(make_device_profile(h200()), {.precision = Precision::fp16s,
                                               .wide_gemm_tile = false,
                                               .winograd = false,
                                               .conv1x1_as_gemm = false,
                                               .shared_attention = true,
                                               .attention_rows = 4,
                                               .sinkhorn_workgroup_per_line = true,
                                               .fused_sinkhorn_max_cells = 0});
}

TEST(DeviceProfile, GpuWithoutSixteenBitStorageDefaultsToFp32) {
  DeviceCaps caps = h200();
  caps.storage_16bit = false;
  EXPECT_EQ(make_device_profile(caps).precision, Precision::fp32);
}

TEST(DeviceProfile, ContextBuildsItFromTheCapsItEnabled) {
  const Context& context = test::gpu();
  const DeviceProfile expected = make_device_profile(context.caps());
  EXPECT_EQ(context.profile().precision, expected.precision);
  EXPECT_EQ(context.profile().winograd, expected.winograd);
  EXPECT_TRUE(context.caps().supports(context.profile().precision));
  const Context without_16bit({.pipeline_cache = false, .use_16bit = false});
  EXPECT_EQ(without_16bit.profile().precision, Precision::fp32);
}

}  // namespace
}  // namespace vkvo::rt
