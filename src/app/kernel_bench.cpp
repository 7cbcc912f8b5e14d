#include "app/kernel_bench.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <random>

#include <fmt/format.h>

#include "runtime/half.hpp"
#include "runtime/ops.hpp"
#include "runtime/tensor_layout.hpp"
#include "runtime/winograd.hpp"

namespace vkvo::app {
namespace {

// Submits the recorded sequence `repeat` times (after a warm-up) and returns the median time.
double time_sequence(rt::Sequence& seq, int repeat, bool timestamps) {
  seq.submit();  // warm-up: first-touch of memory, pipeline compilation on some drivers
  std::vector<double> samples;
  for (int i = 0; i < repeat; ++i) {
    const auto start = std::chrono::steady_clock::now();
    seq.submit();
    const auto wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    samples.push_back(timestamps ? seq.gpu_ms() : wall);
  }
  return median_ms(samples);
}

// Uniform values in [-1, 1] at the storage precision: real data, so that timings include whatever the device
// does differently for non-zero operands (zero-filled buffers would flatter a CPU driver).
void fill_random(rt::Buffer& buffer, rt::Precision precision, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> values(buffer.size() / rt::storage_bytes(precision));
  for (float& v : values) v = uniform(rng);
  const auto bytes = rt::encode_storage(values, precision);
  buffer.upload(bytes.data(), bytes.size());
}

}  // namespace

double median_ms(const std::vector<double>& samples) {
  if (samples.empty()) return 0;
  auto sorted = samples;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

std::vector<BenchResult> bench_kernels(const rt::Context& ctx, rt::Precision precision, int repeat,
                                       std::string_view filter) {
  const auto wanted = [&](const std::string& kernel_name) {
    return filter.empty() || kernel_name.find(filter) != std::string::npos;
  };
  const bool timestamps = ctx.caps().timestamps;
  const double elem = double(rt::storage_bytes(precision));
  const rt::Precision weight_precision = rt::conv_weight_precision(precision);  // the convolutions' weights
  std::vector<BenchResult> results;
  const auto name = std::string(rt::to_string(precision));

  // Convolutions at SuperPoint's shapes for a 752x480 input (the 64->64 layer at 376x240 is the figure), and
  // convDb at 640x480 (256->256 @80x60), to compare with its GEMM form below.
  struct ConvCase {
    std::uint32_t in_c, out_c, h, w, k;
  };
  // Every 3x3 case runs with each kernel the device has (the tiled kernel is what the networks use where
  // available; the direct one is the fallback), so the gain of one over the other is measured, not assumed.
  std::vector<rt::Conv3x3Kernel> kernels3x3{rt::Conv3x3Kernel::direct};
  if (rt::tiled_kernels_available(ctx, precision)) kernels3x3.insert(kernels3x3.begin(), rt::Conv3x3Kernel::tiled);
  if (rt::use_cooperative_matrix(ctx, precision))  // tensor cores (docs/tensor-cores.md)
    kernels3x3.insert(kernels3x3.begin(), rt::Conv3x3Kernel::cooperative_matrix);
  for (const ConvCase c :
       {ConvCase{64, 64, 240, 376, 3}, ConvCase{1, 64, 480, 752, 3}, ConvCase{64, 64, 480, 752, 3},
        ConvCase{128, 256, 60, 94, 3}, ConvCase{256, 65, 60, 94, 1}, ConvCase{256, 256, 60, 80, 1}}) {
    for (const rt::Conv3x3Kernel kernel : c.k == 3 ? kernels3x3 : std::vector{rt::Conv3x3Kernel::automatic}) {
      const char* suffix = c.k == 1                                          ? ""
                           : kernel == rt::Conv3x3Kernel::tiled              ? " tiled"
                           : kernel == rt::Conv3x3Kernel::cooperative_matrix ? " coopmat"
                                                                             : " direct";
      const auto kernel_name = fmt::format("conv{}x{} {}->{} @{}x{}{}", c.k, c.k, c.in_c, c.out_c, c.w, c.h, suffix);
      if (!wanted(kernel_name)) continue;
      const rt::ActivationShape in{c.in_c, c.h, c.w, c.k == 3 ? 1u : 0u};
      const rt::ActivationShape out{c.out_c, c.h, c.w, 1};
      rt::Buffer in_buf(ctx, rt::activation_bytes(in, precision));
      rt::Buffer out_buf(ctx, rt::activation_bytes(out, precision));
      rt::Buffer w_buf(ctx, rt::round_up(c.out_c, 4) * c.in_c * c.k * c.k * rt::storage_bytes(weight_precision));
      rt::Buffer b_buf(ctx, rt::round_up(c.out_c, 4) * sizeof(float));
      fill_random(in_buf, precision, 1);
      fill_random(w_buf, weight_precision, 2);
      b_buf.fill_zero();
      const rt::Conv2d conv(ctx, precision, c.k, kernel);
      rt::Sequence seq(ctx);
      seq.begin();
      conv.record(seq, in_buf, in, w_buf, b_buf, out_buf, out, true);
      seq.end();
      const double ms = time_sequence(seq, repeat, timestamps);
      const double bytes = (double(in.elements()) + double(out.elements())) * elem;
      results.push_back({kernel_name, name, ms, rt::Conv2d::flops(in, c.out_c, c.k) / (ms * 1e6), bytes / (ms * 1e6)});
    }
  }

  // SuperPoint's conv1b + pool1 in one pass, where the device has the tiled kernels: compare with the
  // "conv3x3 64->64 @752x480 tiled" and "maxpool2x2" rows it replaces.
  if (const std::string kernel_name = "conv3x3+maxpool 64->64 @752x480 tiled";
      rt::tiled_kernels_available(ctx, precision) && wanted(kernel_name)) {
    const rt::ActivationShape in{64, 480, 752, 1}, out{64, 240, 376, 1};
    rt::Buffer in_buf(ctx, rt::activation_bytes(in, precision));
    rt::Buffer out_buf(ctx, rt::activation_bytes(out, precision));
    rt::Buffer w_buf(ctx, std::size_t(64) * 64 * 9 * rt::storage_bytes(weight_precision));
    rt::Buffer b_buf(ctx, 64 * sizeof(float));
    fill_random(in_buf, precision, 1);
    fill_random(w_buf, weight_precision, 2);
    b_buf.fill_zero();
    const rt::Conv3x3MaxPool op(ctx, precision);
    rt::Sequence seq(ctx);
    seq.begin();
    op.record(seq, in_buf, in, w_buf, b_buf, out_buf, out, true);
    seq.end();
    const double ms = time_sequence(seq, repeat, timestamps);
    const double bytes = (double(in.elements()) + double(out.elements())) * elem;
    results.push_back({kernel_name, name, ms, rt::Conv2d::flops(in, 64, 3) / (ms * 1e6), bytes / (ms * 1e6)});
  }

  // Winograd F(4x4, 3x3) and F(6x6, 3x3) (what SuperPoint runs in fp32 on CPU devices) at the shapes of the rows
  // above: transforms and GEMMs together; GFLOP/s counts the direct convolution's multiply-adds, so the rows compare
  // as speed.
  struct WinogradCase {
    std::uint32_t in_c, out_c, h, w;
    bool max_pool;
  };
  for (const WinogradCase c : {WinogradCase{64, 64, 240, 376, false}, WinogradCase{64, 64, 480, 752, true},
                               WinogradCase{128, 256, 60, 94, false}}) {
    for (const auto tile : {rt::WinogradConv3x3::Tile::f43, rt::WinogradConv3x3::Tile::f63}) {
      const auto kernel_name = fmt::format("conv3x3{} {}->{} @{}x{} winograd f{}3", c.max_pool ? "+maxpool" : "",
                                           c.in_c, c.out_c, c.w, c.h, std::uint32_t(tile));
      if (precision != rt::Precision::fp32 || !rt::tiled_kernels_available(ctx, precision) || !wanted(kernel_name))
        continue;
      const rt::WinogradConv3x3 op(ctx, precision, tile);
      const rt::ActivationShape in{c.in_c, c.h, c.w, 1};
      const rt::ActivationShape out{c.out_c, c.max_pool ? c.h / 2 : c.h, c.max_pool ? c.w / 2 : c.w, 1};
      rt::Buffer in_buf(ctx, rt::activation_bytes(in, precision)), out_buf(ctx, rt::activation_bytes(out, precision));
      rt::Buffer w_buf(ctx, std::size_t(rt::WinogradConv3x3::points(op.tile())) * c.out_c * c.in_c * sizeof(float));
      rt::Buffer b_buf(ctx, c.out_c * sizeof(float));
      rt::Buffer transformed(ctx, op.transformed_input_bytes(in, c.out_c)),
          products(ctx, op.products_bytes(in, c.out_c));
      fill_random(in_buf, precision, 1);
      fill_random(w_buf, precision, 2);
      b_buf.fill_zero();
      rt::Sequence seq(ctx);
      seq.begin();
      op.record(seq, in_buf, in, w_buf, b_buf, transformed, products, out_buf, out, true, c.max_pool, "conv");
      seq.end();
      const double ms = time_sequence(seq, repeat, timestamps);
      const double bytes = (double(in.elements()) + double(out.elements())) * elem;
      results.push_back({kernel_name, name, ms, rt::Conv2d::flops(in, c.out_c, 3) / (ms * 1e6), bytes / (ms * 1e6)});
    }
  }

  if (const std::string kernel_name = "maxpool2x2 64ch @752x480"; wanted(kernel_name)) {  // SuperPoint's first pool
    const rt::ActivationShape in{64, 480, 752, 1};
    rt::Buffer in_buf(ctx, rt::activation_bytes(in, precision));
    rt::Buffer out_buf(ctx, rt::activation_bytes({64, 240, 376, 1}, precision));
    in_buf.fill_zero();
    const rt::MaxPool2x2 pool(ctx, precision);
    rt::Sequence seq(ctx);
    seq.begin();
    pool.record(seq, in_buf, in, out_buf, 1);
    seq.end();
    const double ms = time_sequence(seq, repeat, timestamps);
    results.push_back({kernel_name, name, ms, 0, double(in.elements()) * 1.25 * elem / (ms * 1e6)});
  }

  // GEMMs at SuperGlue's shapes for 400 keypoints: a projection (B^T = weight) and attention scores; mlp0 at 1000
  // and 400 rows (N = M = 500 and 200: 400 rows leave lanes of the last subgroup idle); and SuperPoint's
  // convDb at 640x480 as a GEMM over its 80 x 60 planes (rt::conv1x1_gemm_shape), to compare with the conv1x1 row.
  for (const rt::GemmShape s : {rt::GemmShape{.m = 400, .n = 256, .k = 256, .b_transposed = true},
                                rt::GemmShape{.m = 400, .n = 400, .k = 64, .b_transposed = true},
                                rt::GemmShape{.m = 1000, .n = 512, .k = 512, .b_transposed = true},
                                rt::GemmShape{.m = 400, .n = 512, .k = 512, .b_transposed = true},
                                rt::conv1x1_gemm_shape(rt::ActivationShape{256, 60, 80, 0}, 256, false)}) {
    const rt::Gemm gemm(ctx, precision);
    const auto kernel_name = fmt::format("gemm {}x{}x{}{}{}", s.m, s.n, s.k, s.b_transposed ? " B^T" : "",
                                         gemm.uses_cooperative_matrix() ? " coopmat" : "");
    if (!wanted(kernel_name)) continue;
    rt::Buffer a(ctx, std::size_t(s.m) * s.k * rt::storage_bytes(precision));
    rt::Buffer b(ctx, std::size_t(s.n) * s.k * rt::storage_bytes(precision));
    rt::Buffer c(ctx, std::size_t(s.m) * s.n * rt::storage_bytes(precision));
    fill_random(a, precision, 3);
    fill_random(b, precision, 4);
    rt::Sequence seq(ctx);
    seq.begin();
    gemm.record(seq, a, b, nullptr, c, s);
    seq.end();
    const double ms = time_sequence(seq, repeat, timestamps);
    const double bytes = (double(s.m) * s.k + double(s.n) * s.k + double(s.m) * s.n) * elem;
    results.push_back({kernel_name, name, ms, rt::Gemm::flops(s) / (ms * 1e6), bytes / (ms * 1e6)});
  }
  return results;
}

void print_bench_header() {
  fmt::print("{:<46} {:<6} {:>10} {:>10} {:>9}\n", "kernel", "prec", "median ms", "GFLOP/s", "GB/s");
}

void print_bench_row(const BenchResult& r) {
  fmt::print("{:<46} {:<6} {:>10.3f} {:>10.1f} {:>9.2f}\n", r.name, r.precision, r.median_ms, r.gflops, r.gbytes);
}

}  // namespace vkvo::app
