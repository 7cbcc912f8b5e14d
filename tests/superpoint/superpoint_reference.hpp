#pragma once
// Plain C++ SuperPoint (network + post-processing), written from the PyTorch reference's definition
// (SuperGluePretrainedNetwork models/superpoint.py) for the data-free tests: double accumulation, no tiling.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "io/model_pack.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::features::reference {

struct Tensor {
  int c = 0, h = 0, w = 0;
  std::vector<float> v;  // CHW
  float& at(int ci, int y, int x) { return v[(std::size_t(ci) * h + y) * w + x]; }
  float at(int ci, int y, int x) const { return v[(std::size_t(ci) * h + y) * w + x]; }
};

// A pack tensor in the "o4" layout back to OIHW.
inline std::vector<float> unpack_o4(const io::ModelPack& pack, const std::string& name, int o, int i, int k) {
  const auto stored = pack.floats(name, io::DType::fp32);
  std::vector<float> oihw(std::size_t(o) * i * k * k);
  for (int oc = 0; oc < o; ++oc)
    for (int ic = 0; ic < i; ++ic)
      for (int t = 0; t < k * k; ++t)
        oihw[(std::size_t(oc) * i + ic) * k * k + t] =
            stored[((std::size_t(oc / 4) * i + ic) * k * k + t) * 4 + oc % 4];
  return oihw;
}

inline Tensor conv(const io::ModelPack& pack, const std::string& name, const Tensor& in, int out_c, int k, bool relu) {
  const auto w = unpack_o4(pack, name + ".weight", out_c, in.c, k);
  const auto b = pack.floats(name + ".bias", io::DType::fp32);
  Tensor out{out_c, in.h, in.w, std::vector<float>(std::size_t(out_c) * in.h * in.w)};
  const int r = k / 2;
  for (int o = 0; o < out_c; ++o)
    for (int y = 0; y < in.h; ++y)
      for (int x = 0; x < in.w; ++x) {
        double s = b[o];
        for (int i = 0; i < in.c; ++i)
          for (int ky = 0; ky < k; ++ky)
            for (int kx = 0; kx < k; ++kx) {
              const int yy = y + ky - r, xx = x + kx - r;
              if (yy >= 0 && yy < in.h && xx >= 0 && xx < in.w)
                s += double(w[((std::size_t(o) * in.c + i) * k + ky) * k + kx]) * in.at(i, yy, xx);
            }
        out.at(o, y, x) = relu ? std::max(0.0f, float(s)) : float(s);
      }
  return out;
}

inline Tensor maxpool2(const Tensor& in) {
  Tensor out{in.c, in.h / 2, in.w / 2, std::vector<float>(std::size_t(in.c) * (in.h / 2) * (in.w / 2))};
  for (int c = 0; c < out.c; ++c)
    for (int y = 0; y < out.h; ++y)
      for (int x = 0; x < out.w; ++x)
        out.at(c, y, x) = std::max({in.at(c, 2 * y, 2 * x), in.at(c, 2 * y, 2 * x + 1), in.at(c, 2 * y + 1, 2 * x),
                                    in.at(c, 2 * y + 1, 2 * x + 1)});
  return out;
}

struct Dense {
  int cells_h = 0, cells_w = 0;
  std::vector<float> scores;       // (cells_h*8) x (cells_w*8)
  std::vector<float> descriptors;  // 256 x cells_h x cells_w
};

