#pragma once
// Helpers of the converter tests: ONNX files edited in memory (int64 -> int32 constants, weights as Constant
// nodes, dead-node removal) and an independent reader of initializer values to compare the packs against.
#include <cstring>
#include <fstream>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <onnx/onnx_pb.h>

#include "io/model_pack.hpp"
#include "runtime/half.hpp"
#include "tools/convert/convert.hpp"

namespace vkvo::convert::test {

// Runs `action`, expecting a std::runtime_error whose message contains every one of `parts`.
inline void expect_error(const std::function<void()>& action, const std::vector<std::string>& parts) {
  try {
    action();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    for (const auto& part : parts) EXPECT_NE(message.find(part), std::string::npos) << "message: " << message;
    return;
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
}

inline onnx::ModelProto load_model(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  onnx::ModelProto model;
  if (!model.ParseFromIstream(&in)) throw std::runtime_error("cannot parse " + path.string());
  return model;
}

inline onnx::NodeProto* find_node(onnx::ModelProto& model, const std::string& name) {
  for (auto& node : *model.mutable_graph()->mutable_node())
    if (node.name() == name) return &node;
  throw std::runtime_error("test model has no node " + name);
}

// The float tensor behind a value: initializer, Constant node or Identity of either (the test's own reading).
inline std::vector<float> tensor_values(const onnx::ModelProto& model, std::string value,
                                        std::vector<std::int64_t>* dims = nullptr) {
  for (int hops = 0; hops < 8; ++hops) {
    for (const auto& t : model.graph().initializer()) {
      if (t.name() != value) continue;
      if (dims) dims->assign(t.dims().begin(), t.dims().end());
      if (t.raw_data().empty()) return {t.float_data().begin(), t.float_data().end()};
      std::vector<float> values(t.raw_data().size() / 4);
      std::memcpy(values.data(), t.raw_data().data(), values.size() * 4);
      return values;
    }
    bool followed = false;
    for (const auto& node : model.graph().node())
      if (node.op_type() == "Identity" && node.output(0) == value) {
        value = node.input(0);
        followed = true;
      }
    if (!followed) break;
  }
  throw std::runtime_error("test model has no float initializer behind " + value);
}

// Rewrites every int64 tensor (initializers and Constant nodes) as int32, as the AirVO ONNX files ship them.
// Returns the number of tensors rewritten.
inline int int64_constants_to_int32(onnx::ModelProto& model) {
  int rewritten = 0;
  auto rewrite = [&rewritten](onnx::TensorProto& t) {
    if (t.data_type() != onnx::TensorProto::INT64) return;
    std::vector<std::int64_t> values(t.int64_data().begin(), t.int64_data().end());
    if (!t.raw_data().empty()) {
      values.resize(t.raw_data().size() / 8);
      std::memcpy(values.data(), t.raw_data().data(), values.size() * 8);
    }
    std::vector<std::int32_t> narrow(values.begin(), values.end());
    t.clear_int64_data();
    t.set_raw_data(std::string(reinterpret_cast<const char*>(narrow.data()), narrow.size() * 4));
    t.set_data_type(onnx::TensorProto::INT32);
    ++rewritten;
  };
  for (auto& t : *model.mutable_graph()->mutable_initializer()) rewrite(t);
  for (auto& node : *model.mutable_graph()->mutable_node())
    for (auto& a : *node.mutable_attribute())
      if (a.has_t()) rewrite(*a.mutable_t());
  return rewritten;
}

// Turns every initializer into a Constant node placed at the front of the graph.
inline void initializers_to_constant_nodes(onnx::ModelProto& model) {
  auto* graph = model.mutable_graph();
  google::protobuf::RepeatedPtrField<onnx::NodeProto> nodes;
  for (const auto& t : graph->initializer()) {
    onnx::NodeProto* node = nodes.Add();
    node->set_op_type("Constant");
    node->set_name("const_" + t.name());
    node->add_output(t.name());
    auto* a = node->add_attribute();
    a->set_name("value");
    a->set_type(onnx::AttributeProto::TENSOR);
    *a->mutable_t() = t;
  }
  for (const auto& node : graph->node()) *nodes.Add() = node;
  graph->clear_initializer();
  *graph->mutable_node() = std::move(nodes);
}

// Removes the nodes none of whose outputs reach a graph output (after rewiring a graph in a test).
inline void remove_dead_nodes(onnx::ModelProto& model) {
  auto* graph = model.mutable_graph();
  std::set<std::string> live;
  for (const auto& out : graph->output()) live.insert(out.name());
  std::vector<bool> keep(static_cast<std::size_t>(graph->node_size()), false);
  for (int i = graph->node_size() - 1; i >= 0; --i) {
    const auto& node = graph->node(i);
    for (const auto& out : node.output())
      keep[static_cast<std::size_t>(i)] = keep[static_cast<std::size_t>(i)] || live.contains(out);
    if (keep[static_cast<std::size_t>(i)])
      for (const auto& in : node.input()) live.insert(in);
  }
  google::protobuf::RepeatedPtrField<onnx::NodeProto> kept;
  for (int i = 0; i < graph->node_size(); ++i)
    if (keep[static_cast<std::size_t>(i)]) *kept.Add() = graph->node(i);
  *graph->mutable_node() = std::move(kept);
}

// Converts an in-memory model and reads the pack back through the verifying reader.
inline io::ModelPack convert_model(const onnx::ModelProto& model, io::NetworkKind kind, const std::string& source) {
  const OnnxGraph graph(model, source);
  const auto bytes = convert_graph(graph).serialize();
  return io::ModelPack::parse(bytes, kind, source);
}

inline std::vector<std::byte> convert_bytes(const onnx::ModelProto& model, const std::string& source) {
  const OnnxGraph graph(model, source);
  return convert_graph(graph).serialize();
}

// fp16 copy of fp32 values, rounded as the pack writes them (rt::float_to_half, checked in runtime/half_test).
inline std::vector<float> as_half(const std::vector<float>& values) {
  std::vector<float> out;
  for (const float v : values) out.push_back(rt::half_to_float(rt::float_to_half(v)));
  return out;
}

}  // namespace vkvo::convert::test
