#include "runtime/ops.hpp"

#include <initializer_list>
#include <map>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>

#include "runtime/context.hpp"
#include "runtime/push_constants.hpp"

namespace vkvo::rt {
namespace {

// Workgroup sizes (specialization constants 0 and 1). 64 invocations: eight 8-wide lanes on lavapipe,
// two warps on NVIDIA, one wave on AMD.
constexpr std::uint32_t kGroupX = 16, kGroupY = 4;

using shader::Conv1x1Push;
using shader::Conv3x3Push;
using shader::GemmPush;
using shader::MaxPoolPush;
// Output rows per invocation of shaders/gemm.comp (its ROWS).
constexpr std::uint32_t kGemmRows = 3;
// gemm_tiled.comp's kBiasPer specialization constant.
constexpr std::uint32_t kGemmNoBias = 0, kGemmBiasPerColumn = 1, kGemmBiasPerRow = 2;

// Output channels and pixels per invocation of conv3x3_tiled.comp (and pixels of conv1x1_tiled.comp).
constexpr std::uint32_t kTiledConvChannels = 8, kTiledConvPixels = 4, kTiledConvRows = 3;
constexpr std::uint32_t kPooledConvRows = 4;  // ROWS of conv3x3_maxpool_tiled.comp
constexpr std::uint32_t kTiledConv1x1Pixels = 8;

// The block of the output each workgroup of the tensor-core kernels computes (shaders/include/coopmat_tile.glsl).
constexpr std::uint32_t kCoopmatBlock = 64;

KernelSpec coopmat_spec(const Context& context, Op op, Precision precision) {
  return {.op = op, .precision = precision, .specialization = {kCoopmatSubgroups * context.caps().subgroup_size}};
}

// The tensor-core kernel for `op` if `choice` asks for it, or `automatic` does on this device.
template <class Choice>
std::optional<Kernel> coopmat_kernel(const Context& context, Op op, Precision precision, Choice choice) {
  if (choice != Choice::cooperative_matrix &&
      (choice != Choice::automatic || !use_cooperative_matrix(context, precision)))
    return std::nullopt;
  return Kernel(context, coopmat_spec(context, op, precision));  // throws naming what the device lacks
}

}  // namespace

bool use_cooperative_matrix(const Context& context, Precision precision) {
  return context.profile().cooperative_matrix && precision != Precision::fp32;
}

bool tiled_kernels_available(const Context& context, Precision precision) {
  return context.supports_uniform_texel_format(activation_texel_format(precision)) &&
         context.supports_uniform_texel_format(vec4_texel_format(precision)) &&
         context.supports_uniform_texel_format(conv_weight_texel_format(precision)) &&
         context.supports_uniform_texel_format(packed_texel_format(precision));
}

namespace {

bool use_tiled_conv(const Context& context, Precision precision, std::uint32_t kernel_size, Conv3x3Kernel choice) {
  if (kernel_size != 3 || choice == Conv3x3Kernel::direct || choice == Conv3x3Kernel::cooperative_matrix) return false;
  const bool available = tiled_kernels_available(context, precision);
  if (choice == Conv3x3Kernel::tiled && !available)
    throw std::invalid_argument(
        "Conv2d: the tiled 3x3 kernel needs uniform texel-buffer reads of the activation and weight formats");
  return available;
}

KernelSpec conv_spec(Precision precision, std::uint32_t kernel_size, bool tiled, bool max_pool = false) {
  if (kernel_size != 1 && kernel_size != 3) throw std::invalid_argument("Conv2d: kernel size must be 1 or 3");
  std::vector<vk::Format> texel_formats;
  if (tiled) texel_formats = {vec4_texel_format(precision), conv_weight_texel_format(precision)};
  const Op op = kernel_size == 1 ? Op::conv1x1
                : !tiled         ? Op::conv3x3
                : max_pool       ? Op::conv3x3_maxpool_tiled
                                 : Op::conv3x3_tiled;
  return {.op = op,
          .precision = precision,
          .specialization = {kGroupX, kGroupY},
          .texel_formats = std::move(texel_formats)};
}

// The tiled 3x3 kernels read the input 4 values per texel through one view of at most the device's texel count.
void check_tiled_conv_input(const ActivationShape& in, std::size_t max_texel_elements) {
  if (in.pad != 1) throw std::invalid_argument("Conv2d 3x3: the input needs a 1-pixel zero border");
  if (in.elements() / 4 > max_texel_elements)
    throw std::invalid_argument(fmt::format("Conv2d: {} input texels exceed the device's {} texel-buffer elements",
                                            in.elements() / 4, max_texel_elements));
}

// Grid of the tiled 3x3 kernels: (8-channel groups, 4-pixel column tiles, `rows`-row tiles) over workgroups of
// kGroupX x kGroupY invocations; the channel group varies fastest (conv3x3_tiled.comp).
Groups tiled_conv_groups(const ActivationShape& in, std::uint32_t out_channels, std::uint32_t rows) {
  return {groups_for(out_channels, kTiledConvChannels), groups_for(groups_for(in.width, kTiledConvPixels), kGroupX),
          groups_for(groups_for(in.height, rows), kGroupY)};
}

}  // namespace

vk::Format activation_texel_format(Precision precision) {
  return precision == Precision::fp32 ? vk::Format::eR32Sfloat : vk::Format::eR16Sfloat;
}
vk::Format vec4_texel_format(Precision precision) {
  return precision == Precision::fp32 ? vk::Format::eR32G32B32A32Sfloat : vk::Format::eR16G16B16A16Sfloat;
}

vk::Format packed_texel_format(Precision precision) {
  return precision == Precision::fp32 ? vk::Format::eR32G32B32A32Sfloat : vk::Format::eR32G32B32A32Uint;
}
std::uint32_t values_per_packed_texel(Precision precision) { return precision == Precision::fp32 ? 4 : 8; }

Precision conv_weight_precision(Precision activations) {
  return activations == Precision::fp16 ? Precision::fp16 : Precision::fp32;
}
vk::Format conv_weight_texel_format(Precision activations) {
  return vec4_texel_format(conv_weight_precision(activations));
}

std::size_t activation_bytes(const ActivationShape& shape, Precision precision) {
  return shape.elements() * storage_bytes(precision);
}

Conv2d::Conv2d(const Context& context, Precision precision, std::uint32_t kernel_size, Conv3x3Kernel choice)
    : kernel_size_(kernel_size),
      tiled_(use_tiled_conv(context, precision, kernel_size, choice)),
      max_texel_elements_(context.caps().max_texel_buffer_elements),
      kernel_(context, conv_spec(precision, kernel_size, tiled_)) {
  if (kernel_size == 3) coopmat_ = coopmat_kernel(context, Op::conv3x3_coopmat, precision, choice);
  if (kernel_size == 1 && choice == Conv3x3Kernel::cooperative_matrix)
    throw std::invalid_argument("Conv2d: the cooperative-matrix kernel is a 3x3 convolution");
  if (kernel_size == 1 && choice != Conv3x3Kernel::direct && tiled_kernels_available(context, precision))
    tiled_1x1_.emplace(context, KernelSpec{.op = Op::conv1x1_tiled,
                                           .precision = precision,
                                           .specialization = {kGroupX, kGroupY},
                                           .texel_formats = {activation_texel_format(precision),
                                                             conv_weight_texel_format(precision)}});
}

bool Conv2d::uses_tiled_kernel(const ActivationShape& in) const {
  if (kernel_size_ == 3) return tiled_;
  // conv1x1_tiled steps 4 input channels at a time; its texel view must fit the device's limit.
  return tiled_1x1_.has_value() && in.channels % 4 == 0 && in.elements() <= max_texel_elements_;
}

void Conv2d::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
                    const Binding& bias, const Buffer& output, const ActivationShape& out, bool relu,
                    std::string label) const {
  if (in.height != out.height || in.width != out.width)
    throw std::invalid_argument("Conv2d: input and output must have the same spatial size");
  const std::uint32_t blocks = (out.channels + 3) / 4;
  if (kernel_size_ == 3) {
    const Conv3x3Push push{in.channels, out.channels, in.height, in.width, out.pad, relu ? 1u : 0u};
    if (coopmat_) {
      if (in.pad != 1) throw std::invalid_argument("Conv2d 3x3: the input needs a 1-pixel zero border");
      seq.dispatch(
          *coopmat_, {input, weights, bias, output}, push,
          {groups_for(std::size_t(in.height) * in.width, kCoopmatBlock), groups_for(out.channels, kCoopmatBlock)},
          label.empty() ? fmt::format("conv3x3 {}->{}", in.channels, out.channels) : std::move(label));
      return;
    }
    if (tiled_)
      check_tiled_conv_input(in, max_texel_elements_);
    else if (in.pad != 1)
      throw std::invalid_argument("Conv2d 3x3: the input needs a 1-pixel zero border");
    const Groups groups =
        tiled_ ? tiled_conv_groups(in, out.channels, kTiledConvRows)
               : Groups{groups_for(groups_for(in.width, 3), kGroupX), groups_for(in.height, kGroupY), blocks};
    seq.dispatch(kernel_, {input, weights, bias, output}, push, groups,
                 label.empty() ? fmt::format("conv3x3 {}->{}", in.channels, out.channels) : std::move(label));
  } else {
    const Conv1x1Push push{in.channels, out.channels, in.height, in.width, in.pad, out.pad, relu ? 1u : 0u};
    if (uses_tiled_kernel(in)) {
      seq.dispatch(*tiled_1x1_, {input, weights, bias, output}, push,
                   {groups_for(out.channels, kTiledConvChannels),
                    groups_for(groups_for(in.width, kTiledConv1x1Pixels), kGroupX), groups_for(in.height, kGroupY)},
                   label.empty() ? fmt::format("conv1x1 {}->{}", in.channels, out.channels) : std::move(label));
      return;
    }
    seq.dispatch(kernel_, {input, weights, bias, output}, push,
                 {groups_for(groups_for(in.width, 4), kGroupX), groups_for(in.height, kGroupY), blocks},
                 label.empty() ? fmt::format("conv1x1 {}->{}", in.channels, out.channels) : std::move(label));
  }
}

