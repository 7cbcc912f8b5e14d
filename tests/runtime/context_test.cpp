#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "runtime/context.hpp"
#include "runtime/kernel.hpp"

namespace vkvo::rt {
namespace {

TEST(Context, ListsAtLeastOneDeviceWithSaneCaps) {
  const auto devices = list_devices();
  ASSERT_FALSE(devices.empty());
  for (const auto& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GE(d.api_version, VK_API_VERSION_1_1) << d.name;
    EXPECT_GT(d.subgroup_size, 0u) << d.name;
    EXPECT_GE(d.max_workgroup_invocations, 128u) << d.name;
    EXPECT_FALSE(d.heaps.empty()) << d.name;
  }
}

TEST(Context, SharedContextHasAPrecisionItSupports) {
  const auto& caps = test::gpu().caps();
  EXPECT_TRUE(caps.supports(Precision::fp32));
  EXPECT_TRUE(caps.supports(test::gpu().profile().precision));
}

TEST(Context, SelectsDeviceByIndexAndByNameSubstring) {
  const auto devices = list_devices();
  const Context by_index({.device = "0", .validation = false, .pipeline_cache = false});
  EXPECT_EQ(by_index.caps().name, devices[0].name);
  std::string fragment = devices[0].name.substr(0, 4);
  for (auto& c : fragment) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));  // case-insensitive
  const Context by_name({.device = fragment, .validation = false, .pipeline_cache = false});
  EXPECT_EQ(by_name.caps().name, devices[0].name);
}

TEST(Context, UnknownDeviceSelectorIsAClearError) {
  try {
    const Context context({.device = "no-such-gpu-xyz", .validation = false, .pipeline_cache = false});
    FAIL() << "expected VulkanError";
  } catch (const VulkanError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpu-xyz"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Context({.device = "999", .validation = false, .pipeline_cache = false}), VulkanError);
}

TEST(Context, WithoutSixteenBitFeaturesOnlyFp32Runs) {
  const Context context({.pipeline_cache = false, .use_16bit = false});
  EXPECT_TRUE(context.caps().supports(Precision::fp32));
  EXPECT_FALSE(context.caps().supports(Precision::fp16s));
  EXPECT_FALSE(context.caps().supports(Precision::fp16));
  EXPECT_EQ(context.profile().precision, Precision::fp32);
  EXPECT_NO_THROW(context.caps().require(Precision::fp32, "test"));
  const std::string error =
      test::error_of([&] { Kernel kernel(context, {.op = Op::gemm, .precision = Precision::fp16s}); });
  EXPECT_NE(error.find("shader gemm: device '" + context.caps().name + "' does not support precision fp16s"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("16-bit storage"), std::string::npos) << error;
}

// With no driver for the loader to find, creating a context fails with the step and a hint, not a crash.
TEST(Context, NoVulkanDriverIsAClearError) {
  std::string error;
  {
    // Both names the loader reads for the driver manifests (VK_DRIVER_FILES from loader 1.3.207 on).
    const test::ScopedEnv icd("VK_ICD_FILENAMES", "/nonexistent/vkvo_no_driver.json"),
        drivers("VK_DRIVER_FILES", "/nonexistent/vkvo_no_driver.json");
    error = test::error_of([] { Context context({.validation = false, .pipeline_cache = false}); });
  }
  EXPECT_NE(error.find("Vulkan"), std::string::npos) << error;
  EXPECT_NE(error.find("vulkaninfo"), std::string::npos) << error;
  // The next context finds the driver again.
  EXPECT_NO_THROW(Context({.validation = false, .pipeline_cache = false}));
}

TEST(Context, PipelineCacheIsWrittenToDisk) {
  const auto dir = test::temp_dir("pipeline_cache") / "cache";  // not there yet: the context makes it
  { const Context context({.validation = false, .cache_dir = dir}); }
  ASSERT_TRUE(std::filesystem::exists(dir));
  EXPECT_FALSE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace vkvo::rt

namespace vkvo::rt {
namespace {

// ctest runs every test with VKVO_VALIDATION=1: make sure the layer really is there, or "no validation
// messages" would prove nothing.
TEST(Context, ValidationLayerIsActiveWhenRequested) {
  const char* env = std::getenv("VKVO_VALIDATION");
  if (!env || std::string(env) != "1") GTEST_SKIP() << "VKVO_VALIDATION is not 1 (ctest sets it)";
  EXPECT_TRUE(test::gpu().validation_enabled()) << "install vulkan-validationlayers (tools/setup.sh does)";
}

}  // namespace
}  // namespace vkvo::rt
