// SuperPoint ONNX -> pack on the shared superpoint_v1.onnx: every tensor equals rt::pack_conv_o4 of the ONNX
// initializer (looked up here by its PyTorch name, which the converter never uses), the int32-constant and
// Constant-node variants give the identical pack, and broken graphs are refused naming the node.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "convert/convert_test_support.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::convert {
namespace {

using test::expect_error;

constexpr const char* kModel = "models/superpoint_v1.onnx";
const char* const kLayers[] = {"conv1a", "conv1b", "conv2a", "conv2b", "conv3a", "conv3b",
                               "conv4a", "conv4b", "convPa", "convPb", "convDa", "convDb"};

TEST(SuperPointConvert, TensorsEqualPackedOnnxInitializers) {
  VKVO_REQUIRE_DATA(path, kModel);
  const auto model = test::load_model(path);
  const io::ModelPack pack = test::convert_model(model, io::NetworkKind::superpoint, path.string());

  EXPECT_EQ(pack.integer("descriptor_dim"), 256);
  EXPECT_EQ(pack.integer("detector_channels"), 65);
  EXPECT_EQ(pack.integer("cell"), 8);
  EXPECT_EQ(pack.tensors().size(), 12u * 2 * 2);  // weight + bias, fp32 + fp16
  for (const std::string layer : kLayers) {
    SCOPED_TRACE(layer);
    std::vector<std::int64_t> dims;
    const auto weight = test::tensor_values(model, layer + ".weight", &dims);
    const auto bias = test::tensor_values(model, layer + ".bias");
    const auto o = static_cast<std::size_t>(dims[0]), i = static_cast<std::size_t>(dims[1]);
    const auto k = static_cast<std::size_t>(dims[2]);
    const auto packed_weight = rt::pack_conv_o4(weight, o, i, k, k);
    const auto packed_bias = rt::pad_bias_o4(bias);

    EXPECT_EQ(pack.tensor(layer + ".weight", io::DType::fp32).shape, dims);
    EXPECT_EQ(pack.tensor(layer + ".weight", io::DType::fp32).layout, "o4");
    // fp32 copies are exact; fp16 copies are the round-to-nearest-even halves of the same values.
    EXPECT_EQ(pack.floats(layer + ".weight", io::DType::fp32), packed_weight);
    EXPECT_EQ(pack.floats(layer + ".bias", io::DType::fp32), packed_bias);
    EXPECT_EQ(pack.floats(layer + ".weight", io::DType::fp16), test::as_half(packed_weight));
    EXPECT_EQ(pack.floats(layer + ".bias", io::DType::fp16), test::as_half(packed_bias));
  }
  // The detector's 65 outputs are padded to 68 with zeros.
  const auto pb = pack.floats("convPb.weight", io::DType::fp32);
  ASSERT_EQ(pb.size(), 17u * 256 * 4);
  for (std::size_t i = 0; i < 256; ++i)
    for (std::size_t lane = 1; lane < 4; ++lane) EXPECT_EQ(pb[(16 * 256 + i) * 4 + lane], 0.0f);
}

TEST(SuperPointConvert, ConvertFileWritesAVerifiedPack) {
  VKVO_REQUIRE_DATA(path, kModel);
  const auto out = vkvo::test::temp_dir("sp_convert_file") / "superpoint_v1.vkvopack";
  const auto summary = convert_file(path, out);
  EXPECT_EQ(summary.kind, io::NetworkKind::superpoint);
  EXPECT_EQ(summary.tensors, 48u);
  EXPECT_EQ(summary.bytes, std::filesystem::file_size(out));
  const io::ModelPack pack = io::ModelPack::load(out, io::NetworkKind::superpoint);
  EXPECT_EQ(pack.string("source"), "superpoint_v1.onnx");
  expect_error([&] { io::ModelPack::load(out, io::NetworkKind::superglue); }, {"holds a superpoint network"});
}

TEST(SuperPointConvert, Int32ConstantsAndConstantNodeWeightsGiveTheSamePack) {
  VKVO_REQUIRE_DATA(path, kModel);
  const auto model = test::load_model(path);
  const auto reference = test::convert_bytes(model, path.string());

  auto int32 = model;
  EXPECT_GT(test::int64_constants_to_int32(int32), 10);  // the Slice/Reshape/Unsqueeze constants
  EXPECT_EQ(test::convert_bytes(int32, path.string()), reference);

  auto constants = model;
  test::initializers_to_constant_nodes(constants);
  ASSERT_EQ(constants.graph().initializer_size(), 0);
  EXPECT_EQ(test::convert_bytes(constants, path.string()), reference);
}

TEST(SuperPointConvert, WrongConvShapeIsRefusedNamingTheNode) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // conv3a as 128 <- 32 channels instead of 128 <- 64.
  for (auto& t : *model.mutable_graph()->mutable_initializer())
    if (t.name() == "conv3a.weight") {
      t.set_dims(1, 32);
      t.mutable_raw_data()->resize(t.raw_data().size() / 2);
    }
  expect_error([&] { test::convert_bytes(model, "broken.onnx"); },
               {"broken.onnx", "node '/conv3a/Conv' (Conv)", "conv3a", "128x64x3x3", "128x32x3x3"});
}

TEST(SuperPointConvert, MissingEncoderLayerIsRefused) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // Drop conv4b: its ReLU reads conv4a's ReLU output directly.
  const std::string conv4a_relu = test::find_node(model, "/conv4b/Conv")->input(0);
  test::find_node(model, "/Relu_7")->set_input(0, conv4a_relu);
  test::remove_dead_nodes(model);
  expect_error([&] { test::convert_bytes(model, "missing.onnx"); },
               {"missing.onnx", "encoder", "found 7", "expected 8"});
}

TEST(SuperPointConvert, MissingDescriptorHeadIsRefused) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // Keep only the detector output: the descriptor head becomes dead and is removed.
  model.mutable_graph()->mutable_output()->DeleteSubrange(1, 1);
  test::remove_dead_nodes(model);
  expect_error([&] { test::convert_bytes(model, "one_head.onnx"); },
               {"one_head.onnx", "1 detector and 0 descriptor head"});
}

}  // namespace
}  // namespace vkvo::convert