Conv3x3MaxPool::Conv3x3MaxPool(const Context& context, Precision precision)
    : max_texel_elements_(context.caps().max_texel_buffer_elements),
      kernel_(context, conv_spec(precision, 3, use_tiled_conv(context, precision, 3, Conv3x3Kernel::tiled), true)) {}

void Conv3x3MaxPool::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
                            const Binding& bias, const Buffer& output, const ActivationShape& out, bool relu,
                            std::string label) const {
  if (out.height != in.height / 2 || out.width != in.width / 2)
    throw std::invalid_argument(fmt::format("Conv3x3MaxPool: a {}x{} input pools to {}x{}, not {}x{}", in.width,
                                            in.height, in.width / 2, in.height / 2, out.width, out.height));
  check_tiled_conv_input(in, max_texel_elements_);
  const Conv3x3Push push{in.channels, out.channels, in.height, in.width, out.pad, relu ? 1u : 0u};
  seq.dispatch(kernel_, {input, weights, bias, output}, push, tiled_conv_groups(in, out.channels, kPooledConvRows),
               label.empty() ? fmt::format("conv3x3+maxpool {}->{}", in.channels, out.channels) : std::move(label));
}

MaxPool2x2::MaxPool2x2(const Context& context, Precision precision)
    : kernel_(context, {.op = Op::maxpool2x2, .precision = precision}) {}

