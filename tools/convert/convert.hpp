#pragma once
// Entry point of the ONNX -> model-pack converter (`vkvo convert`): tells SuperPoint from SuperGlue by graph
// structure and runs the matching converter. See tools/convert/README.md for the tensor naming scheme.
#include <filesystem>
#include <optional>

#include "io/model_pack.hpp"
#include "tools/convert/onnx_graph.hpp"

namespace vkvo::convert {

// superpoint: every Conv is 2-D (rank-4 weights); superglue: every Conv is 1-D (rank-3 weights). Throws otherwise.
io::NetworkKind detect_network(const OnnxGraph& graph);

// Maps the graph (of `kind`, detected when not given) into a pack; throws naming the node it cannot map.
io::ModelPackWriter convert_graph(const OnnxGraph& graph, std::optional<io::NetworkKind> kind = std::nullopt);

struct ConvertSummary {
  io::NetworkKind kind;
  std::size_t tensors = 0;   // table entries (fp32 and fp16 copies counted separately)
  std::uintmax_t bytes = 0;  // pack file size
};
// Reads `onnx`, writes the pack to `out`, and reads it back to verify it.
ConvertSummary convert_file(const std::filesystem::path& onnx, const std::filesystem::path& out,
                            std::optional<io::NetworkKind> kind = std::nullopt);

}  // namespace vkvo::convert
