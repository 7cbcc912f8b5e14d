#pragma once
// Plain C++ (double precision) SuperGlue written from the official PyTorch code's semantics, straight from the
// pack's unfused weights: dim-major head split (channel c = d * heads + h), separate merge projection, concat
// MLP, log-space Sinkhorn with dustbins, mutual-max extraction. Also a writer of packs with random weights.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Core>

#include "features/point_features.hpp"
#include "features/superglue.hpp"
#include "io/model_pack.hpp"

namespace vkvo::test {

using MatrixD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct ReferenceLinear {
  MatrixD w;  // out x in
  Eigen::VectorXd b;
  MatrixD apply(const MatrixD& x) const {  // x: points x in -> points x out
    MatrixD y = x * w.transpose();
    y.rowwise() += b.transpose();
    return y;
  }
};

inline ReferenceLinear reference_linear(const io::ModelPack& pack, const std::string& name) {
  const auto& t = pack.tensor(name + ".weight", io::DType::fp32);
  const auto w = pack.floats(name + ".weight", io::DType::fp32);
  const auto b = pack.floats(name + ".bias", io::DType::fp32);
  ReferenceLinear l{MatrixD(t.shape[0], t.shape[1]), Eigen::VectorXd(t.shape[0])};
  for (Eigen::Index o = 0; o < l.w.rows(); ++o) {
    for (Eigen::Index i = 0; i < l.w.cols(); ++i) l.w(o, i) = w[std::size_t(o * l.w.cols() + i)];
    l.b(o) = b[std::size_t(o)];
  }
  return l;
}

inline MatrixD relu(MatrixD x) { return x.cwiseMax(0.0); }

// Multi-head attention, official layout: head h uses channels d * heads + h.
inline MatrixD reference_attention(const MatrixD& q, const MatrixD& k, const MatrixD& v, int heads) {
  const Eigen::Index dim = q.cols(), head_dim = dim / heads;
  MatrixD out = MatrixD::Zero(q.rows(), dim);
  for (int h = 0; h < heads; ++h) {
    MatrixD qh(q.rows(), head_dim), kh(k.rows(), head_dim), vh(v.rows(), head_dim);
    for (Eigen::Index d = 0; d < head_dim; ++d) {
      qh.col(d) = q.col(d * heads + h);
      kh.col(d) = k.col(d * heads + h);
      vh.col(d) = v.col(d * heads + h);
    }
    MatrixD s = qh * kh.transpose() / std::sqrt(double(head_dim));
    for (Eigen::Index n = 0; n < s.rows(); ++n) {
      const double peak = s.row(n).maxCoeff();
      s.row(n) = (s.row(n).array() - peak).exp();
      s.row(n) /= s.row(n).sum();
    }
    const MatrixD o = s * vh;
    for (Eigen::Index d = 0; d < head_dim; ++d) out.col(d * heads + h) = o.col(d);
  }
  return out;
}

// Log-space Sinkhorn on the couplings with dustbins, returning Z + u + v - norm (SuperGlue's log_optimal_transport).
inline MatrixD reference_optimal_transport(const MatrixD& scores, double bin_score, int iterations) {
  const Eigen::Index m = scores.rows(), n = scores.cols();
  MatrixD z(m + 1, n + 1);
  z.setConstant(bin_score);
  z.topLeftCorner(m, n) = scores;
  const double norm = -std::log(double(m + n));
  Eigen::VectorXd log_mu = Eigen::VectorXd::Constant(m + 1, norm), log_nu = Eigen::VectorXd::Constant(n + 1, norm);
  log_mu(m) = std::log(double(n)) + norm;
  log_nu(n) = std::log(double(m)) + norm;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(m + 1), v = Eigen::VectorXd::Zero(n + 1);
  auto lse = [](const Eigen::ArrayXd& x) {
    const double p = x.maxCoeff();
    return p + std::log((x - p).exp().sum());
  };
  for (int it = 0; it < iterations; ++it) {
    for (Eigen::Index i = 0; i <= m; ++i) u(i) = log_mu(i) - lse(z.row(i).transpose().array() + v.array());
    for (Eigen::Index j = 0; j <= n; ++j) v(j) = log_nu(j) - lse(z.col(j).array() + u.array());
  }
  MatrixD out = z;
  out.colwise() += u;
  out.rowwise() += v.transpose();
  return out.array() - norm;
}

// Mutual max over the inner block, score exp(max) for mutual pairs, match kept above the threshold.
inline features::PointMatches reference_extract(const MatrixD& la, double threshold) {
  const Eigen::Index m = la.rows() - 1, n = la.cols() - 1;
  features::PointMatches out;
  out.matches0.assign(std::size_t(m), -1);
  out.scores0.assign(std::size_t(m), 0.0f);
  std::vector<Eigen::Index> best1(static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) la.col(j).head(m).maxCoeff(&best1[std::size_t(j)]);
  for (Eigen::Index i = 0; i < m; ++i) {
    Eigen::Index j = 0;
    const double value = la.row(i).head(n).maxCoeff(&j);
    if (best1[std::size_t(j)] != i) continue;
    const double score = std::exp(value);
    out.scores0[std::size_t(i)] = float(score);
    if (score > threshold) out.matches0[std::size_t(i)] = int(j);
  }
  return out;
}

struct ReferenceResult {
  MatrixD log_assignment;
  features::PointMatches matches;
};

inline ReferenceResult reference_superglue(const io::ModelPack& pack, const features::PointFeatures& a,
                                           const features::PointFeatures& b, double threshold, int iterations) {
  const auto cfg = features::read_superglue_config(pack);
  const int dim = cfg.descriptor_dim;
  auto encode = [&](const features::PointFeatures& f) {
    MatrixD in(Eigen::Index(f.size()), 3);
    const double w = f.image_width, h = f.image_height, scale = 0.7 * std::max(w, h);
    for (std::size_t i = 0; i < f.size(); ++i)
      in.row(Eigen::Index(i)) << (f.keypoints[i].x() - w / 2) / scale, (f.keypoints[i].y() - h / 2) / scale,
          f.scores[i];
    MatrixD x = in;
    const std::size_t layers = cfg.encoder_widths.size() + 1;
    for (std::size_t l = 0; l < layers; ++l) {
      x = reference_linear(pack, fmt::format("kenc.{}", l)).apply(x);
      if (l + 1 < layers) x = relu(x);
    }
    return MatrixD(x + f.descriptors.cast<double>());
  };
  MatrixD x0 = encode(a), x1 = encode(b);
  for (std::size_t l = 0; l < cfg.cross_layers.size(); ++l) {
    auto lin = [&](const char* part) { return reference_linear(pack, fmt::format("gnn.{}.{}", l, part)); };
    const auto q = lin("q"), k = lin("k"), v = lin("v"), merge = lin("merge"), mlp0 = lin("mlp0"), mlp1 = lin("mlp1");
    auto propagate = [&](const MatrixD& x, const MatrixD& src) {
      const MatrixD message = merge.apply(reference_attention(q.apply(x), k.apply(src), v.apply(src), cfg.heads));
      MatrixD cat(x.rows(), 2 * dim);
      cat << x, message;
      return MatrixD(mlp1.apply(relu(mlp0.apply(cat))));
    };
    const bool cross = cfg.cross_layers[l];
    const MatrixD d0 = propagate(x0, cross ? x1 : x0), d1 = propagate(x1, cross ? x0 : x1);
    x0 += d0;
    x1 += d1;
  }
  const auto fp = reference_linear(pack, "final_proj");
  const MatrixD scores = fp.apply(x0) * fp.apply(x1).transpose() / std::sqrt(double(dim));
  ReferenceResult r;
  r.log_assignment = reference_optimal_transport(scores, cfg.bin_score, iterations);
  r.matches = reference_extract(r.log_assignment, threshold);
  return r;
}

// A SuperGlue pack with seeded random weights: residual branches scaled down and the final projection near
// `proj_gain` * I (as the shared synthetic model) so that matches follow descriptor similarity.
struct RandomSuperGlueSpec {
  int dim = 32, heads = 4;
  std::vector<int> encoder_widths{8, 16};
  std::vector<bool> cross{false, true, false};
  double bin_score = 1.0, proj_gain = 4.0;
  int sinkhorn_iterations = 100;
  std::uint32_t seed = 7;
};

inline io::ModelPack random_superglue_pack(const RandomSuperGlueSpec& spec) {
  std::mt19937 rng(spec.seed);
  io::ModelPackWriter w(io::NetworkKind::superglue);
  auto add = [&](const std::string& name, int out, int in, double gain, double identity = 0.0) {
    std::normal_distribution<float> dist(0.0f, float(gain / std::sqrt(double(in))));
    std::vector<float> weight(static_cast<std::size_t>(out) * in), bias(static_cast<std::size_t>(out));
    for (auto& x : weight) x = dist(rng);
    for (auto& x : bias) x = 0.1f * dist(rng);
    for (int i = 0; i < std::min(out, in); ++i) weight[std::size_t(i) * in + i] += float(identity);
    w.add_tensor(name + ".weight", {out, in}, "oi", weight);
    w.add_tensor(name + ".bias", {out}, "dense", bias);
  };
  int in = 3;
  for (std::size_t i = 0; i <= spec.encoder_widths.size(); ++i) {
    const int out = i < spec.encoder_widths.size() ? spec.encoder_widths[i] : spec.dim;
    add(fmt::format("kenc.{}", i), out, in, i < spec.encoder_widths.size() ? 1.0 : 0.3);
    in = out;
  }
  std::string types;
  for (std::size_t l = 0; l < spec.cross.size(); ++l) {
    const int d = spec.dim;
    add(fmt::format("gnn.{}.q", l), d, d, 2.0);
    add(fmt::format("gnn.{}.k", l), d, d, 2.0);
    add(fmt::format("gnn.{}.v", l), d, d, 1.0);
    add(fmt::format("gnn.{}.merge", l), d, d, 1.0);
    add(fmt::format("gnn.{}.mlp0", l), 2 * d, 2 * d, 1.0);
    add(fmt::format("gnn.{}.mlp1", l), d, 2 * d, 0.3);
    if (l) types += ',';
    types += spec.cross[l] ? "cross" : "self";
  }
  add("final_proj", spec.dim, spec.dim, 0.2, spec.proj_gain);
  w.set_number("descriptor_dim", spec.dim);
  w.set_number("gnn_layers", double(spec.cross.size()));
  w.set_number("heads", spec.heads);
  std::vector<double> widths(spec.encoder_widths.begin(), spec.encoder_widths.end());
  w.set_numbers("keypoint_encoder", widths);
  w.set_string("gnn_layer_types", types);
  w.set_number("sinkhorn_iterations", spec.sinkhorn_iterations);
  w.set_number("bin_score", spec.bin_score);
  w.set_string("attention_channel_order", "dim_major");
  w.set_string("source", "random");
  const auto bytes = w.serialize();
  return io::ModelPack::parse(bytes, io::NetworkKind::superglue, "random superglue pack");
}

// Random unit descriptors (features::random_point_features) at SuperPoint's VGA size unless told otherwise.
inline features::PointFeatures random_features(std::size_t n, int dim, std::mt19937& rng, int width = 640,
                                               int height = 480) {
  return features::random_point_features(n, dim, rng, width, height);
}

}  // namespace vkvo::test
