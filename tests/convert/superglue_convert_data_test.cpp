// SuperGlue ONNX -> pack on the shared superglue_synthetic.onnx: the layer count (18), types and hyper-parameters
// come from the graph; every tensor equals the ONNX weight of the Conv node the exporter named after the PyTorch
// module (names used only here, as the independent reference); the int32 variant gives the same pack; a graph cut
// to 16 layers gives 16; broken graphs are refused naming the node.
#include <regex>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "convert/convert_test_support.hpp"

namespace vkvo::convert {
namespace {

using test::expect_error;

constexpr const char* kModel = "models/superglue_synthetic.onnx";

// Pack layer name of a first-keypoint-set Conv node of the exported graph, "" for other nodes.
std::string pack_name(const std::string& node) {
  static const std::regex kenc(R"(/kenc/encoder/encoder\.(\d+)/Conv)");
  static const std::regex proj(R"(/gnn/layers\.(\d+)/attn/proj\.(\d)/Conv)");
  static const std::regex merge(R"(/gnn/layers\.(\d+)/attn/merge/Conv)");
  static const std::regex mlp(R"(/gnn/layers\.(\d+)/mlp/mlp\.(\d)/Conv)");
  std::smatch m;
  if (std::regex_match(node, m, kenc)) return "kenc." + std::to_string(std::stoi(m[1]) / 3);  // 0,3,6,9,12
  if (std::regex_match(node, m, proj)) return "gnn." + m[1].str() + "." + "qkv"[std::stoi(m[2])];
  if (std::regex_match(node, m, merge)) return "gnn." + m[1].str() + ".merge";
  if (std::regex_match(node, m, mlp)) return "gnn." + m[1].str() + (m[2] == "0" ? ".mlp0" : ".mlp1");
  if (node == "/final_proj/Conv") return "final_proj";
  return "";
}

TEST(SuperGlueConvert, StructureAndTensorsMatchTheOnnxGraph) {
  VKVO_REQUIRE_DATA(path, kModel);
  const auto model = test::load_model(path);
  const io::ModelPack pack = test::convert_model(model, io::NetworkKind::superglue, path.string());

  EXPECT_EQ(pack.integer("gnn_layers"), 18);
  EXPECT_EQ(pack.integer("descriptor_dim"), 256);
  EXPECT_EQ(pack.integer("heads"), 4);
  EXPECT_EQ(pack.integer("sinkhorn_iterations"), 100);
  EXPECT_EQ(pack.numbers("keypoint_encoder"), (std::vector<double>{32, 64, 128, 256}));
  EXPECT_EQ(pack.string("attention_channel_order"), "dim_major");
  std::string alternating;
  for (int l = 0; l < 18; ++l) alternating += l == 0 ? "self" : (l % 2 ? ",cross" : ",self");
  EXPECT_EQ(pack.string("gnn_layer_types"), alternating);
  EXPECT_EQ(pack.number("bin_score"), test::tensor_values(model, "bin_score").at(0));

  std::size_t checked = 0;
  for (const auto& node : model.graph().node()) {
    const std::string name = pack_name(node.name());
    if (name.empty()) continue;
    SCOPED_TRACE(node.name() + " -> " + name);
    std::vector<std::int64_t> dims;
    const auto weight = test::tensor_values(model, node.input(1), &dims);
    const auto bias = test::tensor_values(model, node.input(2));
    const auto& info = pack.tensor(name + ".weight", io::DType::fp32);
    EXPECT_EQ(info.layout, "oi");
    EXPECT_EQ(info.shape, (std::vector<std::int64_t>{dims[0], dims[1]}));
    EXPECT_EQ(pack.floats(name + ".weight", io::DType::fp32), weight);
    EXPECT_EQ(pack.floats(name + ".bias", io::DType::fp32), bias);
    EXPECT_EQ(pack.floats(name + ".weight", io::DType::fp16), test::as_half(weight));
    EXPECT_EQ(pack.floats(name + ".bias", io::DType::fp16), test::as_half(bias));
    ++checked;
  }
  EXPECT_EQ(checked, 5u + 18 * 6 + 1);
  EXPECT_EQ(pack.tensors().size(), checked * 4);  // nothing else in the pack
}

TEST(SuperGlueConvert, Int32ConstantsGiveTheSamePack) {
  VKVO_REQUIRE_DATA(path, kModel);
  const auto model = test::load_model(path);
  auto int32 = model;
  EXPECT_GT(test::int64_constants_to_int32(int32), 100);  // among them the head-split Reshape shapes
  EXPECT_EQ(test::convert_bytes(int32, path.string()), test::convert_bytes(model, path.string()));
}

TEST(SuperGlueConvert, LayerCountIsReadFromTheGraph) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // Feed the final projections with the states after layer 15 (residual Adds 30 and 31): layers 16, 17 go dead.
  test::find_node(model, "/final_proj/Conv")->set_input(0, "/gnn/Add_30_output_0");
  test::find_node(model, "/final_proj_1/Conv")->set_input(0, "/gnn/Add_31_output_0");
  test::remove_dead_nodes(model);
  const io::ModelPack pack = test::convert_model(model, io::NetworkKind::superglue, "cut.onnx");
  EXPECT_EQ(pack.integer("gnn_layers"), 16);
  EXPECT_TRUE(pack.has_tensor("gnn.15.mlp1.weight", io::DType::fp16));
  EXPECT_FALSE(pack.has_tensor("gnn.16.q.weight", io::DType::fp32));
}

TEST(SuperGlueConvert, WrongLayerShapeIsRefusedNamingTheNode) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  for (auto& t : *model.mutable_graph()->mutable_initializer())
    if (t.name() == "gnn.layers.5.attn.merge.weight") {
      t.set_dims(1, 128);
      t.mutable_raw_data()->resize(t.raw_data().size() / 2);
    }
  expect_error([&] { test::convert_bytes(model, "broken.onnx"); },
               {"broken.onnx", "node '/gnn/layers.5/attn/merge/Conv' (Conv)", "merge layer", "256 -> 256"});
}

TEST(SuperGlueConvert, UnmappableAttentionIsRefusedNamingTheNode) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // Layer 3's key and value projections read the keypoint-encoder output instead of either current state.
  test::find_node(model, "/gnn/layers.3/attn/proj.1/Conv")->set_input(0, "/Add_output_0");
  test::find_node(model, "/gnn/layers.3/attn/proj.2/Conv")->set_input(0, "/Add_output_0");
  expect_error([&] { test::convert_bytes(model, "rewired.onnx"); },
               {"rewired.onnx", "node '/gnn/layers.3/attn/proj.1/Conv'", "neither keypoint set's state"});
}

TEST(SuperGlueConvert, DifferentWeightsForTheTwoKeypointSetsAreRefused) {
  VKVO_REQUIRE_DATA(path, kModel);
  auto model = test::load_model(path);
  // The second set's final projection reads its own (edited) copy of the weights.
  auto* node = test::find_node(model, "/final_proj_1/Conv");
  onnx::TensorProto copy;
  for (const auto& t : model.graph().initializer())
    if (t.name() == node->input(1)) copy = t;
  copy.set_name("final_proj_copy.weight");
  (*copy.mutable_raw_data())[0] ^= 1;
  *model.mutable_graph()->add_initializer() = copy;
  node->set_input(1, "final_proj_copy.weight");
  expect_error([&] { test::convert_bytes(model, "unshared.onnx"); },
               {"unshared.onnx", "node '/final_proj_1/Conv'", "differs from the first set's"});
}

}  // namespace
}  // namespace vkvo::convert