void MaxPool2x2::record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Buffer& output,
                        std::uint32_t out_pad, std::string label) const {
  const MaxPoolPush push{in.channels, in.height, in.width, in.pad, out_pad};
  const std::size_t plane = std::size_t(in.height / 2) * (in.width / 2);
  seq.dispatch(kernel_, {input, output}, push, {groups_for(plane, 64), in.channels},
               label.empty() ? "maxpool2x2" : std::move(label));
}

Gemm::Gemm(const Context& context, Precision precision, GemmKernel choice)
    : kernel_(context, {.op = Op::gemm, .precision = precision, .specialization = {kGroupX, kGroupY}}),
      max_texel_elements_(context.caps().max_texel_buffer_elements),
      elements_per_texel_(values_per_packed_texel(precision)),
      dummy_bias_(context, 16, BufferKind::device, "gemm.no_bias") {
  coopmat_ = coopmat_kernel(context, Op::gemm_coopmat, precision, choice);
  if (coopmat_) return;
  const vk::Format texel = packed_texel_format(precision);
  const bool available = context.supports_uniform_texel_format(texel);
  if ((choice == GemmKernel::tiled || choice == GemmKernel::tiled_wide) && !available)
    throw std::invalid_argument("Gemm: the tiled kernel needs uniform texel-buffer reads of the operand format");
  if (choice != GemmKernel::direct && available) {
    // The device profile's tile (gemm_tiled.comp says why CPUs get the wide one), unless the caller chose.
    const bool wide =
        choice == GemmKernel::tiled_wide || (choice == GemmKernel::automatic && context.profile().wide_gemm_tile);
    tile_ = wide ? TiledGemmTile{8, 16} : TiledGemmTile{4, 8};
    tiled_ = std::make_unique<TiledVariants>(context, KernelSpec{.op = wide ? Op::gemm_tiled_wide : Op::gemm_tiled,
                                                                 .precision = precision,
                                                                 .texel_formats = {texel, texel}});
  }
}

