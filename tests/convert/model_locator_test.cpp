// Where `vkvo run` finds its weights (tools/convert/model_locator.hpp): an explicit path first, then the search
// folders in order, a pack before an ONNX file in each; the default order read from the environment. The
// conversion of an ONNX file on first use: model_locator_data_test.cpp.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "tools/convert/model_locator.hpp"

namespace vkvo::convert {
namespace {

namespace fs = std::filesystem;
using vkvo::test::ScopedEnv;

// The locator does not read the files it finds; any bytes stand for a pack here.
fs::path touch(const fs::path& file) {
  vkvo::test::write_text(file, "not read");
  return file;
}

TEST(ModelLocator, AnExplicitPathComesFirstAndMustExist) {
  const auto dir = vkvo::test::temp_dir("locator_explicit");
  const auto given = touch(dir / "mine.vkvopack");
  const ModelSearch search{{{touch(dir / "searched" / "superpoint_v1.vkvopack").parent_path(), "searched"}}};
  const auto found = locate_model("superpoint_v1", given, search);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->pack, given);
  EXPECT_EQ(found->how, "given");
  const std::string error = vkvo::test::error_of([&] { locate_model("superpoint_v1", dir / "missing.onnx", search); });
  EXPECT_NE(error.find("missing.onnx"), std::string::npos) << error;
  EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
}

TEST(ModelLocator, FoldersAreSearchedInOrderAPackBeforeAnOnnxFile) {
  const auto dir = vkvo::test::temp_dir("locator_order");
  const ModelSearch search{{{dir / "first", "first"}, {dir / "second", "second"}, {dir / "third", "third"}}};
  EXPECT_FALSE(locate_model("superpoint_v1", {}, search)) << "nothing there yet";

  touch(dir / "third" / "superpoint_v1.vkvopack");
  touch(dir / "second" / "other_network.vkvopack");
  auto found = locate_model("superpoint_v1", {}, search);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->pack, dir / "third" / "superpoint_v1.vkvopack");
  EXPECT_EQ(found->how, "third");

  // In one folder the pack wins over the ONNX file (which would otherwise be converted: not a valid model here).
  touch(dir / "first" / "superpoint_v1.onnx");
  const auto first_pack = touch(dir / "first" / "superpoint_v1.vkvopack");
  found = locate_model("superpoint_v1", {}, search);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->pack, first_pack);
  EXPECT_EQ(found->how, "first");
}

TEST(ModelLocator, DefaultSearchIsModelsThenTheCheckoutThenTheSharedData) {
  // Paths only: nothing is read, so the folders need not exist.
  const fs::path root = fs::temp_directory_path() / "vkvo-model-search";
  const fs::path my_models = root / "my-models", shared = root / "vkvo-data", checkout = root / "vkvo";
  const ScopedEnv models("VKVO_MODELS", my_models.c_str()), data("VKVO_DATA", shared.c_str());
  const auto search = default_model_search(checkout);
  ASSERT_EQ(search.folders.size(), 5u);
  EXPECT_EQ(search.folders[0].path, my_models);
  EXPECT_EQ(search.folders[1].path, checkout / "models");
  EXPECT_EQ(search.folders[2].path, shared / "models");
  EXPECT_EQ(search.folders[3].path, fs::current_path() / ".." / "shared" / "models");
  EXPECT_EQ(search.folders[4].path, checkout / ".." / "shared" / "models");

  const ScopedEnv no_models("VKVO_MODELS", nullptr), no_data("VKVO_DATA", nullptr);
  const auto bare = default_model_search({});
  ASSERT_EQ(bare.folders.size(), 1u) << "no environment, no checkout: ../shared/models only";
  EXPECT_EQ(bare.folders[0].path, fs::current_path() / ".." / "shared" / "models");
}

TEST(ModelLocator, TheHelpSaysWhereToPutTheWeights) {
  const std::string help = superpoint_help();
  for (const char* part : {"superpoint_v1.onnx", "$VKVO_MODELS", "models/", "vkvo convert"})
    EXPECT_NE(help.find(part), std::string::npos) << part;
}

}  // namespace
}  // namespace vkvo::convert
