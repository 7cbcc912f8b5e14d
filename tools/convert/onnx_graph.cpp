#include "tools/convert/onnx_graph.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/model_pack.hpp"
#include "runtime/half.hpp"

namespace vkvo::convert {

namespace {

std::size_t element_count(const onnx::TensorProto& t) {
  std::size_t count = 1;
  for (const auto d : t.dims()) count *= static_cast<std::size_t>(std::max<std::int64_t>(d, 0));
  return count;
}

// Little-endian elements of type T from raw_data.
template <typename T>
std::vector<T> raw_elements(const onnx::TensorProto& t) {
  std::vector<T> values(t.raw_data().size() / sizeof(T));
  std::memcpy(values.data(), t.raw_data().data(), values.size() * sizeof(T));
  return values;
}

float bfloat16_to_float(std::uint32_t bits) { return std::bit_cast<float>(bits << 16); }

}  // namespace

OnnxGraph::OnnxGraph(onnx::ModelProto model, std::string source)
    : model_(std::move(model)), source_(std::move(source)) {
  const auto& g = model_.graph();
  for (const auto& t : g.initializer()) initializers_[t.name()] = &t;
  for (int i = 0; i < g.node_size(); ++i) {
    const auto& node = g.node(i);
    index_[&node] = static_cast<std::size_t>(i);
    for (const auto& out : node.output())
      if (!out.empty()) producers_[out] = &node;
    for (const auto& in : node.input())
      if (!in.empty()) consumers_[in].push_back(&node);
  }
}

OnnxGraph OnnxGraph::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("ONNX '{}': cannot open the file", path.string()));
  onnx::ModelProto model;
  if (!model.ParseFromIstream(&in))
    throw std::runtime_error(fmt::format("ONNX '{}': not a valid ONNX model (protobuf parse failed)", path.string()));
  return OnnxGraph(std::move(model), path.string());
}

std::vector<std::string> OnnxGraph::runtime_inputs() const {
  std::vector<std::string> names;
  for (const auto& input : graph().input())
    if (!initializers_.contains(input.name())) names.push_back(input.name());
  return names;
}

const onnx::NodeProto* OnnxGraph::producer(std::string_view value) const {
  const auto it = producers_.find(value);
  return it == producers_.end() ? nullptr : it->second;
}

const std::vector<const onnx::NodeProto*>& OnnxGraph::consumers(std::string_view value) const {
  static const std::vector<const onnx::NodeProto*> none;
  const auto it = consumers_.find(value);
  return it == consumers_.end() ? none : it->second;
}

std::size_t OnnxGraph::index_of(const onnx::NodeProto& node) const { return index_.at(&node); }

std::vector<const onnx::NodeProto*> OnnxGraph::nodes_of_type(std::string_view op_type) const {
  std::vector<const onnx::NodeProto*> nodes;
  for (const auto& node : graph().node())
    if (node.op_type() == op_type) nodes.push_back(&node);
  return nodes;
}

const onnx::NodeProto* OnnxGraph::producer_skipping(std::string_view value,
                                                    std::initializer_list<std::string_view> transparent) const {
  const onnx::NodeProto* node = producer(value);
  while (node && node->input_size() > 0 &&
         std::find(transparent.begin(), transparent.end(), node->op_type()) != transparent.end())
    node = producer(node->input(0));
  return node;
}

const onnx::TensorProto* OnnxGraph::constant_proto(std::string_view value) const {
  for (int hops = 0; hops < 64; ++hops) {
    if (const auto it = initializers_.find(value); it != initializers_.end()) return it->second;
    const onnx::NodeProto* node = producer(value);
    if (!node) return nullptr;
    if (node->op_type() == "Identity" && node->input_size() == 1) {
      value = node->input(0);
      continue;
    }
    if (node->op_type() == "Constant") {
      for (const auto& a : node->attribute())
        if (a.name() == "value" && a.has_t()) return &a.t();
    }
    return nullptr;
  }
  return nullptr;
}