inline Dense forward(const io::ModelPack& pack, const cv::Mat& image, int dim = 256) {
  Tensor x{1, image.rows, image.cols, std::vector<float>(std::size_t(image.rows) * image.cols)};
  for (int y = 0; y < image.rows; ++y)
    for (int c = 0; c < image.cols; ++c) x.at(0, y, c) = float(image.at<std::uint8_t>(y, c)) / 255.0f;
  const char* names[4][2] = {{"conv1a", "conv1b"}, {"conv2a", "conv2b"}, {"conv3a", "conv3b"}, {"conv4a", "conv4b"}};
  const int widths[4] = {64, 64, 128, 128};
  for (int level = 0; level < 4; ++level) {
    x = conv(pack, names[level][1], conv(pack, names[level][0], x, widths[level], 3, true), widths[level], 3, true);
    if (level < 3) x = maxpool2(x);
  }
  const Tensor logits = conv(pack, "convPb", conv(pack, "convPa", x, 256, 3, true), 65, 1, false);
  const Tensor desc = conv(pack, "convDb", conv(pack, "convDa", x, 256, 3, true), dim, 1, false);
  Dense d{x.h, x.w, std::vector<float>(std::size_t(x.h) * x.w * 64), std::vector<float>(desc.v.size())};
  for (int y = 0; y < x.h; ++y)
    for (int c = 0; c < x.w; ++c) {
      double top = -1e30, sum = 0, sq = 0;
      for (int k = 0; k < 65; ++k) top = std::max<double>(top, logits.at(k, y, c));
      for (int k = 0; k < 65; ++k) sum += std::exp(logits.at(k, y, c) - top);
      for (int k = 0; k < 64; ++k)
        d.scores[(std::size_t(y) * 8 + k / 8) * x.w * 8 + c * 8 + k % 8] =
            float(std::exp(logits.at(k, y, c) - top) / sum);
      for (int k = 0; k < dim; ++k) sq += double(desc.at(k, y, c)) * desc.at(k, y, c);
      const double inv = 1.0 / std::max(std::sqrt(sq), 1e-12);
      for (int k = 0; k < dim; ++k) d.descriptors[(std::size_t(k) * x.h + y) * x.w + c] = float(desc.at(k, y, c) * inv);
    }
  return d;
}

// (2r+1)^2 max-pool, stride 1, -inf padding, as torch.nn.functional.max_pool2d.
inline std::vector<float> max_pool(const std::vector<float>& s, int h, int w, int r) {
  std::vector<float> out(s.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float m = -std::numeric_limits<float>::infinity();
      for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx)
          m = std::max(m, s[std::size_t(yy) * w + xx]);
      out[std::size_t(y) * w + x] = m;
    }
  return out;
}

// simple_nms of the reference: two suppression rounds.
inline std::vector<float> simple_nms(const std::vector<float>& scores, int h, int w, int r) {
  const std::size_t n = scores.size();
  std::vector<float> mask(n), pooled = max_pool(scores, h, w, r);
  for (std::size_t i = 0; i < n; ++i) mask[i] = scores[i] == pooled[i];
  for (int round = 0; round < 2; ++round) {
    const auto supp_pool = max_pool(mask, h, w, r);
    std::vector<float> supp_scores(n);
    for (std::size_t i = 0; i < n; ++i) supp_scores[i] = supp_pool[i] > 0 ? 0.0f : scores[i];
    const auto ss_pool = max_pool(supp_scores, h, w, r);
    for (std::size_t i = 0; i < n; ++i)
      if (supp_scores[i] == ss_pool[i] && !(supp_pool[i] > 0)) mask[i] = 1;
  }
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = mask[i] != 0 ? scores[i] : 0.0f;
  return out;
}

struct Keypoints {
  std::vector<Eigen::Vector2f> xy;
  std::vector<float> scores;
  std::vector<std::vector<float>> descriptors;
};

// SuperPoint's descriptor at pixel (x, y) of an image of cells_h x cells_w cells: grid_sample(align_corners=True)
// of the dense descriptors (dim x cells_h x cells_w) at the SuperGlue-normalised position, then L2 norm.
inline std::vector<float> sample_descriptor(const std::vector<float>& dense, int cells_h, int cells_w, float x, float y,
                                            int dim = 256) {
  const int h = cells_h * 8, w = cells_w * 8;
  const double gx = (x - 4.0 + 0.5) / (w - 4.0 - 0.5) * 2 - 1, gy = (y - 4.0 + 0.5) / (h - 4.0 - 0.5) * 2 - 1;
  const double px = (gx + 1) / 2 * (cells_w - 1), py = (gy + 1) / 2 * (cells_h - 1);
  const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
  const double tx = px - x0, ty = py - y0;
  std::vector<float> v(dim);
  double sq = 0;
  for (int c = 0; c < dim; ++c) {
    const auto tap = [&](int yy, int xx) -> double {
      if (xx < 0 || yy < 0 || xx >= cells_w || yy >= cells_h) return 0.0;
      return dense[(std::size_t(c) * cells_h + yy) * cells_w + xx];
    };
    const double s = (tap(y0, x0) * (1 - tx) + tap(y0, x0 + 1) * tx) * (1 - ty) +
                     (tap(y0 + 1, x0) * (1 - tx) + tap(y0 + 1, x0 + 1) * tx) * ty;
    v[c] = float(s);
    sq += s * s;
  }
  for (auto& e : v) e = float(e / std::max(std::sqrt(sq), 1e-12));
  return v;
}

