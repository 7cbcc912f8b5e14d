#include "runtime/ops.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "runtime/context.hpp"

namespace vkvo::rt {
namespace {

// Workgroup sizes (specialization constants 0 and 1). 64 invocations: eight 8-wide lanes on lavapipe,
// two warps on NVIDIA, one wave on AMD.
constexpr std::uint32_t kGroupX = 16, kGroupY = 4;

struct ConvPush {
  std::uint32_t in_channels, out_channels, height, width, out_pad, relu;
};
struct Conv1x1Push {
  std::uint32_t in_channels, out_channels, height, width, in_pad, out_pad, relu;
};
struct PoolPush {
  std::uint32_t channels, in_height, in_width, in_pad, out_pad;
};
struct GemmPush {
  std::uint32_t m, n, k, b_transposed, has_bias, relu;
  float alpha;
};

KernelSpec conv_spec(Precision precision, std::uint32_t kernel_size) {
  if (kernel_size != 1 && kernel_size != 3) throw std::invalid_argument("Conv2d: kernel size must be 1 or 3");
  return {.op = kernel_size == 3 ? "conv3x3" : "conv1x1", .precision = precision, .bindings = 4,
          .written_bindings = 1u << 3,
          .push_constant_bytes = kernel_size == 3 ? std::uint32_t(sizeof(ConvPush)) : std::uint32_t(sizeof(Conv1x1Push)),
          .specialization = {kGroupX, kGroupY}};
}

}  // namespace

std::size_t activation_bytes(const ActivationShape& shape, Precision precision) {
  return shape.elements() * storage_bytes(precision);
}

Conv2d::Conv2d(const Context& context, Precision precision, std::uint32_t kernel_size)
    : kernel_size_(kernel_size), kernel_(context, conv_spec(precision, kernel_size)) {}

void Conv2d::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Buffer& weights,
                    const Buffer& bias, const Buffer& output, const ActivationShape& out, bool relu,
                    std::string label) const {
  if (in.height != out.height || in.width != out.width)
    throw std::invalid_argument("Conv2d: input and output must have the same spatial size");
  const std::uint32_t blocks = (out.channels + 3) / 4;
  if (kernel_size_ == 3) {
    if (in.pad != 1) throw std::invalid_argument("Conv2d 3x3: the input needs a 1-pixel zero border");
    const ConvPush push{in.channels, out.channels, in.height, in.width, out.pad, relu ? 1u : 0u};
    seq.dispatch(kernel_, {input, weights, bias, output}, push,
                 {groups_for(groups_for(in.width, 3), kGroupX), groups_for(in.height, kGroupY), blocks},
                 label.empty() ? fmt::format("conv3x3 {}->{}", in.channels, out.channels) : std::move(label));
  } else {
    const Conv1x1Push push{in.channels, out.channels, in.height, in.width, in.pad, out.pad, relu ? 1u : 0u};
    seq.dispatch(kernel_, {input, weights, bias, output}, push,
                 {groups_for(groups_for(in.width, 4), kGroupX), groups_for(in.height, kGroupY), blocks},
                 label.empty() ? fmt::format("conv1x1 {}->{}", in.channels, out.channels) : std::move(label));
  }
}

MaxPool2x2::MaxPool2x2(const Context& context, Precision precision)
    : kernel_(context, {.op = "maxpool2x2", .precision = precision, .bindings = 2, .written_bindings = 1u << 1,
                        .push_constant_bytes = sizeof(PoolPush), .specialization = {}}) {}

void MaxPool2x2::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Buffer& output,
                        std::uint32_t out_pad, std::string label) const {
  const PoolPush push{in.channels, in.height, in.width, in.pad, out_pad};
  const std::size_t outputs = std::size_t(in.channels) * (in.height / 2) * (in.width / 2);
  seq.dispatch(kernel_, {input, output}, push, {groups_for(outputs, 64)},
               label.empty() ? "maxpool2x2" : std::move(label));
}

Gemm::Gemm(const Context& context, Precision precision)
    : kernel_(context, {.op = "gemm", .precision = precision, .bindings = 4, .written_bindings = 1u << 3,
                        .push_constant_bytes = sizeof(GemmPush), .specialization = {kGroupX, kGroupY}}),
      dummy_bias_(context, 16, BufferKind::device, "gemm.no_bias") {}

void Gemm::record(Sequence& seq, const Buffer& a, const Buffer& b, const Buffer* bias, const Buffer& c,
                  const GemmShape& s, std::string label) const {
  const GemmPush push{s.m, s.n, s.k, s.b_transposed ? 1u : 0u, bias ? 1u : 0u, s.relu ? 1u : 0u, s.alpha};
  seq.dispatch(kernel_, {a, b, bias ? *bias : dummy_bias_, c}, push,
               {groups_for(groups_for(s.n, 4), kGroupX), groups_for(groups_for(s.m, 4), kGroupY)},
               label.empty() ? fmt::format("gemm {}x{}x{}", s.m, s.n, s.k) : std::move(label));
}

}  // namespace vkvo::rt
