// SuperGlue's host-side weight preparation (features/superglue/weights.hpp) against the pack's unfused layers in
// double precision (superglue_reference.hpp): the stacked head-major q, k, v projections, the merge projection
// folded into the first message-MLP layer, the padded encoder input and the layout of the prepared arrays. The
// network tests cover the same preparation end to end; these name the step that breaks.
#include <random>

#include <gtest/gtest.h>

#include "features/superglue/weights.hpp"
#include "superglue_reference.hpp"

namespace vkvo::features {
namespace {

using test::MatrixD;

// Rows of random inputs, one point per row.
MatrixD random_rows(Eigen::Index rows, Eigen::Index cols, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> dist;
  MatrixD x(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (Eigen::Index c = 0; c < cols; ++c) x(r, c) = dist(rng);
  return x;
}

// The prepared layer as a double-precision linear layer.
test::ReferenceLinear as_reference(const SuperGlueWeights& prepared, const PreparedLinear& layer) {
  test::ReferenceLinear l{MatrixD(layer.out, layer.in), Eigen::VectorXd(layer.out)};
  for (std::uint32_t o = 0; o < layer.out; ++o) {
    for (std::uint32_t i = 0; i < layer.in; ++i)
      l.w(o, i) = prepared.weights[layer.weight_offset + std::size_t(o) * layer.in + i];
    l.b(o) = prepared.biases[layer.bias_offset / sizeof(float) + o];
  }
  return l;
}

// Columns of `x` (official dim-major channels) in head-major order.
MatrixD head_major(const MatrixD& x, int heads) {
  const int dim = int(x.cols()), head_dim = dim / heads;
  MatrixD y(x.rows(), dim);
  for (int c = 0; c < dim; ++c) y.col(c) = x.col(head_major_source(c, heads, head_dim));
  return y;
}

class SuperGlueWeightsTest : public ::testing::Test {
 protected:
  test::RandomSuperGlueSpec spec;  // dim 32, 4 heads, encoder 8-16, self/cross/self
  io::ModelPack pack = test::random_superglue_pack(spec);
  SuperGlueWeights prepared = prepare_superglue_weights(pack, read_superglue_config(pack));
  // fp32 weights folded in double precision, compared in double: within a few fp32 roundings of the products.
  static constexpr double kTolerance = 1e-5;
};

TEST_F(SuperGlueWeightsTest, HeadMajorSourceInvertsTheOfficialSplit) {
  // head h, dimension d sits at channel d * heads + h officially and at h * head_dim + d head-major.
  EXPECT_EQ(head_major_source(0, 4, 8), 0);
  EXPECT_EQ(head_major_source(1, 4, 8), 4);    // head 0, d = 1
  EXPECT_EQ(head_major_source(8, 4, 8), 1);    // head 1, d = 0
  EXPECT_EQ(head_major_source(31, 4, 8), 31);  // head 3, d = 7
  std::vector<bool> seen(32, false);
  for (int c = 0; c < 32; ++c) seen[std::size_t(head_major_source(c, 4, 8))] = true;
  EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 32) << "not a permutation";
}

TEST_F(SuperGlueWeightsTest, StackedProjectionsAreQKeyValueInHeadMajorOrder) {
  ASSERT_EQ(prepared.gnn.size(), spec.cross.size());
  const MatrixD x = random_rows(5, spec.dim, 11);
  for (std::size_t layer = 0; layer < spec.cross.size(); ++layer) {
    EXPECT_EQ(prepared.gnn[layer].cross, bool(spec.cross[layer]));
    const MatrixD stacked = as_reference(prepared, prepared.gnn[layer].qkv).apply(x);
    ASSERT_EQ(stacked.cols(), 3 * spec.dim);
    const char* names[3] = {"q", "k", "v"};
    for (int p = 0; p < 3; ++p) {
      const MatrixD expected =
          head_major(test::reference_linear(pack, fmt::format("gnn.{}.{}", layer, names[p])).apply(x), spec.heads);
      EXPECT_LE((stacked.middleCols(p * spec.dim, spec.dim) - expected).cwiseAbs().maxCoeff(), kTolerance)
          << "layer " << layer << ", " << names[p];
    }
  }
}

TEST_F(SuperGlueWeightsTest, FoldedMlp0IsMergeThenMlp0) {
  // The attention's message arrives head-major; the official network merges the dim-major one.
  const MatrixD x = random_rows(6, spec.dim, 12), message = random_rows(6, spec.dim, 13);
  for (std::size_t layer = 0; layer < spec.cross.size(); ++layer) {
    const auto merge = test::reference_linear(pack, fmt::format("gnn.{}.merge", layer));
    const auto mlp0 = test::reference_linear(pack, fmt::format("gnn.{}.mlp0", layer));
    MatrixD official(x.rows(), 2 * spec.dim), folded_input(x.rows(), 2 * spec.dim);
    official << x, merge.apply(message);
    folded_input << x, head_major(message, spec.heads);
    const MatrixD expected = mlp0.apply(official);
    const MatrixD got = as_reference(prepared, prepared.gnn[layer].mlp0).apply(folded_input);
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), kTolerance * expected.cwiseAbs().maxCoeff()) << "layer " << layer;
  }
}

TEST_F(SuperGlueWeightsTest, EncoderTakesFourInputsAndLayersAreAligned) {
  ASSERT_EQ(prepared.encoder.size(), spec.encoder_widths.size() + 1);
  EXPECT_EQ(prepared.encoder[0].in, 4u);
  EXPECT_EQ(prepared.encoder.back().out, std::uint32_t(spec.dim));
  // [x, y, score, anything]: the fourth input column is zero.
  MatrixD keypoints = random_rows(4, 4, 14);
  const MatrixD got = as_reference(prepared, prepared.encoder[0]).apply(keypoints);
  const MatrixD expected = test::reference_linear(pack, "kenc.0").apply(keypoints.leftCols(3));
  EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), kTolerance);

  std::vector<PreparedLinear> all(prepared.encoder.begin(), prepared.encoder.end());
  for (const auto& layer : prepared.gnn) all.insert(all.end(), {layer.qkv, layer.mlp0, layer.mlp1});
  all.push_back(prepared.final_proj);
  for (const PreparedLinear& l : all) {
    EXPECT_EQ(l.weight_offset % 4, 0u);
    EXPECT_EQ(l.bias_offset % SuperGlueWeights::kBiasAlignment, 0u);
    EXPECT_LE(l.weight_offset + std::size_t(l.out) * l.in, prepared.weights.size());
    EXPECT_LE(l.bias_offset / sizeof(float) + l.out, prepared.biases.size());
  }
}

TEST_F(SuperGlueWeightsTest, AWrongShapeNamesThePackAndTheTensor) {
  SuperGlueConfig wider = read_superglue_config(pack);
  wider.descriptor_dim = 64;  // the pack's layers are 32 wide
  try {
    prepare_superglue_weights(pack, wider);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("random superglue pack"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("kenc.2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vkvo::features