// The vertex of the parabola through (-1, left), (0, centre), (1, right), clamped to half a pixel; 0 where centre is
// no strict peak of the three.
inline double parabola_peak(double left, double centre, double right) {
  const double curvature = left - 2 * centre + right;
  return curvature < 0 ? std::clamp(0.5 * (left - right) / curvature, -0.5, 0.5) : 0.0;
}

// Keypoint (x, y) of a w x h score map moved to its sub-pixel peak: one parabola per axis through the log scores
// (a Gaussian peak), not at the map's edge.
inline Eigen::Vector2f subpixel_peak(const std::vector<float>& scores, int w, int h, int x, int y) {
  if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return {float(x), float(y)};
  const auto at = [&](int xx, int yy) { return std::log(std::max(double(scores[std::size_t(yy) * w + xx]), 1e-30)); };
  return {float(x + parabola_peak(at(x - 1, y), at(x, y), at(x + 1, y))),
          float(y + parabola_peak(at(x, y - 1), at(x, y), at(x, y + 1)))};
}

// Threshold, border removal, top-k (ties: lower pixel index first), bilinear descriptor sampling + L2 norm at the
// whole pixel; `subpixel` then moves each keypoint to its sub-pixel peak.
inline Keypoints postprocess(const Dense& d, float threshold, int radius, int border, int max_keypoints,
                             bool subpixel = false, int dim = 256) {
  const int h = d.cells_h * 8, w = d.cells_w * 8;
  const auto nms = simple_nms(d.scores, h, w, radius);
  std::vector<int> idx;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if (nms[i] > threshold && y >= border && y < h - border && x >= border && x < w - border) idx.push_back(i);
    }
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return d.scores[a] > d.scores[b]; });
  if (max_keypoints > 0 && int(idx.size()) > max_keypoints) idx.resize(max_keypoints);
  Keypoints k;
  for (int i : idx) {
    const float x = float(i % w), y = float(i / w);
    k.xy.push_back(subpixel ? subpixel_peak(d.scores, w, h, i % w, i / w) : Eigen::Vector2f(x, y));
    k.scores.push_back(d.scores[i]);
    k.descriptors.push_back(sample_descriptor(d.descriptors, d.cells_h, d.cells_w, x, y, dim));
  }
  return k;
}

// A SuperPoint-shaped pack with He-initialised random weights (activations stay O(1) through the 10 layers).
inline io::ModelPack random_superpoint_pack(std::uint32_t seed) {
  std::mt19937 rng(seed);
  io::ModelPackWriter writer(io::NetworkKind::superpoint);
  struct Layer {
    const char* name;
    int in, out, k;
  };
  const Layer layers[] = {{"conv1a", 1, 64, 3},    {"conv1b", 64, 64, 3},   {"conv2a", 64, 64, 3},
                          {"conv2b", 64, 64, 3},   {"conv3a", 64, 128, 3},  {"conv3b", 128, 128, 3},
                          {"conv4a", 128, 128, 3}, {"conv4b", 128, 128, 3}, {"convPa", 128, 256, 3},
                          {"convPb", 256, 65, 1},  {"convDa", 128, 256, 3}, {"convDb", 256, 256, 1}};
  for (const auto& l : layers) {
    std::normal_distribution<float> w_dist(0.0f, std::sqrt(2.0f / float(l.in * l.k * l.k)));
    std::uniform_real_distribution<float> b_dist(-0.1f, 0.1f);
    std::vector<float> w(std::size_t(l.out) * l.in * l.k * l.k), b(l.out);
    for (auto& v : w) v = w_dist(rng);
    for (auto& v : b) v = b_dist(rng);
    // The detector logits get a wider spread so that the softmax is peaked, as in the trained network.
    if (std::string(l.name) == "convPb")
      for (auto& v : w) v *= 4.0f;
    writer.add_tensor(std::string(l.name) + ".weight", {l.out, l.in, l.k, l.k}, "o4",
                      rt::pack_conv_o4(w, l.out, l.in, l.k, l.k));
    writer.add_tensor(std::string(l.name) + ".bias", {l.out}, "o4", rt::pad_bias_o4(b));
  }
  writer.set_number("descriptor_dim", 256);
  writer.set_number("detector_channels", 65);
  const auto bytes = writer.serialize();
  return io::ModelPack::parse(bytes, io::NetworkKind::superpoint, "random weights");
}

}  // namespace vkvo::features::reference
