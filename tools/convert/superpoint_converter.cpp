#include "tools/convert/superpoint_converter.hpp"

#include <array>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "features/superpoint/architecture.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::convert {

namespace {

using features::kSuperPointArchitecture;
using features::kSuperPointEncoderLayers;
using features::SuperPointConvSpec;
using features::SuperPointLayer;

struct NamedConv {
  std::string name;
  ConvWeights conv;
};

void check_shape(const OnnxGraph& graph, const ConvWeights& conv, SuperPointLayer layer) {
  const SuperPointConvSpec& expected = kSuperPointArchitecture[layer];
  const std::vector<std::int64_t> want{expected.out, expected.in, expected.kernel, expected.kernel};
  if (conv.dims != want)
    graph.fail(*conv.node, fmt::format("as SuperPoint's {} its weight should be {}, found {}", expected.name,
                                       fmt::join(want, "x"), fmt::join(conv.dims, "x")));
}

// The single consumer of `value` when it has exactly one, else nullptr.
const onnx::NodeProto* only_consumer(const OnnxGraph& graph, const std::string& value) {
  const auto& users = graph.consumers(value);
  return users.size() == 1 ? users.front() : nullptr;
}

// Encoder: Conv/Relu/MaxPool chain from the image input up to the value both heads read.
std::vector<NamedConv> map_encoder(const OnnxGraph& graph, std::string& trunk) {
  const auto inputs = graph.runtime_inputs();
  if (inputs.size() != 1)
    graph.fail(fmt::format("SuperPoint takes one image input, this graph has {} ({})", inputs.size(),
                           fmt::join(inputs, ", ")));
  std::string value = inputs.front();
  std::vector<NamedConv> convs;
  std::vector<std::size_t> pools_after;
  const onnx::NodeProto* last = nullptr;
  bool relu_pending = false;  // a conv whose ReLU has not been seen yet
  while (const onnx::NodeProto* node = only_consumer(graph, value)) {
    const std::string& op = node->op_type();
    if (op == "Conv") {
      if (relu_pending) graph.fail(*node, "convolution follows a convolution without ReLU");
      if (convs.size() == kSuperPointEncoderLayers) break;  // a head starts here (the other one is missing)
      const auto layer = static_cast<SuperPointLayer>(convs.size());
      convs.push_back({kSuperPointArchitecture[layer].name, read_conv(graph, *node)});
      check_shape(graph, convs.back().conv, layer);
      relu_pending = true;
    } else if (op == "Relu") {
      relu_pending = false;
    } else if (op == "MaxPool") {
      const std::vector<std::int64_t> two{2, 2};
      if (graph.ints_attribute(*node, "kernel_shape") != two || graph.ints_attribute(*node, "strides") != two)
        graph.fail(*node, "expected a 2x2 max-pool with stride 2");
      pools_after.push_back(convs.size() - 1);
    } else {
      break;
    }
    last = node;
    value = node->output(0);
  }
  if (convs.size() != kSuperPointEncoderLayers || relu_pending) {
    const std::string where = last ? OnnxGraph::describe(*last) : "the input '" + inputs.front() + "'";
    graph.fail(
        fmt::format("SuperPoint encoder: found {} Conv+ReLU stages before the heads, expected {} (the "
                    "Conv/Relu/MaxPool chain ends after {})",
                    convs.size() - (relu_pending ? 1 : 0), kSuperPointEncoderLayers, where));
  }
  if (pools_after !=
      std::vector<std::size_t>(features::kSuperPointPoolAfter.begin(), features::kSuperPointPoolAfter.end()))
    graph.fail(*last, fmt::format("SuperPoint encoder: max-pools follow convolutions [{}], expected after conv1b, "
                                  "conv2b and conv3b",
                                  fmt::join(pools_after, ", ")));
  trunk = value;
  return convs;
}

// Checks the Slice that drops the dustbin channel after the detector's softmax, when the export has one.
void check_dustbin_slice(const OnnxGraph& graph, const onnx::NodeProto& softmax) {
  const onnx::NodeProto* slice = only_consumer(graph, softmax.output(0));
  if (!slice || slice->op_type() != "Slice") return;
  if (slice->input_size() < 4) graph.fail(*slice, "Slice without explicit axes");
  const auto starts = graph.constant_integers(slice->input(1));
  const auto ends = graph.constant_integers(slice->input(2));
  const auto axes = graph.constant_integers(slice->input(3));
  if (!starts || !ends || !axes) graph.fail(*slice, "cannot read the Slice bounds as integer constants");
  if (*axes != std::vector<std::int64_t>{1} || *starts != std::vector<std::int64_t>{0} ||
      (*ends != std::vector<std::int64_t>{-1} && *ends != std::vector<std::int64_t>{64}))
    graph.fail(*slice, fmt::format("expected the slice [0, 64) of channel axis 1 (drop the dustbin), found "
                                   "starts {} ends {} axes {}",
                                   fmt::join(*starts, ","), fmt::join(*ends, ","), fmt::join(*axes, ",")));
}

// Checks the channel-wise L2 norm after the descriptor head (ReduceL2 over axis 1 or LpNormalization p=2 axis 1).
void check_l2_norm(const OnnxGraph& graph, const onnx::NodeProto& norm) {
  std::optional<std::vector<std::int64_t>> axes;
  if (norm.op_type() == "ReduceL2") {
    axes = graph.ints_attribute(norm, "axes");  // opset < 18
    if (!axes && norm.input_size() > 1) axes = graph.constant_integers(norm.input(1));
  } else {
    if (graph.int_attribute(norm, "p").value_or(2) != 2) graph.fail(norm, "expected an L2 normalisation");
    axes = std::vector<std::int64_t>{graph.int_attribute(norm, "axis").value_or(-1)};
  }
  if (!axes || *axes != std::vector<std::int64_t>{1})
    graph.fail(norm, "the descriptor normalisation must reduce over the channel axis 1");
}

// One head: Conv -> Relu -> Conv, then the op that identifies it (Softmax: detector; L2 norm: descriptor).
enum class Head { detector, descriptor };
std::pair<Head, std::array<ConvWeights, 2>> map_head(const OnnxGraph& graph, const onnx::NodeProto& first) {
  ConvWeights a = read_conv(graph, first);
  const onnx::NodeProto* relu = only_consumer(graph, first.output(0));
  if (!relu || relu->op_type() != "Relu") graph.fail(first, "head convolution not followed by a single ReLU");
  const onnx::NodeProto* second = only_consumer(graph, relu->output(0));
  if (!second || second->op_type() != "Conv") graph.fail(*relu, "ReLU of a head not followed by a single Conv");
  ConvWeights b = read_conv(graph, *second);
  for (const onnx::NodeProto* user : graph.consumers(second->output(0))) {
    if (user->op_type() == "Softmax") {
      if (graph.int_attribute(*user, "axis") != 1) graph.fail(*user, "detector softmax must run over axis 1");
      check_dustbin_slice(graph, *user);
      check_shape(graph, a, features::convPa);
      check_shape(graph, b, features::convPb);
      return {Head::detector, {std::move(a), std::move(b)}};
    }
    if (user->op_type() == "ReduceL2" || user->op_type() == "LpNormalization") {
      check_l2_norm(graph, *user);
      check_shape(graph, a, features::convDa);
      check_shape(graph, b, features::convDb);
      return {Head::descriptor, {std::move(a), std::move(b)}};
    }
  }
  graph.fail(*second, "head output feeds neither a Softmax (detector) nor an L2 normalisation (descriptor)");
}

void add_conv(io::ModelPackWriter& pack, const std::string& name, const ConvWeights& conv) {
  const auto o = static_cast<std::size_t>(conv.dims[0]), i = static_cast<std::size_t>(conv.dims[1]);
  const auto kh = static_cast<std::size_t>(conv.dims[2]), kw = static_cast<std::size_t>(conv.dims[3]);
  pack.add_tensor(name + ".weight", conv.dims, "o4", rt::pack_conv_o4(conv.weight, o, i, kh, kw));
  pack.add_tensor(name + ".bias", {conv.dims[0]}, "o4", rt::pad_bias_o4(conv.bias));
}

}  // namespace

