// An ONNX file found by the model locator (tools/convert/model_locator.hpp) is converted once into the cache
// folder and the pack reused while the file is unchanged; a broken ONNX file is an error naming it.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "io/model_pack.hpp"
#include "tools/convert/model_locator.hpp"

namespace vkvo::convert {
namespace {

namespace fs = std::filesystem;

TEST(ModelLocatorData, AnOnnxFileIsConvertedOnceIntoTheCache) {
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  const auto dir = vkvo::test::temp_dir("locator_convert");
  fs::create_directories(dir / "models");
  fs::copy_file(onnx, dir / "models" / "superpoint_v1.onnx");
  const std::string cache = (dir / "cache").string();
  const vkvo::test::ScopedEnv cache_dir("VKVO_CACHE_DIR", cache.c_str());
  const ModelSearch search{{{dir / "models", "models"}}};

  const auto first = locate_model("superpoint_v1", {}, search);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->pack.parent_path(), fs::path(cache));
  EXPECT_NE(first->how.find("converted from"), std::string::npos) << first->how;
  EXPECT_NO_THROW(io::ModelPack::load(first->pack, io::NetworkKind::superpoint));
  const auto written = fs::last_write_time(first->pack);
  const auto second = locate_model("superpoint_v1", {}, search);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->pack, first->pack);
  EXPECT_EQ(fs::last_write_time(second->pack), written) << "converted again";

  vkvo::test::write_text(dir / "broken" / "superpoint_v1.onnx", "not a protobuf");
  const std::string error = vkvo::test::error_of([&] {
    locate_model("superpoint_v1", {}, ModelSearch{{{dir / "broken", "broken"}}});
  });
  EXPECT_NE(error.find("superpoint_v1.onnx"), std::string::npos) << error;
}

}  // namespace
}  // namespace vkvo::convert
