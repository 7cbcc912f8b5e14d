// DeviceProfile: the per-device choices, pinned for a described CPU device (lavapipe) and a described discrete GPU
// (an H200), so that a change to any of them is a deliberate one (docs/performance-history.md has the figures).
#include <cstdlib>
#include <optional>
#include <string>

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
  EXPECT_EQ(profile.cooperative_matrix, expected.cooperative_matrix);
}

// An H200 as VK_NV_cooperative_matrix describes it: the kernels' shape among others.
DeviceCaps h200_with_tensor_cores() {
  DeviceCaps caps = h200();
  caps.max_workgroup_invocations = 1024;
  caps.cooperative_matrix = CooperativeMatrixApi::nv;
  caps.vulkan_memory_model = true;
  CooperativeMatrixShape fp16_result = kCoopmatKernelShape;
  fp16_result.c = fp16_result.result = MatrixComponent::f16;
  CooperativeMatrixShape int8{.m = 16, .n = 16, .k = 32};
  int8.a = int8.b = MatrixComponent::s8;
  int8.c = int8.result = MatrixComponent::s32;
  int8.scope = MatrixScope::subgroup;
  caps.cooperative_matrix_shapes = {fp16_result, kCoopmatKernelShape, int8};
  return caps;
}

// Restores an environment variable's value when the test ends.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      setenv(name, value, 1);
    else
      unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

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

TEST(DeviceProfile, TensorCoresWhereTheDeviceReportsTheKernelsShape) {
  const ScopedEnv unset("VKVO_COOPERATIVE_MATRIX", nullptr);
  EXPECT_TRUE(make_device_profile(h200_with_tensor_cores()).cooperative_matrix);
  EXPECT_TRUE(make_device_profile(effective_caps(h200_with_tensor_cores(), {})).cooperative_matrix);
  // Everything else stays as on a GPU without them.
  DeviceProfile expected = make_device_profile(h200());
  expected.cooperative_matrix = true;
  expect_choices(make_device_profile(h200_with_tensor_cores()), expected);
}

TEST(DeviceProfile, NoTensorCoresWithoutTheKernelsShape) {
  DeviceCaps caps = h200_with_tensor_cores();
  // 16x16x16 with fp16 accumulation, 16x8x16 fp32 and a workgroup-scope one: none is what the kernels run.
  CooperativeMatrixShape smaller_n = kCoopmatKernelShape, workgroup = kCoopmatKernelShape;
  smaller_n.n = 8;
  workgroup.scope = MatrixScope::workgroup;
  caps.cooperative_matrix_shapes.erase(caps.cooperative_matrix_shapes.begin() + 1);
  caps.cooperative_matrix_shapes.push_back(smaller_n);
  caps.cooperative_matrix_shapes.push_back(workgroup);
  EXPECT_FALSE(make_device_profile(caps).cooperative_matrix);
  EXPECT_FALSE(make_device_profile(h200()).cooperative_matrix);
  EXPECT_FALSE(make_device_profile(lavapipe()).cooperative_matrix);
}

TEST(DeviceProfile, NoTensorCoresWithoutTheExtensionOrSixteenBitTypes) {
  DeviceCaps no_api = h200_with_tensor_cores();
  no_api.cooperative_matrix = CooperativeMatrixApi::none;  // shapes listed, but the feature or memory model missing
  EXPECT_FALSE(make_device_profile(no_api).cooperative_matrix);
  EXPECT_FALSE(make_device_profile(effective_caps(h200_with_tensor_cores(), {.use_16bit = false})).cooperative_matrix);
}

// The kernels' workgroups: four subgroups and 26.5 KiB of shared memory.
TEST(DeviceProfile, NoTensorCoresWithoutRoomForTheirWorkgroups) {
  DeviceCaps small_shared = h200_with_tensor_cores(), small_groups = h200_with_tensor_cores();
  small_shared.max_shared_memory_bytes = 16384;
  small_groups.max_workgroup_invocations = 64;
  EXPECT_FALSE(make_device_profile(small_shared).cooperative_matrix);
  EXPECT_FALSE(make_device_profile(small_groups).cooperative_matrix);
  EXPECT_EQ(kCoopmatSharedBytes, 27136u);
}

TEST(DeviceProfile, CooperativeMatrixOffSwitch) {
  {
    const ScopedEnv off("VKVO_COOPERATIVE_MATRIX", "0");
    const DeviceCaps caps = effective_caps(h200_with_tensor_cores(), {});
    EXPECT_FALSE(make_device_profile(caps).cooperative_matrix);
    EXPECT_TRUE(caps.cooperative_matrix_shapes.empty());
    // An explicit option overrides the environment.
    EXPECT_TRUE(
        make_device_profile(effective_caps(h200_with_tensor_cores(), {.cooperative_matrix = true})).cooperative_matrix);
  }
  const ScopedEnv on("VKVO_COOPERATIVE_MATRIX", "1");
  EXPECT_TRUE(make_device_profile(effective_caps(h200_with_tensor_cores(), {})).cooperative_matrix);
  EXPECT_FALSE(
      make_device_profile(effective_caps(h200_with_tensor_cores(), {.cooperative_matrix = false})).cooperative_matrix);
}

TEST(DeviceProfile, ShapesPrintAsDevicesListsThem) {
  EXPECT_EQ(to_string(kCoopmatKernelShape), "16x16x16 f16*f16+f32->f32 subgroup");
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
  EXPECT_EQ(context.profile().cooperative_matrix, expected.cooperative_matrix);
  // The shapes are listed only with the extension that runs them.
  if (context.caps().cooperative_matrix == CooperativeMatrixApi::none) {
    EXPECT_TRUE(context.caps().cooperative_matrix_shapes.empty());
  }
  EXPECT_TRUE(context.caps().supports(context.profile().precision));
  const Context without_16bit({.pipeline_cache = false, .use_16bit = false});
  EXPECT_EQ(without_16bit.profile().precision, Precision::fp32);
}

}  // namespace
}  // namespace vkvo::rt