Gemm::Gemm(Gemm&&) noexcept = default;
Gemm::~Gemm() = default;

struct Gemm::TiledVariants {
  TiledVariants(const Context& c, KernelSpec s) : context(c), spec(std::move(s)) {}
  const Context& context;
  KernelSpec spec;  // without its specialization constants
  std::mutex mutex;
  std::map<std::uint32_t, Kernel> kernels;  // by specialization key; map nodes stay put as variants are added
};

// The epilogue is specialised rather than read from push-constant flags: lavapipe runs both sides of a branch
// under lane masks, so a flag left off still ran the bias loads and the accumulating load of C, each a scalar
// loop over the lanes. SuperPoint's Winograd GEMMs (K = 64) use neither (docs/performance-history.md, "Tiled
// GEMM").
const Kernel& Gemm::tiled_kernel(bool vec4_store, bool accumulate, std::uint32_t bias_per) const {
  const std::uint32_t key = (vec4_store ? 1u : 0u) | (accumulate ? 2u : 0u) | (bias_per << 2);
  const std::lock_guard lock(tiled_->mutex);
  auto it = tiled_->kernels.find(key);
  if (it == tiled_->kernels.end()) {
    KernelSpec spec = tiled_->spec;
    spec.specialization = {kGroupX * kGroupY, vec4_store ? 1u : 0u, accumulate ? 1u : 0u, bias_per};
    it = tiled_->kernels.try_emplace(key, tiled_->context, std::move(spec)).first;
  }
  return it->second;
}

namespace {
bool multiples_of(std::uint32_t divisor, std::initializer_list<std::uint32_t> values) {
  for (auto v : values)
    if (v % divisor != 0) return false;
  return true;
}
bool multiples_of_4(std::initializer_list<std::uint32_t> values) { return multiples_of(4, values); }
std::uint32_t leading_a(const GemmShape& s) { return s.lda ? s.lda : s.k; }
std::uint32_t leading_b(const GemmShape& s) { return s.ldb ? s.ldb : (s.b_transposed ? s.k : s.n); }
std::uint32_t leading_c(const GemmShape& s) { return s.ldc ? s.ldc : s.n; }
}  // namespace

bool Gemm::uses_tiled_kernel(const GemmShape& s, const Binding& a, const Binding& b) const {
  if (!tiled_ || coopmat_) return false;
  // Texel views start at the binding offsets (256 bytes satisfies every device's texel offset alignment) and
  // must stay within the device's texel count; A is read along K, B along K (B^T) or N, a whole texel at a time.
  // 16-bit texels hold 8 columns of B: N must fill them (the kernel clamps a tile's columns to the last whole texel).
  const std::uint32_t per_texel = elements_per_texel_;
  const auto texels = [&](const Binding& x) {
    const std::size_t bytes = x.range == VK_WHOLE_SIZE ? x.buffer->size() - x.offset : x.range;
    return bytes / kPackedTexelBytes;
  };
  return a.offset % 256 == 0 && b.offset % 256 == 0 && texels(a) <= max_texel_elements_ &&
         texels(b) <= max_texel_elements_ &&
         multiples_of(per_texel,
                      {s.k, leading_a(s), s.a_offset, s.a_batch_stride, leading_b(s), s.b_offset, s.b_batch_stride}) &&
         (s.b_transposed || per_texel == 4 || s.n % per_texel == 0);
}