io::ModelPackWriter convert_superpoint(const OnnxGraph& graph) {
  std::string trunk;
  const std::vector<NamedConv> encoder = map_encoder(graph, trunk);

  const auto& branches = graph.consumers(trunk);
  std::optional<std::array<ConvWeights, 2>> detector, descriptor;
  for (const onnx::NodeProto* branch : branches) {
    if (branch->op_type() != "Conv") graph.fail(*branch, "the encoder output may only feed the two head convolutions");
    auto [kind, convs] = map_head(graph, *branch);
    auto& slot = kind == Head::detector ? detector : descriptor;
    if (slot) graph.fail(*branch, "a second head of the same kind");
    slot = std::move(convs);
  }
  if (!detector || !descriptor)
    graph.fail(
        fmt::format("SuperPoint needs a detector head (Conv-Relu-Conv-Softmax) and a descriptor head "
                    "(Conv-Relu-Conv-L2 norm) reading the encoder output '{}'; found {} detector and {} "
                    "descriptor head",
                    trunk, detector ? 1 : 0, descriptor ? 1 : 0));

  io::ModelPackWriter pack(io::NetworkKind::superpoint);
  for (const auto& [name, conv] : encoder) add_conv(pack, name, conv);
  for (std::size_t k = 0; k < 2; ++k) {
    add_conv(pack, kSuperPointArchitecture[features::convPa + k].name, (*detector)[k]);
    add_conv(pack, kSuperPointArchitecture[features::convDa + k].name, (*descriptor)[k]);
  }
  pack.set_number("descriptor_dim", static_cast<double>((*descriptor)[1].out_channels()));
  pack.set_number("detector_channels", static_cast<double>((*detector)[1].out_channels()));
  pack.set_number("cell", 8);  // three 2x2 pools, checked above
  pack.set_numbers("encoder_widths", {64, 64, 128, 128});
  pack.set_string("source", std::filesystem::path(graph.source()).filename().string());
  return pack;
}

}  // namespace vkvo::convert