std::optional<FloatTensor> OnnxGraph::constant_floats(std::string_view value) const {
  const onnx::TensorProto* t = constant_proto(value);
  if (!t) {
    // Constant nodes may also carry a scalar or a list directly.
    const onnx::NodeProto* node = producer(value);
    if (node && node->op_type() == "Constant")
      for (const auto& a : node->attribute()) {
        if (a.name() == "value_float") return FloatTensor{{}, {a.f()}};
        if (a.name() == "value_floats")
          return FloatTensor{{a.floats_size()}, std::vector<float>(a.floats().begin(), a.floats().end())};
      }
    return std::nullopt;
  }
  if (t->data_location() == onnx::TensorProto::EXTERNAL)
    throw std::runtime_error(
        fmt::format("ONNX '{}': tensor '{}' keeps its data in an external file, which is not "
                    "supported; export with the weights embedded",
                    source_, t->name()));
  FloatTensor out;
  out.dims.assign(t->dims().begin(), t->dims().end());
  const bool raw = !t->raw_data().empty();
  switch (t->data_type()) {
    case onnx::TensorProto::FLOAT:
      out.values = raw ? raw_elements<float>(*t) : std::vector<float>(t->float_data().begin(), t->float_data().end());
      break;
    case onnx::TensorProto::DOUBLE: {
      const auto d =
          raw ? raw_elements<double>(*t) : std::vector<double>(t->double_data().begin(), t->double_data().end());
      out.values.assign(d.begin(), d.end());
      break;
    }
    case onnx::TensorProto::FLOAT16:
    case onnx::TensorProto::BFLOAT16: {
      std::vector<std::uint16_t> bits;
      if (raw) {
        bits = raw_elements<std::uint16_t>(*t);
      } else {
        for (const auto v : t->int32_data()) bits.push_back(static_cast<std::uint16_t>(v));
      }
      for (const auto b : bits)
        out.values.push_back(t->data_type() == onnx::TensorProto::FLOAT16 ? rt::half_to_float(b)
                                                                          : bfloat16_to_float(b));
      break;
    }
    default: return std::nullopt;  // not a float tensor
  }
  if (out.values.size() != element_count(*t))
    throw std::runtime_error(fmt::format("ONNX '{}': tensor '{}' holds {} values, its shape needs {}", source_,
                                         t->name(), out.values.size(), element_count(*t)));
  return out;
}

std::optional<std::vector<std::int64_t>> OnnxGraph::constant_dims(std::string_view value) const {
  const onnx::TensorProto* t = constant_proto(value);
  if (!t) return std::nullopt;
  return std::vector<std::int64_t>(t->dims().begin(), t->dims().end());
}

std::optional<std::vector<std::int64_t>> OnnxGraph::constant_integers(std::string_view value) const {
  const onnx::TensorProto* t = constant_proto(value);
  if (!t) {
    const onnx::NodeProto* node = producer(value);
    if (node && node->op_type() == "Constant")
      for (const auto& a : node->attribute()) {
        if (a.name() == "value_int") return std::vector<std::int64_t>{a.i()};
        if (a.name() == "value_ints") return std::vector<std::int64_t>(a.ints().begin(), a.ints().end());
      }
    return std::nullopt;
  }
  std::vector<std::int64_t> values;
  const bool raw = !t->raw_data().empty();
  auto widen = [&values](const auto& source) { values.assign(source.begin(), source.end()); };
  switch (t->data_type()) {
    case onnx::TensorProto::INT64: raw ? widen(raw_elements<std::int64_t>(*t)) : widen(t->int64_data()); break;
    case onnx::TensorProto::INT32: raw ? widen(raw_elements<std::int32_t>(*t)) : widen(t->int32_data()); break;
    case onnx::TensorProto::INT16: raw ? widen(raw_elements<std::int16_t>(*t)) : widen(t->int32_data()); break;
    case onnx::TensorProto::INT8: raw ? widen(raw_elements<std::int8_t>(*t)) : widen(t->int32_data()); break;
    case onnx::TensorProto::UINT8: raw ? widen(raw_elements<std::uint8_t>(*t)) : widen(t->int32_data()); break;
    default: return std::nullopt;  // not an integer tensor
  }
  if (values.size() != element_count(*t))
    throw std::runtime_error(fmt::format("ONNX '{}': tensor '{}' holds {} values, its shape needs {}", source_,
                                         t->name(), values.size(), element_count(*t)));
  return values;
}

std::optional<std::vector<std::int64_t>> OnnxGraph::folded_integers(std::string_view value) const {
  if (auto constant = constant_integers(value)) return constant;
  const onnx::NodeProto* node = producer(value);
  if (!node) return std::nullopt;
  if (node->op_type() == "Concat") {
    std::vector<std::int64_t> all;
    for (const auto& in : node->input()) {
      const auto part = folded_integers(in);
      if (!part) return std::nullopt;
      all.insert(all.end(), part->begin(), part->end());
    }
    return all;
  }
  if (node->op_type() == "Unsqueeze" || node->op_type() == "Identity" || node->op_type() == "Cast") {
    if (auto inner = constant_integers(node->input(0))) return inner;
    return std::vector<std::int64_t>{kUnknownDim};  // one element computed at run time
  }
  return std::nullopt;
}