void Gemm::record(Sequence& seq, const Buffer& a, const Buffer& b, const Buffer* bias, const Buffer& c,
                  const GemmShape& s, std::string label) const {
  const Binding bias_binding(bias ? *bias : dummy_bias_);
  record(seq, Binding(a), Binding(b), bias ? &bias_binding : nullptr, Binding(c), s, std::move(label));
}

void Gemm::record(Sequence& seq, const Binding& a, const Binding& b, const Binding* bias, const Binding& c,
                  const GemmShape& s, std::string label) const {
  if (s.m == 0 || s.n == 0 || s.batch == 0) return;
  const std::uint32_t lda = leading_a(s), ldb = leading_b(s), ldc = leading_c(s);
  const Binding bindings[] = {a, b, bias ? *bias : Binding(dummy_bias_), c};
  std::uint32_t flags = (s.b_transposed ? shader::kGemmTransposedB : 0u) | (bias ? shader::kGemmBias : 0u) |
                        (s.relu ? shader::kGemmRelu : 0u) | (s.accumulate ? shader::kGemmAccumulate : 0u) |
                        (s.bias_per_row ? shader::kGemmRowBias : 0u);
  const bool tiled = uses_tiled_kernel(s, a, b);
  const Kernel* kernel = &kernel_;
  Groups groups;
  if (coopmat_) {
    kernel = &*coopmat_;
    groups = {groups_for(s.n, kCoopmatBlock), groups_for(s.m, kCoopmatBlock), s.batch};
  } else if (tiled) {
    const bool vec4_store = c.offset % 16 == 0 && multiples_of_4({s.n, ldc, s.c_offset, s.c_batch_stride});
    kernel = &tiled_kernel(vec4_store, s.accumulate,
                           !bias            ? kGemmNoBias
                           : s.bias_per_row ? kGemmBiasPerRow
                                            : kGemmBiasPerColumn);
    groups = {groups_for(s.n, tile_.cols), groups_for(groups_for(s.m, tile_.rows), kGroupX * kGroupY), s.batch};
  } else {
    // vec4 loads need every vec4 to start at a multiple of 4 elements (and the binding offsets at 16 bytes).
    const bool bindings_aligned = a.offset % 16 == 0 && b.offset % 16 == 0;
    if (s.b_transposed && bindings_aligned &&
        multiples_of_4({s.k, lda, ldb, s.a_offset, s.b_offset, s.a_batch_stride, s.b_batch_stride}))
      flags |= shader::kGemmVec4K;
    if (!s.b_transposed && bindings_aligned && multiples_of_4({s.n, ldb, s.b_offset, s.b_batch_stride}))
      flags |= shader::kGemmVec4N;
    groups = {groups_for(groups_for(s.n, 4), kGroupX), groups_for(groups_for(s.m, kGemmRows), kGroupY), s.batch};
  }
  const GemmPush push{s.m,
                      s.n,
                      s.k,
                      lda,
                      ldb,
                      ldc,
                      s.a_offset,
                      s.b_offset,
                      s.c_offset,
                      s.a_batch_stride,
                      s.b_batch_stride,
                      s.c_batch_stride,
                      flags,
                      s.alpha};
  seq.dispatch(*kernel, bindings, &push, sizeof(push), groups,
               label.empty() ? fmt::format("gemm {}x{}x{}", s.m, s.n, s.k) : std::move(label));
}

GemmShape conv1x1_gemm_shape(const ActivationShape& in, std::uint32_t out_channels, bool relu) {
  if (in.pad != 0) throw std::invalid_argument("conv1x1_gemm_shape: the input planes must have no border");
  const auto pixels = static_cast<std::uint32_t>(in.plane());
  return {.m = out_channels, .n = pixels, .k = in.channels, .b_transposed = false, .relu = relu, .bias_per_row = true};
}

}  // namespace vkvo::rt
