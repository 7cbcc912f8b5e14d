#include "features/superglue/weights.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "runtime/tensor_layout.hpp"

namespace vkvo::features {
namespace {

// A linear layer y = W x + b as the pack holds it, W row-major [out][in].
struct Linear {
  int out = 0, in = 0;
  std::vector<float> weight, bias;
};

Linear read_linear(const io::ModelPack& pack, const std::string& name, int out, int in) {
  const auto& w = pack.tensor(name + ".weight", io::DType::fp32);
  if (w.shape.size() != 2 || w.layout != "oi")
    throw std::runtime_error(
        fmt::format("model pack '{}': tensor '{}.weight' must be a 2-D 'oi' linear weight", pack.source(), name));
  Linear l{int(w.shape[0]), int(w.shape[1]), pack.floats(name + ".weight", io::DType::fp32),
           pack.floats(name + ".bias", io::DType::fp32)};
  if (l.bias.size() < std::size_t(l.out))
    throw std::runtime_error(fmt::format("model pack '{}': '{}.bias' has {} values, expected {}", pack.source(), name,
                                         l.bias.size(), l.out));
  l.bias.resize(std::size_t(l.out));
  if (l.out != out || l.in != in)
    throw std::runtime_error(fmt::format("model pack '{}': '{}' maps {} -> {}, expected {} -> {}", pack.source(), name,
                                         l.in, l.out, in, out));
  return l;
}

// The encoder's first layer with a zero fourth input column.
Linear padded_to_four_inputs(const Linear& l) {
  Linear padded{l.out, 4, std::vector<float>(std::size_t(l.out) * 4, 0.0f), l.bias};
  for (int o = 0; o < l.out; ++o)
    for (int c = 0; c < l.in; ++c) padded.weight[std::size_t(o) * 4 + c] = l.weight[std::size_t(o) * l.in + c];
  return padded;
}

// q, k, v stacked, output channels regrouped head-major.
Linear stacked_qkv(const Linear (&projections)[3], int heads) {
  const int dim = projections[0].out, head_dim = dim / heads;
  Linear qkv{3 * dim, dim, std::vector<float>(std::size_t(3) * dim * dim), std::vector<float>(std::size_t(3) * dim)};
  for (int p = 0; p < 3; ++p)
    for (int c = 0; c < dim; ++c) {
      const int source = head_major_source(c, heads, head_dim);
      std::copy_n(&projections[p].weight[std::size_t(source) * dim], dim,
                  &qkv.weight[(std::size_t(p) * dim + c) * dim]);
      qkv.bias[std::size_t(p) * dim + c] = projections[p].bias[std::size_t(source)];
    }
  return qkv;
}

// mlp0 on concat(x, merge(m)) == [W0x | W0m Wmerge] concat(x, m) + (b0 + W0m bmerge), m's channels head-major.
Linear merge_folded_into(const Linear& mlp0, const Linear& merge, int heads) {
  const int dim = merge.out, head_dim = dim / heads;
  Linear folded{2 * dim, 2 * dim, std::vector<float>(std::size_t(4) * dim * dim), mlp0.bias};
  std::vector<double> row(static_cast<std::size_t>(dim));
  for (int o = 0; o < 2 * dim; ++o) {
    const float* w0 = &mlp0.weight[std::size_t(o) * 2 * dim];
    float* out = &folded.weight[std::size_t(o) * 2 * dim];
    std::copy_n(w0, dim, out);
    std::fill(row.begin(), row.end(), 0.0);
    double bias = mlp0.bias[std::size_t(o)];
    for (int r = 0; r < dim; ++r) {
      const double w = w0[dim + r];
      const float* wm = &merge.weight[std::size_t(r) * dim];
      for (int c = 0; c < dim; ++c) row[std::size_t(c)] += w * wm[c];
      bias += w * merge.bias[std::size_t(r)];
    }
    for (int c = 0; c < dim; ++c) out[dim + c] = float(row[std::size_t(head_major_source(c, heads, head_dim))]);
    folded.bias[std::size_t(o)] = float(bias);
  }
  return folded;
}

}  // namespace

int head_major_source(int channel, int heads, int head_dim) {
  const int h = channel / head_dim, d = channel % head_dim;
  return d * heads + h;
}

SuperGlueWeights prepare_superglue_weights(const io::ModelPack& pack, const SuperGlueConfig& config) {
  const int dim = config.descriptor_dim, heads = config.heads;
  SuperGlueWeights prepared;
  auto add = [&prepared](const Linear& l) {
    auto& weights = prepared.weights;
    auto& biases = prepared.biases;
    const PreparedLinear layer{std::uint32_t(l.out), std::uint32_t(l.in), std::uint32_t(weights.size()),
                               biases.size() * sizeof(float)};
    weights.insert(weights.end(), l.weight.begin(), l.weight.end());
    weights.resize(rt::round_up(weights.size(), 4));
    biases.insert(biases.end(), l.bias.begin(), l.bias.end());
    biases.resize(rt::round_up(biases.size(), SuperGlueWeights::kBiasAlignment / sizeof(float)));
    return layer;
  };

  // Keypoint encoder [x, y, score] -> widths... -> dim.
  int in = 3;
  const std::size_t encoder_layers = config.encoder_widths.size() + 1;
  for (std::size_t i = 0; i < encoder_layers; ++i) {
    const int out = i < config.encoder_widths.size() ? config.encoder_widths[i] : dim;
    const Linear l = read_linear(pack, fmt::format("kenc.{}", i), out, in);
    prepared.encoder.push_back(add(i == 0 ? padded_to_four_inputs(l) : l));
    in = out;
  }

  for (std::size_t layer = 0; layer < config.cross_layers.size(); ++layer) {
    auto part = [&](const char* what, int out, int in_dim) {
      return read_linear(pack, fmt::format("gnn.{}.{}", layer, what), out, in_dim);
    };
    const Linear projections[3] = {part("q", dim, dim), part("k", dim, dim), part("v", dim, dim)};
    const Linear merge = part("merge", dim, dim);
    const Linear folded = merge_folded_into(part("mlp0", 2 * dim, 2 * dim), merge, heads);
    // Braced: the layers are added (and so laid out) in this order.
    prepared.gnn.push_back({config.cross_layers[layer], add(stacked_qkv(projections, heads)), add(folded),
                            add(part("mlp1", dim, 2 * dim))});
  }
  prepared.final_proj = add(read_linear(pack, "final_proj", dim, dim));
  return prepared;
}

}  // namespace vkvo::features
