#include "tools/convert/convert.hpp"

#include <fmt/format.h>

#include "tools/convert/superglue_converter.hpp"
#include "tools/convert/superpoint_converter.hpp"

namespace vkvo::convert {

io::NetworkKind detect_network(const OnnxGraph& graph) {
  std::size_t conv2d = 0, conv1d = 0;
  for (const onnx::NodeProto* conv : graph.nodes_of_type("Conv")) {
    const auto dims = conv->input_size() > 1 ? graph.constant_dims(conv->input(1)) : std::nullopt;
    if (!dims) graph.fail(*conv, "convolution weight is not a constant");
    (dims->size() == 4 ? conv2d : conv1d) += 1;
  }
  if (conv2d > 0 && conv1d == 0) return io::NetworkKind::superpoint;
  if (conv1d > 0 && conv2d == 0) return io::NetworkKind::superglue;
  graph.fail(
      fmt::format("cannot tell the network: {} 2-D and {} 1-D convolutions (SuperPoint has only 2-D, "
                  "SuperGlue only 1-D ones)",
                  conv2d, conv1d));
}

io::ModelPackWriter convert_graph(const OnnxGraph& graph, std::optional<io::NetworkKind> kind) {
  switch (kind.value_or(detect_network(graph))) {
    case io::NetworkKind::superpoint: return convert_superpoint(graph);
    case io::NetworkKind::superglue: return convert_superglue(graph);
  }
  graph.fail("unknown network kind");
}

ConvertSummary convert_file(const std::filesystem::path& onnx, const std::filesystem::path& out,
                            std::optional<io::NetworkKind> kind) {
  const OnnxGraph graph = OnnxGraph::load(onnx);
  const io::ModelPackWriter pack = convert_graph(graph, kind);
  pack.write(out);
  const io::ModelPack check = io::ModelPack::load(out, pack.kind());  // verifies what was written
  return {check.kind(), check.tensors().size(), std::filesystem::file_size(out)};
}

}  // namespace vkvo::convert