std::string OnnxGraph::describe(const onnx::NodeProto& node) {
  if (!node.name().empty()) return fmt::format("node '{}' ({})", node.name(), node.op_type());
  return fmt::format("node producing '{}' ({})", node.output_size() ? node.output(0) : "?", node.op_type());
}

void OnnxGraph::fail(const onnx::NodeProto& node, const std::string& reason) const {
  throw std::runtime_error(fmt::format("ONNX '{}': {}: {}", source_, describe(node), reason));
}

void OnnxGraph::fail(const std::string& reason) const {
  throw std::runtime_error(fmt::format("ONNX '{}': {}", source_, reason));
}

std::optional<std::int64_t> OnnxGraph::int_attribute(const onnx::NodeProto& node, std::string_view name) {
  for (const auto& a : node.attribute())
    if (a.name() == name && a.type() == onnx::AttributeProto::INT) return a.i();
  return std::nullopt;
}

std::optional<std::vector<std::int64_t>> OnnxGraph::ints_attribute(const onnx::NodeProto& node, std::string_view name) {
  for (const auto& a : node.attribute())
    if (a.name() == name && a.type() == onnx::AttributeProto::INTS)
      return std::vector<std::int64_t>(a.ints().begin(), a.ints().end());
  return std::nullopt;
}

std::optional<std::string> OnnxGraph::string_attribute(const onnx::NodeProto& node, std::string_view name) {
  for (const auto& a : node.attribute())
    if (a.name() == name && a.type() == onnx::AttributeProto::STRING) return a.s();
  return std::nullopt;
}

ConvWeights read_conv(const OnnxGraph& graph, const onnx::NodeProto& node) {
  if (node.op_type() != "Conv") graph.fail(node, "expected a Conv node");
  if (node.input_size() < 2) graph.fail(node, "Conv without a weight input");
  auto weight = graph.constant_floats(node.input(1));
  if (!weight) graph.fail(node, fmt::format("weight '{}' is not a constant float tensor", node.input(1)));
  if (weight->dims.size() < 3)
    graph.fail(node, fmt::format("weight has rank {}, expected 3 or 4", weight->dims.size()));

  const std::size_t spatial = weight->dims.size() - 2;
  const std::vector<std::int64_t> ones(spatial, 1);
  if (graph.int_attribute(node, "group").value_or(1) != 1) graph.fail(node, "grouped convolution is not supported");
  if (graph.ints_attribute(node, "strides").value_or(ones) != ones) graph.fail(node, "stride other than 1");
  if (graph.ints_attribute(node, "dilations").value_or(ones) != ones) graph.fail(node, "dilation other than 1");
  if (const auto pad = graph.string_attribute(node, "auto_pad"); pad && *pad != "NOTSET")
    graph.fail(node, fmt::format("auto_pad '{}' is not supported", *pad));
  std::vector<std::int64_t> same_pads;
  for (int twice = 0; twice < 2; ++twice)
    for (std::size_t k = 0; k < spatial; ++k) same_pads.push_back(weight->dims[2 + k] / 2);
  const auto pads = graph.ints_attribute(node, "pads").value_or(std::vector<std::int64_t>(2 * spatial, 0));
  if (pads != same_pads) graph.fail(node, "padding is not 'same' (kernel/2 on every side)");

  ConvWeights conv;
  conv.node = &node;
  conv.dims = weight->dims;
  conv.weight = std::move(weight->values);
  const auto out_channels = static_cast<std::size_t>(conv.dims[0]);
  if (node.input_size() >= 3 && !node.input(2).empty()) {
    auto bias = graph.constant_floats(node.input(2));
    if (!bias) graph.fail(node, fmt::format("bias '{}' is not a constant float tensor", node.input(2)));
    if (bias->values.size() != out_channels)
      graph.fail(node, fmt::format("bias has {} values for {} output channels", bias->values.size(), out_channels));
    conv.bias = std::move(bias->values);
  } else {
    conv.bias.assign(out_channels, 0.0f);
  }
  return conv;
}

}  // namespace vkvo::convert
