#pragma once
// Host side of the generic neural-network kernels in shaders/: each op owns its pipeline and records one
// dispatch into a Sequence. Activations are CHW planes with an optional zero border (shaders/include/tensor.glsl).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "runtime/buffer.hpp"
#include "runtime/kernel.hpp"
#include "runtime/sequence.hpp"

namespace vkvo::rt {

// A bordered tensor's rows are padded to a multiple of 4 elements (the tiled 3x3 convolution reads 4 pixels per
// texel from rows that start on a texel); an unbordered tensor is dense CHW.
struct ActivationShape {
  std::uint32_t channels = 0, height = 0, width = 0, pad = 0;
  std::size_t row_stride() const { return pad > 0 ? (std::size_t(width) + 2 * pad + 3) / 4 * 4 : width; }
  std::size_t plane() const { return (std::size_t(height) + 2 * pad) * row_stride(); }
  std::size_t elements() const { return std::size_t(channels) * plane(); }
  // Element index of (c, y, x), x and y without the border.
  std::size_t index(std::uint32_t c, std::uint32_t y, std::uint32_t x) const {
    return c * plane() + (std::size_t(y) + pad) * row_stride() + x + pad;
  }
};

// Texel formats of the tiled kernels at a storage precision: one activation value per texel (conv1x1_tiled,
// superpoint_detector_head_tiled), and 4 values per texel (weights; conv3x3_tiled's input rows).
vk::Format activation_texel_format(Precision precision);
vk::Format vec4_texel_format(Precision precision);
// 16-byte texels packed as full as the storage precision allows (shaders/include/packed_texel.glsl): 4 fp32
// values per RGBA32F texel, 8 halves per RGBA32UI texel. The tiled GEMMs' operands, SuperGlue's fused attention.
vk::Format packed_texel_format(Precision precision);
std::uint32_t values_per_packed_texel(Precision precision);
inline constexpr std::size_t kPackedTexelBytes = 16;

// Storage precision of convolution weights (Conv2d, Conv3x3MaxPool) for activations stored at `activations`:
// fp32 for the 16-bit-storage variant (fp16s), which keeps only the activations in 16 bits. SuperPoint's dense
// scores are far more sensitive to rounded weights than to rounded activations (docs/performance-history.md,
// "Precision"); the weights are a few MB, the activations are what 16 bits save bandwidth on. fp16 math (fp16)
// rounds the weights to multiply them in 16 bits anyway, so it keeps them in 16 bits.
Precision conv_weight_precision(Precision activations);
// The texel format the tiled convolutions read those weights through (4 output channels per texel).
vk::Format conv_weight_texel_format(Precision activations);

// Bytes of a buffer holding `shape` at `precision`.
std::size_t activation_bytes(const ActivationShape& shape, Precision precision);

// 3x3 (stride 1, pad 1; input must carry a 1-pixel zero border) or 1x1 convolution + bias (+ ReLU).
// Weights in the "o4" layout (runtime/tensor_layout.hpp) at conv_weight_precision(precision); bias fp32, padded
// to 4.
// Weights and bias may be ranges of one buffer (e.g. a model pack's data block bound at each tensor's offset).
// Which shader runs a 3x3 convolution: `tiled` (conv3x3_tiled.comp: 8 output channels x 4 pixels x 3 rows per
// invocation, operands read through texel buffers) where the device reads the texel formats it needs
// (tiled_kernels_available), else `direct` (conv3x3.comp: 4 x 3, storage-buffer loads). Both read the same
// weight layout. `direct` also keeps 1x1 convolutions on conv1x1.comp. `cooperative_matrix` (conv3x3_coopmat.comp:
// an implicit GEMM on tensor cores, fp16 x fp16 -> fp32) is what `automatic` runs at the 16-bit storage precisions
// where DeviceProfile::cooperative_matrix (uses_cooperative_matrix).
enum class Conv3x3Kernel { automatic, direct, tiled, cooperative_matrix };

// Whether `automatic` runs the tensor-core kernels for operands stored at `precision` on this device: the profile's
// cooperative_matrix, at fp16s or fp16 (they round their operands to fp16, which fp32 is asked for to avoid).
bool use_cooperative_matrix(const Context& context, Precision precision);

// Whether the device reads the uniform texel buffer formats of the tiled convolution and GEMM kernels at this
// storage precision (one activation value per texel, 4 weights per texel, 4 fp32 or 8 fp16 GEMM operands).
bool tiled_kernels_available(const Context& context, Precision precision);

class Conv2d {
 public:
  Conv2d(const Context& context, Precision precision, std::uint32_t kernel_size,
         Conv3x3Kernel choice = Conv3x3Kernel::automatic);
  // 3x3: whether conv3x3_tiled.comp runs. 1x1 runs conv1x1_tiled.comp (8 output channels x 8 pixels,
  // weights broadcast, input through a texel buffer) where the device can and the input has a multiple of 4
  // channels, else conv1x1.comp: uses_tiled_kernel(in) says which for an input.
  bool uses_tiled_kernel() const { return tiled_; }
  bool uses_tiled_kernel(const ActivationShape& in) const;
  // 3x3: whether conv3x3_coopmat.comp runs (tensor cores).
  bool uses_cooperative_matrix() const { return coopmat_.has_value(); }
  void record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
              const Binding& bias, const Buffer& output, const ActivationShape& out, bool relu,
              std::string label = {}) const;
  static double flops(const ActivationShape& in, std::uint32_t out_channels, std::uint32_t kernel_size) {
    return 2.0 * in.height * in.width * in.channels * out_channels * kernel_size * kernel_size;
  }

