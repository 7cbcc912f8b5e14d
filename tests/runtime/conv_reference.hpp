#pragma once
// Plain C++ references of the convolution kernels' operations, and the bordered activation layout, for the
// kernel tests.
#include <algorithm>
#include <vector>

#include "runtime/ops.hpp"

namespace vkvo::test {

// Plain convolution on unpadded CHW tensors (PyTorch semantics: stride 1, zero padding k/2).
inline std::vector<float> reference_conv(const std::vector<float>& in, const std::vector<float>& w,
                                         const std::vector<float>& b, int ic, int oc, int h, int wd, int k, bool relu) {
  std::vector<float> out(std::size_t(oc) * h * wd);
  const int r = k / 2;
  for (int o = 0; o < oc; ++o)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < wd; ++x) {
        double s = b[o];
        for (int i = 0; i < ic; ++i)
          for (int ky = 0; ky < k; ++ky)
            for (int kx = 0; kx < k; ++kx) {
              const int yy = y + ky - r, xx = x + kx - r;
              if (yy < 0 || yy >= h || xx < 0 || xx >= wd) continue;
              s += double(w[((o * ic + i) * k + ky) * k + kx]) * in[(i * h + yy) * wd + xx];
            }
        out[(o * h + y) * wd + x] = relu ? std::max(0.0f, float(s)) : float(s);
      }
  return out;
}

// CHW -> the bordered layout of rt::ActivationShape (zero border of `pad`, rows padded to whole texels), and back.
inline std::vector<float> add_border(const std::vector<float>& t, int c, int h, int w, int pad) {
  const rt::ActivationShape shape{std::uint32_t(c), std::uint32_t(h), std::uint32_t(w), std::uint32_t(pad)};
  std::vector<float> out(shape.elements(), 0.0f);
  for (int i = 0; i < c; ++i)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out[shape.index(i, y, x)] = t[(i * h + y) * w + x];
  return out;
}
inline std::vector<float> strip_border(const std::vector<float>& t, int c, int h, int w, int pad) {
  const rt::ActivationShape shape{std::uint32_t(c), std::uint32_t(h), std::uint32_t(w), std::uint32_t(pad)};
  std::vector<float> out(std::size_t(c) * h * w);
  for (int i = 0; i < c; ++i)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out[(i * h + y) * w + x] = t[shape.index(i, y, x)];
  return out;
}

// PyTorch's max_pool2d(2) on CHW: floor semantics, a last odd row or column is dropped.
inline std::vector<float> reference_max_pool(const std::vector<float>& in, int c, int h, int w) {
  const int oh = h / 2, ow = w / 2;
  std::vector<float> out(std::size_t(c) * oh * ow);
  for (int i = 0; i < c; ++i)
    for (int y = 0; y < oh; ++y)
      for (int x = 0; x < ow; ++x) {
        const float* p = &in[(std::size_t(i) * h + 2 * y) * w + 2 * x];
        out[(std::size_t(i) * oh + y) * ow + x] = std::max(std::max(p[0], p[1]), std::max(p[w], p[w + 1]));
      }
  return out;
}

}  // namespace vkvo::test
