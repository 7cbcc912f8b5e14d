#pragma once
// Internals of features::SuperPoint: the uploaded weights, the pipelines of every op, and the per-image-size plan
// (activation buffers + the recorded sequence).
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "features/superpoint.hpp"
#include "features/superpoint/architecture.hpp"
#include "io/model_pack.hpp"
#include "runtime/buffer.hpp"
#include "runtime/host_transfer.hpp"
#include "runtime/kernel.hpp"
#include "runtime/ops.hpp"
#include "runtime/sequence.hpp"
#include "runtime/winograd.hpp"

namespace vkvo::features {

// One convolution of the pack: its tensors are ranges of the uploaded data block.
struct SuperPointConv {
  std::string name;
  std::uint32_t in_channels = 0, out_channels = 0, kernel = 0;
  std::size_t weight_offset = 0, weight_bytes = 0, bias_offset = 0, bias_bytes = 0;
};

// NMS's separable max-pool passes (shaders/superpoint_nms_*.comp): the row half, and the column half fused with
// the suppression steps, stages 0..3.
struct NmsKernels {
  // `texel`: read the maps through RGBA32F texel views (the _tiled shaders) instead of storage buffers.
  NmsKernels(const rt::Context& context, bool texel);
  rt::Kernel rowmax;
  std::array<rt::Kernel, 4> colmax;
};

// Tensors derived from the pack when it is loaded, at most one per layer (Winograd filters, 1x1 weight matrices,
// conv1a's rescaled weights), in one device buffer at 256-byte aligned offsets (texel views start there).
class DerivedLayerTensors {
 public:
  void add(SuperPointLayer layer, std::span<const std::byte> bytes);
  // After the last add(): creates the buffer and uploads what was added.
  void upload(const rt::Context& context, const std::string& name);
  bool has(SuperPointLayer layer) const { return bytes_[layer] > 0; }
  rt::Binding binding(SuperPointLayer layer) const;

 private:
  std::vector<std::byte> staged_;
  std::optional<rt::Buffer> buffer_;
  std::array<std::size_t, kSuperPointLayers> offset_{}, bytes_{};
};

struct SuperPointNetwork {
  // `tiled`: use the texel-buffer kernels where the device reads their formats (SuperPointParams::tiled_kernels).
  SuperPointNetwork(const rt::Context& context, const io::ModelPack& pack, rt::Precision precision, bool tiled,
                    SuperPointParams::Winograd winograd, rt::WinogradConv3x3::Tile winograd_tile);

  rt::Binding weights(SuperPointLayer layer) const;
  rt::Binding bias(SuperPointLayer layer) const;
  // Whether `layer` runs as a Winograd convolution on an input of `in`, and its transformed weights.
  bool uses_winograd(SuperPointLayer layer, const rt::ActivationShape& in) const;
  // The GEMM that computes 1x1 `layer` on `input` (shape `in`), where it runs as one (conv1x1_gemm below).
  std::optional<rt::GemmShape> conv1x1_as_gemm(SuperPointLayer layer, const rt::Buffer& input,
                                               const rt::ActivationShape& in, std::uint32_t out_pad, bool relu) const;
  rt::Binding winograd_weights(SuperPointLayer layer) const;

  rt::Precision precision;
  std::array<SuperPointConv, kSuperPointLayers> convs;
  rt::Buffer block;  // the pack's whole data block
  // conv1a's weights / 255 (the input plane holds pixel values 0-255), at rt::conv_weight_precision.
  DerivedLayerTensors rescaled_weights;
  rt::Conv2d conv3x3, conv1x1;
  rt::Kernel input, detector_head, l2norm, rank, sample;
  NmsKernels nms;
  // Where the device reads the tiled kernels' texel formats: the detector head, and conv*b fused with the pool;
  // elsewhere conv*b is followed by `pool`. Exactly one of conv_pool and pool is set.
  std::optional<rt::Kernel> detector_head_tiled;
  std::optional<rt::Conv3x3MaxPool> conv_pool;
  std::optional<rt::MaxPool2x2> pool;
  // Set with the tiled kernels; used for maps of at most max_texel_elements vec4s.
  std::optional<NmsKernels> nms_tiled;
  std::size_t max_texel_elements;
  // Set where Winograd runs (SuperPointParams::winograd): the op, and the transformed weights of the 3x3 layers
  // it can take.
  std::optional<rt::WinogradConv3x3> winograd;
  DerivedLayerTensors winograd_filters;
  // Set on CPU devices with the tiled kernels, and on tensor cores: the GEMM that runs the 1x1 layers on borderless
  // planes, and their weights as O x I matrices at the storage precision.
  std::optional<rt::Gemm> conv1x1_gemm;
  DerivedLayerTensors conv1x1_matrices;
};

// Buffers and the recorded sequence for one image size.
class SuperPointPlan {
 public:
  // `profile`: a GPU timestamp after every command (SuperPoint::set_profiling).
  SuperPointPlan(const rt::Context& context, const SuperPointNetwork& net, const SuperPointParams& params, int width,
                 int height, bool profile);

  // Writes the image (CV_8UC1 data, `stride` bytes per row) into mapped memory, submits the sequence (the one
  // submission of a call: it also copies the outputs below to the host where the device does not map them),
  // returns the number of NMS candidates.
  std::uint32_t run(const std::uint8_t* pixels, std::size_t stride);
  // Number of keypoints the last run produced, and its outputs.
  std::uint32_t keypoint_count(std::uint32_t candidates) const;
  void download(std::uint32_t count, std::vector<float>& keypoints_xy, std::vector<float>& scores,
                std::vector<float>& descriptors) const;
  // The dense maps, on request (SuperPoint::detect's `dense`): a transfer of their own.
  void download_dense(std::vector<float>& scores, std::vector<float>& descriptors) const;

  const rt::Sequence& sequence() const { return seq_; }
  std::uint32_t cells_h() const { return cells_h_; }
  std::uint32_t cells_w() const { return cells_w_; }

 private:
  rt::Buffer& activation(const rt::ActivationShape& shape, const std::string& name);
  void allocate_winograd_scratch();
  void record();

  const rt::Context& context_;
  const SuperPointNetwork& net_;
  std::uint32_t width_, height_, cells_h_, cells_w_, dim_;
  std::uint32_t radius_, border_, capacity_, max_keypoints_;
  float threshold_;
  bool subpixel_;
  std::deque<rt::Buffer> activations_;  // a deque: record() holds references to earlier ones as it adds more
  rt::Buffer image_, dense_scores_, rows_, mask_, supp_scores_, supp_, candidates_, counter_, order_;
  rt::Buffer dense_descriptors_, keypoints_, scores_, descriptors_;
  // The host's view of the counter and the outputs, copied by the sequence where they are not mapped.
  std::optional<rt::HostOutput> counter_out_, keypoints_out_, scores_out_, descriptors_out_;
  // Scratch of the Winograd layers (transformed input, GEMM products), sized for the largest; empty without.
  std::optional<rt::Buffer> winograd_input_, winograd_products_;
  rt::Sequence seq_;
};

}  // namespace vkvo::features