 private:
  std::uint32_t kernel_size_;
  bool tiled_;
  std::size_t max_texel_elements_;
  Kernel kernel_;
  std::optional<Kernel> tiled_1x1_;
  std::optional<Kernel> coopmat_;
};

// 3x3 convolution + bias (+ ReLU) followed by a 2x2 max-pool (floor semantics), in one pass
// (conv3x3_maxpool_tiled.comp): the full-resolution output is never stored. Needs the tiled kernels' texel
// formats (tiled_kernels_available); elsewhere run Conv2d and MaxPool2x2.
class Conv3x3MaxPool {
 public:
  Conv3x3MaxPool(const Context& context, Precision precision);
  // `in`: the convolution's input (1-pixel border); `out`: the pooled output, in.height / 2 x in.width / 2.
  void record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Binding& weights,
              const Binding& bias, const Buffer& output, const ActivationShape& out, bool relu,
              std::string label = {}) const;

 private:
  std::size_t max_texel_elements_;
  Kernel kernel_;
};

// 2x2 max-pool, stride 2, floor semantics.
class MaxPool2x2 {
 public:
  MaxPool2x2(const Context& context, Precision precision);
  void record(Sequence& seq, const Buffer& input, const ActivationShape& in, const Buffer& output,
              std::uint32_t out_pad, std::string label = {}) const;

 private:
  Kernel kernel_;
};

// C(MxN) = alpha * A(MxK) * op(B) + bias (+ C) (+ ReLU); op(B) = B (K x N) or B^T (B stored N x K). Row-major.
// Leading dimensions (0: dense), element offsets and a batch of `batch` problems whose operands advance by
// fixed element strides let one dispatch work on column blocks of wider matrices (attention heads, [x | msg]).
struct GemmShape {
  std::uint32_t m = 0, n = 0, k = 0;
  bool b_transposed = false;
  bool relu = false;
  float alpha = 1.0f;
  bool accumulate = false;    // C += result (residual connections); ReLU, if any, applies to the sum
  bool bias_per_row = false;  // the bias holds one value per row of C (M), e.g. a 1x1 convolution's per channel
  std::uint32_t lda = 0, ldb = 0, ldc = 0;
  std::uint32_t a_offset = 0, b_offset = 0, c_offset = 0;
  std::uint32_t batch = 1;
  std::uint32_t a_batch_stride = 0, b_batch_stride = 0, c_batch_stride = 0;
};

