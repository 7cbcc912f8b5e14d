#include "tools/convert/superglue_converter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

namespace vkvo::convert {

namespace {

constexpr std::int64_t kDefaultSinkhornIterations = 100;  // SuperGlue's default, when the loop is not unrolled

// A Conv1d with kernel 1, i.e. a per-point linear layer.
struct Linear {
  const onnx::NodeProto* node = nullptr;
  std::vector<std::int64_t> dims;  // [O, I]
  std::vector<float> weight, bias;
};

Linear read_linear(const OnnxGraph& graph, const onnx::NodeProto& node) {
  ConvWeights conv = read_conv(graph, node);
  if (conv.dims.size() != 3 || conv.dims[2] != 1)
    graph.fail(node, fmt::format("expected a Conv1d with kernel 1, weight is {}", fmt::join(conv.dims, "x")));
  return {&node, {conv.dims[0], conv.dims[1]}, std::move(conv.weight), std::move(conv.bias)};
}

void expect_dims(const OnnxGraph& graph, const Linear& layer, std::int64_t out, std::int64_t in, const char* what) {
  if (layer.dims != std::vector<std::int64_t>{out, in})
    graph.fail(*layer.node, fmt::format("{} should map {} -> {} channels, its weight is {}x{}", what, in, out,
                                        layer.dims[0], layer.dims[1]));
}

// SuperGlue runs one module on both keypoint sets: the second set's copy must hold the same numbers.
void expect_same(const OnnxGraph& graph, const Linear& first, const Linear& second, const std::string& what) {
  if (first.dims != second.dims || first.weight != second.weight || first.bias != second.bias)
    graph.fail(*second.node, fmt::format("{} of the second keypoint set differs from the first set's ({})", what,
                                         OnnxGraph::describe(*first.node)));
}

const onnx::NodeProto* producer_of_type(const OnnxGraph& graph, const std::string& value, std::string_view op,
                                        std::initializer_list<std::string_view> transparent = {}) {
  const onnx::NodeProto* node = graph.producer_skipping(value, transparent);
  return node && node->op_type() == op ? node : nullptr;
}

std::string without_spaces(std::string text) {
  text.erase(std::remove(text.begin(), text.end(), ' '), text.end());
  return text;
}

const onnx::NodeProto& expect_einsum(const OnnxGraph& graph, const onnx::NodeProto& user, const std::string& value,
                                     std::string_view equation, std::initializer_list<std::string_view> transparent) {
  const onnx::NodeProto* einsum = producer_of_type(graph, value, "Einsum", transparent);
  if (!einsum) graph.fail(user, fmt::format("expected its input '{}' to come from an Einsum '{}'", value, equation));
  const auto found = graph.string_attribute(*einsum, "equation");
  if (!found || without_spaces(*found) != equation)
    graph.fail(*einsum, fmt::format("expected equation '{}', found '{}'", equation, found.value_or("")));
  return *einsum;
}

// ---------------------------------------------------------------------------------------------------------------
// Keypoint encoder

struct KeypointEncoder {
  std::vector<Linear> layers;
  std::string state;  // descriptors + encoder output: the first GNN input of this keypoint set
};

KeypointEncoder map_keypoint_encoder(const OnnxGraph& graph, const onnx::NodeProto& first) {
  KeypointEncoder encoder;
  const onnx::NodeProto* node = &first;
  while (true) {
    encoder.layers.push_back(read_linear(graph, *node));
    const auto& users = graph.consumers(node->output(0));
    if (users.size() != 1) graph.fail(*node, "keypoint-encoder layer output must feed exactly one node");
    const onnx::NodeProto* next = users.front();
    if (next->op_type() == "Add") {
      encoder.state = next->output(0);
      return encoder;
    }
    if (next->op_type() != "Relu") graph.fail(*next, "expected ReLU or the descriptor Add in the keypoint encoder");
    const auto& after = graph.consumers(next->output(0));
    if (after.size() != 1 || after.front()->op_type() != "Conv")
      graph.fail(*next, "keypoint-encoder ReLU must feed exactly one Conv");
    node = after.front();
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Attentional layers

struct AttentionLayer {
  bool cross = false;
  std::int64_t heads = 0;
  Linear q, k, v, merge, mlp0, mlp1;
  std::string output;  // the updated state (residual Add)

  std::array<std::pair<const char*, const Linear*>, 6> parts() const {
    return {{{"q", &q}, {"k", &k}, {"v", &v}, {"merge", &merge}, {"mlp0", &mlp0}, {"mlp1", &mlp1}}};
  }
};

// The residual Add(state, Conv(Relu(Conv(Concat(state, message))))) that updates `state`, if any.
const onnx::NodeProto* find_residual(const OnnxGraph& graph, const std::string& state) {
  const onnx::NodeProto* found = nullptr;
  for (const onnx::NodeProto* add : graph.consumers(state)) {
    if (add->op_type() != "Add" || add->input_size() != 2) continue;
    const std::string& other = add->input(0) == state ? add->input(1) : add->input(0);
    const onnx::NodeProto* mlp1 = producer_of_type(graph, other, "Conv");
    if (!mlp1) continue;
    const onnx::NodeProto* relu = producer_of_type(graph, mlp1->input(0), "Relu");
    const onnx::NodeProto* mlp0 = relu ? producer_of_type(graph, relu->input(0), "Conv") : nullptr;
    const onnx::NodeProto* concat = mlp0 ? producer_of_type(graph, mlp0->input(0), "Concat") : nullptr;
    if (!concat || concat->input_size() != 2 || concat->input(0) != state) continue;
    if (found) graph.fail(*add, fmt::format("a second residual update of '{}'", state));
    found = add;
  }
  return found;
}

// Heads of the multi-head split: the Reshape of the query to [batch, head_dim, heads, points].
std::int64_t read_heads(const OnnxGraph& graph, const onnx::NodeProto& einsum, std::int64_t dim) {
  const onnx::NodeProto* reshape = graph.producer(einsum.input(0));
  if (!reshape || reshape->op_type() != "Reshape")
    graph.fail(einsum, "expected the query to be reshaped into heads right before the attention Einsum");
  const auto shape = graph.folded_integers(reshape->input(1));
  if (!shape || shape->size() != 4 || (*shape)[1] <= 0 || (*shape)[2] <= 0 || (*shape)[1] * (*shape)[2] != dim)
    graph.fail(*reshape, fmt::format("cannot read [batch, {} / heads, heads, points] from its shape input '{}'", dim,
                                     reshape->input(1)));
  return (*shape)[2];
}

AttentionLayer map_attention_layer(const OnnxGraph& graph, const onnx::NodeProto& residual, const std::string& state,
                                   const std::string& other_state, std::int64_t dim) {
  AttentionLayer layer;
  layer.output = residual.output(0);
  const std::string& mlp_out = residual.input(0) == state ? residual.input(1) : residual.input(0);
  const onnx::NodeProto* mlp1 = graph.producer(mlp_out);
  const onnx::NodeProto* mlp0 = graph.producer(graph.producer(mlp1->input(0))->input(0));
  const onnx::NodeProto* concat = graph.producer(mlp0->input(0));
  if (OnnxGraph::int_attribute(*concat, "axis") != 1) graph.fail(*concat, "message must be concatenated on axis 1");
  layer.mlp1 = read_linear(graph, *mlp1);
  layer.mlp0 = read_linear(graph, *mlp0);
  expect_dims(graph, layer.mlp0, 2 * dim, 2 * dim, "the first MLP layer");
  expect_dims(graph, layer.mlp1, dim, 2 * dim, "the last MLP layer");

  const onnx::NodeProto* merge = producer_of_type(graph, concat->input(1), "Conv");
  if (!merge) graph.fail(*concat, "the message must come from the attention's merge Conv");
  layer.merge = read_linear(graph, *merge);
  expect_dims(graph, layer.merge, dim, dim, "the merge layer");

  const std::initializer_list<std::string_view> kReshapes{"Reshape", "Transpose", "Identity"};
  const auto& weighted = expect_einsum(graph, *merge, merge->input(0), "bhnm,bdhm->bdhn", kReshapes);
  const onnx::NodeProto* softmax = producer_of_type(graph, weighted.input(0), "Softmax");
  if (!softmax) graph.fail(weighted, "expected attention weights from a Softmax");
  const auto& scores = expect_einsum(graph, *softmax, softmax->input(0), "bdhn,bdhm->bhnm", {"Div", "Mul"});
  layer.heads = read_heads(graph, scores, dim);

  auto projection = [&](const onnx::NodeProto& user, const std::string& value, const char* what) {
    const onnx::NodeProto* conv = producer_of_type(graph, value, "Conv", kReshapes);
    if (!conv) graph.fail(user, fmt::format("expected the {} projection (Conv) behind input '{}'", what, value));
    Linear linear = read_linear(graph, *conv);
    expect_dims(graph, linear, dim, dim, what);
    return std::make_pair(std::move(linear), conv->input(0));
  };
  auto [q, q_source] = projection(scores, scores.input(0), "query");
  auto [k, k_source] = projection(scores, scores.input(1), "key");
  auto [v, v_source] = projection(weighted, weighted.input(1), "value");
  if (q_source != state) graph.fail(*q.node, "the query projection must read the keypoint set being updated");
  if (k_source != v_source) graph.fail(*v.node, "key and value projections read different keypoint sets");
  if (k_source != state && k_source != other_state)
    graph.fail(*k.node, fmt::format("key projection reads '{}', neither keypoint set's state", k_source));
  layer.cross = k_source != state;
  layer.q = std::move(q);
  layer.k = std::move(k);
  layer.v = std::move(v);
  return layer;
}

// ---------------------------------------------------------------------------------------------------------------
// Final projection, dustbin score, Sinkhorn

const onnx::NodeProto& find_final_projection(const OnnxGraph& graph, const std::string& state) {
  for (const onnx::NodeProto* conv : graph.consumers(state)) {
    if (conv->op_type() != "Conv") continue;
    for (const onnx::NodeProto* user : graph.consumers(conv->output(0)))
      if (user->op_type() == "Einsum") return *conv;
  }
  const onnx::NodeProto* producer = graph.producer(state);
  if (producer)
    graph.fail(*producer,
               "its output is followed neither by another attentional layer nor by the "
               "final projection feeding the score Einsum");
  graph.fail(fmt::format("value '{}' is followed neither by an attentional layer nor by the final projection", state));
}

double find_bin_score(const OnnxGraph& graph, const onnx::NodeProto& score_einsum, std::int64_t dim) {
  std::string scores = score_einsum.output(0);
  const auto& users = graph.consumers(scores);
  if (users.size() == 1 && (users.front()->op_type() == "Div" || users.front()->op_type() == "Mul")) {
    const auto& scale_node = *users.front();
    const auto scale = graph.constant_floats(scale_node.input(1));
    const double expected = scale_node.op_type() == "Div" ? std::sqrt(double(dim)) : 1.0 / std::sqrt(double(dim));
    if (!scale || scale->values.size() != 1 || std::abs(scale->values[0] - expected) > 1e-4 * expected)
      graph.fail(scale_node, fmt::format("scores must be scaled by 1/sqrt({})", dim));
    scores = scale_node.output(0);
  }
  for (const onnx::NodeProto* concat : graph.consumers(scores)) {
    if (concat->op_type() != "Concat") continue;
    for (const auto& in : concat->input()) {
      const onnx::NodeProto* expand = graph.producer(in);
      if (!expand || expand->op_type() != "Expand") continue;
      const auto bin = graph.constant_floats(expand->input(0));
      if (bin && bin->values.size() == 1) return bin->values[0];
    }
  }
  graph.fail(score_einsum, "cannot find the dustbin score: expected Concat(scores, Expand(<scalar bin_score>))");
}

std::int64_t count_sinkhorn_iterations(const OnnxGraph& graph) {
  const auto reductions = graph.nodes_of_type("ReduceLogSumExp").size();
  if (reductions == 0 || reductions % 2 != 0) {
    spdlog::warn(
        "ONNX '{}': Sinkhorn iterations not unrolled as pairs of ReduceLogSumExp ({} found); recording "
        "SuperGlue's default {}",
        graph.source(), reductions, kDefaultSinkhornIterations);
    return kDefaultSinkhornIterations;
  }
  return static_cast<std::int64_t>(reductions / 2);
}

void add_linear(io::ModelPackWriter& pack, const std::string& name, const Linear& layer) {
  pack.add_tensor(name + ".weight", layer.dims, "oi", layer.weight);
  pack.add_tensor(name + ".bias", {layer.dims[0]}, "dense", layer.bias);
}

}  // namespace

io::ModelPackWriter convert_superglue(const OnnxGraph& graph) {
  // Keypoint encoders: the Conv1d chains that start from 3 channels [x, y, score], one per keypoint set.
  std::vector<const onnx::NodeProto*> starts;
  for (const onnx::NodeProto* conv : graph.nodes_of_type("Conv")) {
    const auto dims = conv->input_size() > 1 ? graph.constant_dims(conv->input(1)) : std::nullopt;
    if (dims && dims->size() == 3 && (*dims)[1] == 3) starts.push_back(conv);
  }
  if (starts.size() != 2)
    graph.fail(fmt::format("SuperGlue needs two keypoint encoders (Conv1d chains from 3 input channels), found {}",
                           starts.size()));
  std::array<KeypointEncoder, 2> encoders{map_keypoint_encoder(graph, *starts[0]),
                                          map_keypoint_encoder(graph, *starts[1])};
  const auto& kenc = encoders[0].layers;
  const std::int64_t dim = kenc.back().dims[0];
  for (std::size_t i = 0; i < kenc.size(); ++i) {
    const std::int64_t in = i == 0 ? 3 : kenc[i - 1].dims[0];
    if (kenc[i].dims[1] != in) expect_dims(graph, kenc[i], kenc[i].dims[0], in, "this keypoint-encoder layer");
  }
  if (encoders[1].layers.size() != kenc.size())
    graph.fail(*starts[1], "the two keypoint encoders have different depths");
  for (std::size_t i = 0; i < kenc.size(); ++i)
    expect_same(graph, kenc[i], encoders[1].layers[i], fmt::format("keypoint-encoder layer {}", i));

  // Attentional layers, until the states feed the final projection.
  std::array<std::string, 2> states{encoders[0].state, encoders[1].state};
  std::vector<AttentionLayer> layers;
  while (const onnx::NodeProto* residual0 = find_residual(graph, states[0])) {
    const onnx::NodeProto* residual1 = find_residual(graph, states[1]);
    if (!residual1) graph.fail(*residual0, "the second keypoint set has no matching attentional layer");
    AttentionLayer first = map_attention_layer(graph, *residual0, states[0], states[1], dim);
    const AttentionLayer second = map_attention_layer(graph, *residual1, states[1], states[0], dim);
    if (first.cross != second.cross || first.heads != second.heads)
      graph.fail(*residual1, "the keypoint sets disagree on the layer type or head count");
    for (std::size_t p = 0; p < first.parts().size(); ++p)
      expect_same(graph, *first.parts()[p].second, *second.parts()[p].second,
                  fmt::format("layer {} {}", layers.size(), first.parts()[p].first));
    if (!layers.empty() && first.heads != layers.front().heads)
      graph.fail(*residual0, "head count differs between attentional layers");
    states = {first.output, second.output};
    layers.push_back(std::move(first));
  }
  if (layers.empty())
    graph.fail(fmt::format("no attentional layer found after the keypoint encoder ('{}')", states[0]));

  const onnx::NodeProto& final0 = find_final_projection(graph, states[0]);
  const onnx::NodeProto& final1 = find_final_projection(graph, states[1]);
  const Linear final_proj = read_linear(graph, final0);
  expect_dims(graph, final_proj, dim, dim, "the final projection");
  expect_same(graph, final_proj, read_linear(graph, final1), "final projection");
  const onnx::NodeProto* score_einsum = nullptr;
  for (const onnx::NodeProto* user : graph.consumers(final0.output(0)))
    if (user->op_type() == "Einsum") score_einsum = user;
  if (without_spaces(OnnxGraph::string_attribute(*score_einsum, "equation").value_or("")) != "bdn,bdm->bnm" ||
      score_einsum->input(0) != final0.output(0) || score_einsum->input(1) != final1.output(0))
    graph.fail(*score_einsum, "expected the scores Einsum 'bdn,bdm->bnm' of the two final projections");
  const double bin_score = find_bin_score(graph, *score_einsum, dim);

  io::ModelPackWriter pack(io::NetworkKind::superglue);
  for (std::size_t i = 0; i < kenc.size(); ++i) add_linear(pack, fmt::format("kenc.{}", i), kenc[i]);
  std::vector<std::string> types;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    for (const auto& [part, linear] : layers[l].parts()) add_linear(pack, fmt::format("gnn.{}.{}", l, part), *linear);
    types.push_back(layers[l].cross ? "cross" : "self");
  }
  add_linear(pack, "final_proj", final_proj);

  std::vector<double> widths;
  for (std::size_t i = 0; i + 1 < kenc.size(); ++i) widths.push_back(static_cast<double>(kenc[i].dims[0]));
  pack.set_number("descriptor_dim", static_cast<double>(dim));
  pack.set_number("gnn_layers", static_cast<double>(layers.size()));
  pack.set_number("heads", static_cast<double>(layers.front().heads));
  pack.set_numbers("keypoint_encoder", widths);
  pack.set_string("gnn_layer_types", fmt::format("{}", fmt::join(types, ",")));
  pack.set_number("sinkhorn_iterations", static_cast<double>(count_sinkhorn_iterations(graph)));
  pack.set_number("bin_score", bin_score);
  pack.set_string("attention_channel_order", "dim_major");
  pack.set_string("source", std::filesystem::path(graph.source()).filename().string());
  return pack;
}

}  // namespace vkvo::convert
