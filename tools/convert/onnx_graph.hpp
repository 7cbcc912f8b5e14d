#pragma once
// A read-only view of an ONNX graph for the model-pack converters: who produces and who consumes each value,
// constant tensors wherever the exporter put them (initializers, Constant nodes, behind Identity nodes), and
// errors that name the file, the node and the reason.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <onnx/onnx_pb.h>

namespace vkvo::convert {

// A constant float tensor (fp32, fp16, bf16 and fp64 are widened/narrowed to float).
struct FloatTensor {
  std::vector<std::int64_t> dims;
  std::vector<float> values;
};

// Marks an element of a shape that is computed at run time (e.g. the batch size read with Shape/Gather).
inline constexpr std::int64_t kUnknownDim = INT64_MIN;

class OnnxGraph {
 public:
  OnnxGraph(onnx::ModelProto model, std::string source);
  static OnnxGraph load(const std::filesystem::path& path);
  // The maps below point into the model: neither copied nor moved.
  OnnxGraph(const OnnxGraph&) = delete;
  OnnxGraph& operator=(const OnnxGraph&) = delete;

  const std::string& source() const { return source_; }
  const onnx::GraphProto& graph() const { return model_.graph(); }

  // Graph inputs that are not initializers, in declaration order.
  std::vector<std::string> runtime_inputs() const;
  // The node that computes `value`; nullptr for graph inputs and initializers.
  const onnx::NodeProto* producer(std::string_view value) const;
  const std::vector<const onnx::NodeProto*>& consumers(std::string_view value) const;
  // Position of a node in the (topologically sorted) node list.
  std::size_t index_of(const onnx::NodeProto& node) const;
  std::vector<const onnx::NodeProto*> nodes_of_type(std::string_view op_type) const;
  // The producer of `value`, walking up through nodes whose op is in `transparent` (along their first input).
  const onnx::NodeProto* producer_skipping(std::string_view value,
                                           std::initializer_list<std::string_view> transparent) const;

  // Constant tensors: from an initializer or a Constant node, through any chain of Identity nodes;
  // nullopt when the value is computed. Integer tensors may be int64 (the official export) or int32 (AirVO).
  std::optional<FloatTensor> constant_floats(std::string_view value) const;
  // The dims of a constant tensor without decoding its values.
  std::optional<std::vector<std::int64_t>> constant_dims(std::string_view value) const;
  std::optional<std::vector<std::int64_t>> constant_integers(std::string_view value) const;
  // A 1-D integer tensor assembled by Concat/Unsqueeze/Identity from constants; computed parts are kUnknownDim.
  std::optional<std::vector<std::int64_t>> folded_integers(std::string_view value) const;

  // "node '<name>' (<op>)", or the first output's name when the node has none.
  static std::string describe(const onnx::NodeProto& node);
  [[noreturn]] void fail(const onnx::NodeProto& node, const std::string& reason) const;
  [[noreturn]] void fail(const std::string& reason) const;

  static std::optional<std::int64_t> int_attribute(const onnx::NodeProto& node, std::string_view name);
  static std::optional<std::vector<std::int64_t>> ints_attribute(const onnx::NodeProto& node, std::string_view name);
  static std::optional<std::string> string_attribute(const onnx::NodeProto& node, std::string_view name);

 private:
  const onnx::TensorProto* constant_proto(std::string_view value) const;

  onnx::ModelProto model_;
  std::string source_;
  std::map<std::string, const onnx::TensorProto*, std::less<>> initializers_;
  std::map<std::string, const onnx::NodeProto*, std::less<>> producers_;
  std::map<std::string, std::vector<const onnx::NodeProto*>, std::less<>> consumers_;
  std::map<const onnx::NodeProto*, std::size_t> index_;
};

// The weights of one Conv node (Conv1d or Conv2d), checked to be a plain convolution: group 1, stride 1,
// dilation 1, "same" padding (k/2 on every side) and no auto_pad. Missing bias -> zeros.
struct ConvWeights {
  const onnx::NodeProto* node = nullptr;
  std::vector<std::int64_t> dims;  // [O, I, K...]
  std::vector<float> weight;
  std::vector<float> bias;  // [O]
  std::int64_t out_channels() const { return dims[0]; }
  std::int64_t in_channels() const { return dims[1]; }
};
ConvWeights read_conv(const OnnxGraph& graph, const onnx::NodeProto& node);

}  // namespace vkvo::convert