// `tiled` (gemm_tiled.comp: 4 x 8 blocks of C, operands read through texel buffers of 4 fp32 or 8 fp16
// elements) serves the calls whose operands are aligned to whole texels (uses_tiled_kernel) where the device
// reads the texel format; `direct` (gemm.comp) serves every other call and device. `tiled_wide`
// (gemm_tiled_wide) is the same with 8 x 16 blocks, which `automatic` picks where DeviceProfile::wide_gemm_tile.
// `cooperative_matrix` (gemm_coopmat.comp: 64 x 64 blocks on tensor cores, fp16 x fp16 -> fp32, any alignment)
// serves every call; `automatic` picks it where use_cooperative_matrix.
enum class GemmKernel { automatic, direct, tiled, tiled_wide, cooperative_matrix };

// Rows and columns of C per invocation of the tiled kernel; a workgroup spans `cols` columns.
struct TiledGemmTile {
  std::uint32_t rows = 4, cols = 8;
};

class Gemm {
 public:
  Gemm(const Context& context, Precision precision, GemmKernel choice = GemmKernel::automatic);
  Gemm(Gemm&&) noexcept;
  ~Gemm();
  // Whether a call with this shape and these bindings runs the tiled kernel.
  bool uses_tiled_kernel(const GemmShape& shape, const Binding& a, const Binding& b) const;
  // Whether every call runs gemm_coopmat.comp (tensor cores).
  bool uses_cooperative_matrix() const { return coopmat_.has_value(); }
  // `bias` (N floats, fp32; M with GemmShape::bias_per_row) may be null.
  void record(Sequence& seq, const Buffer& a, const Buffer& b, const Buffer* bias, const Buffer& c,
              const GemmShape& shape, std::string label = {}) const;
  // Same with the bias bound at a byte offset of a larger buffer (weights of a model pack uploaded as one block).
  void record(Sequence& seq, const Binding& a, const Binding& b, const Binding* bias, const Binding& c,
              const GemmShape& shape, std::string label = {}) const;
  static double flops(const GemmShape& s) { return 2.0 * s.m * s.n * s.k * s.batch; }
  // The tile of the tiled kernel this Gemm runs (meaningful where it has one).
  TiledGemmTile tiled_tile() const { return tile_; }

 private:
  // gemm_tiled.comp (or gemm_tiled_wide.comp) specialised for one epilogue: C stored a whole vec4 at a time or
  // one element at a time, C accumulated or not, bias none / per column / per row. Built at the first call that
  // needs it (12 possible; SuperPoint's Winograd GEMMs use one), shared by all threads.
  struct TiledVariants;
  const Kernel& tiled_kernel(bool vec4_store, bool accumulate, std::uint32_t bias_per) const;

  Kernel kernel_;
  std::optional<Kernel> coopmat_;
  std::unique_ptr<TiledVariants> tiled_;  // null where the device cannot read the operands as texels
  TiledGemmTile tile_;
  std::size_t max_texel_elements_;
  std::uint32_t elements_per_texel_;  // of gemm_tiled.comp's operand views
  Buffer dummy_bias_;
};

// A 1x1 convolution (+ bias per output channel, + ReLU) on planes without a border, as one GEMM over the planes:
// out (O x H*W) = W (O x I) * in (I x H*W) + bias, with W row-major (unpack_conv_o4 of the layer's weights) as A,
// the input as B and the output as C. conv1x1_tiled.comp reads one pixel per texel fetch; the tiled GEMM reads 4
// and fetches fewer texels per multiply-add (SuperPoint uses it for convDb on CPU devices).
GemmShape conv1x1_gemm_shape(const ActivationShape& in, std::uint32_t out_channels, bool relu);

}  // namespace vkvo::rt
