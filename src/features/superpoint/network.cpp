#include "features/superpoint/network.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "features/superpoint.hpp"
#include "runtime/context.hpp"
#include "runtime/half.hpp"
#include "runtime/push_constants.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::features {
namespace {

using shader::DetectorHeadPush;
using shader::ImageInputPush;
using shader::L2NormPush;
using shader::NmsColumnsPush;
using shader::NmsRowsPush;
using shader::RankPush;
using shader::SamplePush;

rt::Kernel rowmax_kernel(const rt::Context& ctx, bool texel) {
  // Bindings: 0 the map, 1 the row maxima.
  rt::KernelSpec s{.op = texel ? rt::Op::superpoint_nms_rowmax_tiled : rt::Op::superpoint_nms_rowmax};
  if (texel) s.texel_formats = {rt::vec4_texel_format(rt::Precision::fp32)};
  return rt::Kernel(ctx, std::move(s));
}

rt::Kernel colmax_kernel(const rt::Context& ctx, bool texel, std::uint32_t stage) {
  // Bindings: 0 rows, 1 scores, 2 max_mask, 3 supp_scores, 4 supp, 5 candidates, 6 counter.
  rt::KernelSpec s{.op = texel ? rt::Op::superpoint_nms_colmax_tiled : rt::Op::superpoint_nms_colmax,
                   .specialization = {stage}};
  if (texel) s.texel_formats = {rt::vec4_texel_format(rt::Precision::fp32), rt::vec4_texel_format(rt::Precision::fp32)};
  return rt::Kernel(ctx, std::move(s));
}

// The encoder: four levels of two 3x3 conv + ReLU, a 2x2 max-pool between levels.
constexpr SuperPointLayer kEncoderLevels[4][2] = {
    {conv1a, conv1b}, {conv2a, conv2b}, {conv3a, conv3b}, {conv4a, conv4b}};

SuperPointConv find_conv(const io::ModelPack& pack, SuperPointLayer layer, rt::Precision precision) {
  const SuperPointConvSpec& expected = kSuperPointArchitecture[layer];
  const io::DType dtype =
      rt::conv_weight_precision(precision) == rt::Precision::fp32 ? io::DType::fp32 : io::DType::fp16;
  const auto& w = pack.tensor(std::string(expected.name) + ".weight", dtype);
  const auto& b = pack.tensor(std::string(expected.name) + ".bias", io::DType::fp32);
  SuperPointConv conv{expected.name, expected.in, expected.out, expected.kernel,
                      w.offset,      w.byte_size, b.offset,     b.byte_size};
  // The descriptor dimension is the pack's (convDb's output width).
  if (layer == convDb && !w.shape.empty()) conv.out_channels = static_cast<std::uint32_t>(w.shape[0]);
  const std::vector<std::int64_t> want{conv.out_channels, conv.in_channels, conv.kernel, conv.kernel};
  if (w.shape != want || w.layout != "o4" || b.layout != "o4")
    throw std::runtime_error(fmt::format("model pack '{}': tensor {}.weight should be {} in layout o4, found {} in {}",
                                         pack.source(), expected.name, fmt::join(want, "x"), fmt::join(w.shape, "x"),
                                         w.layout));
  return conv;
}

}  // namespace

NmsKernels::NmsKernels(const rt::Context& ctx, bool texel)
    : rowmax(rowmax_kernel(ctx, texel)),
      colmax{colmax_kernel(ctx, texel, 0), colmax_kernel(ctx, texel, 1), colmax_kernel(ctx, texel, 2),
             colmax_kernel(ctx, texel, 3)} {}

SuperPointNetwork::SuperPointNetwork(const rt::Context& ctx, const io::ModelPack& pack, rt::Precision p, bool tiled,
                                     SuperPointParams::Winograd winograd_choice,
                                     rt::WinogradConv3x3::Tile winograd_tile)
    : precision(p),
      block(ctx, std::max<std::size_t>(pack.data_block().size(), 16), rt::BufferKind::device, "superpoint.weights"),
      conv3x3(ctx, p, 3, tiled ? rt::Conv3x3Kernel::automatic : rt::Conv3x3Kernel::direct),
      conv1x1(ctx, p, 1, tiled ? rt::Conv3x3Kernel::automatic : rt::Conv3x3Kernel::direct),
      input(ctx, {.op = rt::Op::superpoint_input, .precision = p}),
      detector_head(ctx, {.op = rt::Op::superpoint_detector_head, .precision = p}),
      l2norm(ctx, {.op = rt::Op::superpoint_l2norm, .precision = p}),
      rank(ctx, {.op = rt::Op::superpoint_rank}),
      sample(ctx, {.op = rt::Op::superpoint_sample}),
      nms(ctx, false),
      max_texel_elements(ctx.caps().max_texel_buffer_elements) {
  if (tiled && rt::tiled_kernels_available(ctx, p)) {
    detector_head_tiled.emplace(
        ctx, rt::KernelSpec{.op = rt::Op::superpoint_detector_head_tiled,
                            .precision = p,
                            .texel_formats = {rt::activation_texel_format(p), rt::conv_weight_texel_format(p)}});
    nms_tiled.emplace(ctx, true);
  }
  // On tensor cores conv*b runs as conv3x3_coopmat, then the pool: the fused pass is a SIMT kernel.
  if (tiled && rt::tiled_kernels_available(ctx, p) && !conv3x3.uses_cooperative_matrix())
    conv_pool.emplace(ctx, p);
  else
    pool.emplace(ctx, p);
  for (std::size_t i = 0; i < kSuperPointLayers; ++i) convs[i] = find_conv(pack, static_cast<SuperPointLayer>(i), p);
  block.upload(pack.data_block().data(), pack.data_block().size());

  // The input plane holds the pixel values 0-255, exact at every storage precision, and SuperPoint's 1/255 is
  // folded into conv1a's weights here: with 16-bit activations, pixel / 255 rounded to 16 bits costs the dense
  // scores more than twice the error of exact pixels (docs/performance-history.md, "SuperPoint").
  {
    const SuperPointConv& first = convs[conv1a];
    std::vector<float> w = pack.floats(first.name + ".weight", io::DType::fp32);
    for (float& v : w) v /= 255.0f;
    rescaled_weights.add(conv1a, rt::encode_storage(w, rt::conv_weight_precision(p)));
    rescaled_weights.upload(ctx, "superpoint.conv1a_weights");
  }

  // 1x1 layers as GEMMs where the device profile says (rt::conv1x1_gemm_shape): on CPU devices conv1x1_tiled.comp
  // reads one pixel per texel fetch, the tiled GEMM 4 (docs/performance-history.md, "SuperPoint"). The GEMM reads
  // the weights as an O x I matrix, so those layers get a row-major copy. Its two operands share one texel
  // format, so where the weights are stored wider than the activations (fp16s, rt::conv_weight_precision) the
  // 1x1 layers stay on the convolution kernels.
  // On tensor cores (rt::use_cooperative_matrix) they run as gemm_coopmat, which reads any operand layout and
  // rounds the weights to fp16 to multiply them anyway.
  const bool coopmat_gemm = tiled && rt::use_cooperative_matrix(ctx, p);
  if (coopmat_gemm || (tiled && rt::tiled_kernels_available(ctx, p) && ctx.profile().conv1x1_as_gemm &&
                       rt::conv_weight_precision(p) == p)) {
    for (std::size_t i = 0; i < kSuperPointLayers; ++i) {
      const SuperPointConv& c = convs[i];
      if (c.kernel != 1) continue;
      const auto o4 = pack.floats(c.name + ".weight", io::DType::fp32);
      conv1x1_matrices.add(static_cast<SuperPointLayer>(i),
                           rt::encode_storage(rt::unpack_conv_o4(o4, c.out_channels, c.in_channels, 1, 1), p));
    }
    conv1x1_matrices.upload(ctx, "superpoint.conv1x1_matrices");
    conv1x1_gemm.emplace(ctx, p);
  }

  // Winograd is fp32 only (runtime/winograd.hpp); `automatic` takes it where the device profile says (CPU devices;
  // GPUs run the direct kernels faster: docs/performance-history.md, "SuperPoint").
  const bool wanted = winograd_choice == SuperPointParams::Winograd::on ||
                      (winograd_choice == SuperPointParams::Winograd::automatic && ctx.profile().winograd);
  if (!wanted || p != rt::Precision::fp32 || !tiled || !rt::tiled_kernels_available(ctx, p)) return;
  winograd.emplace(ctx, p, winograd_tile);
  for (std::size_t i = 0; i < kSuperPointLayers; ++i) {
    const SuperPointConv& c = convs[i];
    if (c.kernel != 3 || c.in_channels % 4 != 0) continue;
    const auto u = rt::WinogradConv3x3::transform_weights(pack.floats(c.name + ".weight", io::DType::fp32),
                                                          c.out_channels, c.in_channels, winograd_tile);
    winograd_filters.add(static_cast<SuperPointLayer>(i), std::as_bytes(std::span<const float>(u)));
  }
  winograd_filters.upload(ctx, "superpoint.winograd_weights");
}

void DerivedLayerTensors::add(SuperPointLayer layer, std::span<const std::byte> bytes) {
  staged_.resize(rt::round_up(staged_.size(), 256));
  offset_[layer] = staged_.size();
  bytes_[layer] = bytes.size();
  staged_.insert(staged_.end(), bytes.begin(), bytes.end());
}

void DerivedLayerTensors::upload(const rt::Context& context, const std::string& name) {
  buffer_.emplace(context, std::max<std::size_t>(staged_.size(), 16), rt::BufferKind::device, name);
  buffer_->upload(staged_.data(), staged_.size());
  staged_ = {};
}

rt::Binding DerivedLayerTensors::binding(SuperPointLayer layer) const {
  if (!has(layer) || !buffer_) throw std::logic_error("DerivedLayerTensors: no uploaded tensor for this layer");
  return {*buffer_, offset_[layer], bytes_[layer]};
}

std::optional<rt::GemmShape> SuperPointNetwork::conv1x1_as_gemm(SuperPointLayer layer, const rt::Buffer& input,
                                                                const rt::ActivationShape& in, std::uint32_t out_pad,
                                                                bool relu) const {
  if (!conv1x1_gemm || !conv1x1_matrices.has(layer) || in.pad != 0 || out_pad != 0) return std::nullopt;
  const rt::GemmShape shape = rt::conv1x1_gemm_shape(in, convs[layer].out_channels, relu);
  if (!conv1x1_gemm->uses_cooperative_matrix() &&
      !conv1x1_gemm->uses_tiled_kernel(shape, conv1x1_matrices.binding(layer), rt::Binding(input)))
    return std::nullopt;
  return shape;
}

bool SuperPointNetwork::uses_winograd(SuperPointLayer layer, const rt::ActivationShape& in) const {
  return winograd && winograd_filters.has(layer) && winograd->supports(in, convs[layer].out_channels);
}

rt::Binding SuperPointNetwork::winograd_weights(SuperPointLayer layer) const { return winograd_filters.binding(layer); }

rt::Binding SuperPointNetwork::weights(SuperPointLayer layer) const {
  if (rescaled_weights.has(layer)) return rescaled_weights.binding(layer);
  return {block, convs[layer].weight_offset, convs[layer].weight_bytes};
}
rt::Binding SuperPointNetwork::bias(SuperPointLayer layer) const {
  return {block, convs[layer].bias_offset, convs[layer].bias_bytes};
}

SuperPointPlan::SuperPointPlan(const rt::Context& ctx, const SuperPointNetwork& net, const SuperPointParams& params,
                               int width, int height, bool profile)
    : context_(ctx),
      net_(net),
      width_(static_cast<std::uint32_t>(width)),
      height_(static_cast<std::uint32_t>(height)),
      cells_h_(height_ / 8),
      cells_w_(width_ / 8),
      dim_(net.convs[convDb].out_channels),
      radius_(static_cast<std::uint32_t>(params.nms_radius)),
      border_(static_cast<std::uint32_t>(std::max(params.remove_borders, 0))),
      threshold_(params.keypoint_threshold),
      subpixel_(params.subpixel),
      image_(ctx, rt::round_up(std::size_t(width_) * height_, 4), rt::BufferKind::staging, "superpoint.image"),
      dense_scores_(ctx, std::size_t(cells_h_) * cells_w_ * 64 * 4, rt::BufferKind::device, "superpoint.dense_scores"),
      rows_(ctx, dense_scores_.size(), rt::BufferKind::device, "superpoint.nms_rows"),
      mask_(ctx, dense_scores_.size(), rt::BufferKind::device, "superpoint.nms_mask"),
      supp_scores_(ctx, dense_scores_.size(), rt::BufferKind::device, "superpoint.nms_supp_scores"),
      supp_(ctx, dense_scores_.size(), rt::BufferKind::device, "superpoint.nms_supp"),
      candidates_(ctx, 16, rt::BufferKind::device, "superpoint.candidates"),
      counter_(ctx, 16, rt::BufferKind::device, "superpoint.counter"),
      order_(ctx, 16, rt::BufferKind::device, "superpoint.order"),
      dense_descriptors_(ctx, std::size_t(dim_) * cells_h_ * cells_w_ * 4, rt::BufferKind::device,
                         "superpoint.dense_descriptors"),
      keypoints_(ctx, 16, rt::BufferKind::device, "superpoint.keypoints"),
      scores_(ctx, 16, rt::BufferKind::device, "superpoint.scores"),
      descriptors_(ctx, 16, rt::BufferKind::device, "superpoint.descriptors"),
      seq_(ctx, profile ? 512 : 0) {
  // NMS maxima closer than r+1 pixels need exactly equal scores, so (r+1)^2 pixels per candidate is a safe
  // bound in practice; an overflow is reported by keypoint_count().
  const std::size_t pixels = std::size_t(cells_h_) * cells_w_ * 64;
  capacity_ = static_cast<std::uint32_t>(std::min(pixels, pixels / ((radius_ + 1) * (radius_ + 1)) + 4096));
  // One sampling workgroup per keypoint: at most 65535 (the guaranteed maxComputeWorkGroupCount).
  max_keypoints_ = std::min<std::uint32_t>(
      params.max_keypoints > 0 ? std::min<std::uint32_t>(params.max_keypoints, capacity_) : capacity_, 65535u);
  candidates_ = rt::Buffer(ctx, std::size_t(capacity_) * 8, rt::BufferKind::device, "superpoint.candidates");
  order_ = rt::Buffer(ctx, std::size_t(max_keypoints_) * 4, rt::BufferKind::device, "superpoint.order");
  keypoints_ = rt::Buffer(ctx, std::size_t(max_keypoints_) * 8, rt::BufferKind::device, "superpoint.keypoints");
  scores_ = rt::Buffer(ctx, std::size_t(max_keypoints_) * 4, rt::BufferKind::device, "superpoint.scores");
  descriptors_ =
      rt::Buffer(ctx, std::size_t(max_keypoints_) * dim_ * 4, rt::BufferKind::device, "superpoint.descriptors");
  image_.fill_zero();
  counter_out_.emplace(ctx, counter_);
  keypoints_out_.emplace(ctx, keypoints_);
  scores_out_.emplace(ctx, scores_);
  descriptors_out_.emplace(ctx, descriptors_);
  allocate_winograd_scratch();
  record();
}

void SuperPointPlan::allocate_winograd_scratch() {
  if (!net_.winograd) return;
  // Walk the layers' input shapes as record() does; one pair of buffers serves every Winograd layer.
  std::size_t input_bytes = 0, products_bytes = 0;
  const auto need = [&](SuperPointLayer layer, std::uint32_t height, std::uint32_t width) {
    const rt::ActivationShape in{net_.convs[layer].in_channels, height, width, 1};
    if (!net_.uses_winograd(layer, in)) return;
    const std::uint32_t out_channels = net_.convs[layer].out_channels;
    input_bytes = std::max(input_bytes, net_.winograd->transformed_input_bytes(in, out_channels));
    products_bytes = std::max(products_bytes, net_.winograd->products_bytes(in, out_channels));
  };
  std::uint32_t height = height_, width = width_;
  for (int level = 0; level < 4; ++level) {
    need(kEncoderLevels[level][0], height, width);
    need(kEncoderLevels[level][1], height, width);
    if (level < 3) height /= 2, width /= 2;
  }
  need(convPa, height, width);
  need(convDa, height, width);
  if (input_bytes == 0) return;
  winograd_input_.emplace(context_, input_bytes, rt::BufferKind::device, "superpoint.winograd_input");
  winograd_products_.emplace(context_, products_bytes, rt::BufferKind::device, "superpoint.winograd_products");
}

rt::Buffer& SuperPointPlan::activation(const rt::ActivationShape& shape, const std::string& name) {
  activations_.emplace_back(context_, rt::activation_bytes(shape, net_.precision), rt::BufferKind::device,
                            "superpoint." + name);
  activations_.back().fill_zero();  // the zero border is never written by the kernels
  return activations_.back();
}

void SuperPointPlan::record() {
  seq_.begin();
  seq_.fill_zero(counter_, "clear counter");

  rt::ActivationShape shape{1, height_, width_, 1};
  const rt::Buffer* x = &activation(shape, "input");
  seq_.dispatch(net_.input, {image_, *x}, ImageInputPush{width_, height_},
                {rt::groups_for(std::size_t(width_) * height_, 64)}, "input");

  // Encoder: four levels of two 3x3 conv + ReLU, a 2x2 max-pool between levels.
  const auto conv = [&](SuperPointLayer layer, const rt::Buffer& in, const rt::ActivationShape& in_shape,
                        std::uint32_t out_pad, bool relu) -> std::pair<const rt::Buffer*, rt::ActivationShape> {
    const auto& c = net_.convs[layer];
    const rt::ActivationShape out{c.out_channels, in_shape.height, in_shape.width, out_pad};
    rt::Buffer& buffer = activation(out, c.name);
    if (net_.uses_winograd(layer, in_shape)) {
      net_.winograd->record(seq_, in, in_shape, net_.winograd_weights(layer), net_.bias(layer), *winograd_input_,
                            *winograd_products_, buffer, out, relu, false, c.name);
    } else if (const auto gemm = net_.conv1x1_as_gemm(layer, in, in_shape, out_pad, relu)) {
      const rt::Binding bias = net_.bias(layer);
      net_.conv1x1_gemm->record(seq_, net_.conv1x1_matrices.binding(layer), rt::Binding(in), &bias, rt::Binding(buffer),
                                *gemm, c.name + " gemm");
    } else {
      const rt::Conv2d& op = c.kernel == 3 ? net_.conv3x3 : net_.conv1x1;
      op.record(seq_, in, in_shape, net_.weights(layer), net_.bias(layer), buffer, out, relu, c.name);
    }
    return {&buffer, out};
  };
  const auto& levels = kEncoderLevels;
  for (int level = 0; level < 4; ++level) {
    // Where conv1b runs as Winograd, conv1a (1 -> 64 channels) is computed inside its input transform: the
    // full-resolution 64-channel activation is never stored nor read back.
    const SuperPointConv& first = net_.convs[levels[level][0]];
    const rt::ActivationShape first_out{first.out_channels, shape.height, shape.width, 1};
    const bool stem =
        level == 0 && first.kernel == 3 && first.in_channels == 1 && net_.uses_winograd(levels[level][1], first_out);
    const auto [a, a_shape] = stem ? std::pair{x, first_out} : conv(levels[level][0], *x, shape, 1, true);
    if (level == 3) {
      std::tie(x, shape) = conv(levels[level][1], *a, a_shape, 1, true);
      break;
    }
    const rt::ActivationShape pooled_shape{net_.convs[levels[level][1]].out_channels, a_shape.height / 2,
                                           a_shape.width / 2, 1};
    rt::Buffer& pooled = activation(pooled_shape, fmt::format("pool{}", level + 1));
    const SuperPointLayer pooled_layer = levels[level][1];
    const std::string pooled_label = fmt::format("{}+pool{}", net_.convs[pooled_layer].name, level + 1);
    if (net_.uses_winograd(pooled_layer, a_shape)) {  // pooled in the output transform
      const rt::WinogradConv3x3::Stem first_conv{net_.weights(levels[level][0]), net_.bias(levels[level][0])};
      net_.winograd->record(seq_, *a, a_shape, net_.winograd_weights(pooled_layer), net_.bias(pooled_layer),
                            *winograd_input_, *winograd_products_, pooled, pooled_shape, true, true, pooled_label,
                            stem ? &first_conv : nullptr);
    } else if (net_.conv_pool) {  // one pass; the full-resolution conv*b output is never stored
      net_.conv_pool->record(seq_, *a, a_shape, net_.weights(pooled_layer), net_.bias(pooled_layer), pooled,
                             pooled_shape, true, pooled_label);
    } else {
      const auto [b, b_shape] = conv(pooled_layer, *a, a_shape, 0, true);
      net_.pool->record(seq_, *b, b_shape, pooled, 1, fmt::format("pool{}", level + 1));
    }
    x = &pooled;
    shape = pooled_shape;
  }

  // Detector head: convPa + ReLU, then convPb + softmax + depth-to-space in one kernel.
  const auto [pa, pa_shape] = conv(convPa, *x, shape, 0, true);
  const std::uint32_t cells = cells_h_ * cells_w_;
  // The tiled head computes 4 cells per invocation and steps 4 input channels at a time.
  const DetectorHeadPush head{pa_shape.channels, cells_h_, cells_w_};
  const bool tiled_head =
      net_.detector_head_tiled && pa_shape.channels % 4 == 0 && pa_shape.elements() <= net_.max_texel_elements;
  seq_.dispatch(tiled_head ? *net_.detector_head_tiled : net_.detector_head,
                {*pa, net_.weights(convPb), net_.bias(convPb), dense_scores_}, head,
                {rt::groups_for(cells, tiled_head ? 4 * 64 : 64)}, "convPb+softmax");
  // Descriptor head: convDa + ReLU, convDb, L2 normalisation.
  const auto [da, da_shape] = conv(convDa, *x, shape, 0, true);
  const auto [db, db_shape] = conv(convDb, *da, da_shape, 0, false);
  seq_.dispatch(net_.l2norm, {*db, dense_descriptors_}, L2NormPush{db_shape.channels, cells},
                {rt::groups_for(cells, 64)}, "descriptor l2norm");

  // NMS (two suppression rounds), selection, top-k, sampling. 4 pixels per invocation: w8 is a multiple of 8.
  const std::uint32_t w8 = cells_w_ * 8, h8 = cells_h_ * 8;
  const std::size_t map_vec4s = std::size_t(w8) * h8 / 4;
  const NmsKernels& nms = net_.nms_tiled && map_vec4s <= net_.max_texel_elements ? *net_.nms_tiled : net_.nms;
  const rt::Groups pixel_groups{rt::groups_for(map_vec4s, 64)};
  const NmsRowsPush row_push{w8, h8, radius_};
  const NmsColumnsPush col_push{w8, h8, radius_, border_, threshold_, capacity_};
  const auto colmax = [&](int stage, const char* label) {
    seq_.dispatch(nms.colmax[stage], {rows_, dense_scores_, mask_, supp_scores_, supp_, candidates_, counter_},
                  col_push, pixel_groups, label);
  };
  seq_.dispatch(nms.rowmax, {dense_scores_, rows_}, row_push, pixel_groups, "nms rows(scores)");
  colmax(0, "nms max mask");
  for (int round = 0; round < 2; ++round) {
    seq_.dispatch(nms.rowmax, {mask_, rows_}, row_push, pixel_groups, "nms rows(mask)");
    colmax(1, "nms suppress");
    seq_.dispatch(nms.rowmax, {supp_scores_, rows_}, row_push, pixel_groups, "nms rows(supp scores)");
    colmax(round == 0 ? 2 : 3, round == 0 ? "nms update" : "nms update+select");
  }
  seq_.dispatch(net_.rank, {candidates_, counter_, order_}, RankPush{capacity_, max_keypoints_},
                {rt::groups_for(capacity_, 64)}, "top-k rank");
  seq_.dispatch(net_.sample,
                {candidates_, counter_, order_, dense_scores_, dense_descriptors_, keypoints_, scores_, descriptors_},
                SamplePush{cells_h_, cells_w_, dim_, capacity_, max_keypoints_, subpixel_ ? 1u : 0u}, {max_keypoints_},
                "sample descriptors");
  for (const auto* out : {&*counter_out_, &*keypoints_out_, &*scores_out_, &*descriptors_out_}) out->record(seq_);
  seq_.end();
}

std::uint32_t SuperPointPlan::run(const std::uint8_t* pixels, std::size_t stride) {
  if (stride == width_) {
    image_.upload(pixels, std::size_t(width_) * height_);
  } else {
    for (std::uint32_t y = 0; y < height_; ++y) image_.upload(pixels + y * stride, width_, std::size_t(y) * width_);
  }
  seq_.submit();
  return counter_out_->read<std::uint32_t>(1)[0];
}

std::uint32_t SuperPointPlan::keypoint_count(std::uint32_t candidates) const {
  if (candidates > capacity_)
    spdlog::warn("SuperPoint: {} NMS candidates exceed the list capacity {}; the weakest may be missing", candidates,
                 capacity_);
  return std::min({candidates, capacity_, max_keypoints_});
}

void SuperPointPlan::download(std::uint32_t count, std::vector<float>& keypoints_xy, std::vector<float>& scores,
                              std::vector<float>& descriptors) const {
  keypoints_xy.clear();
  scores.clear();
  descriptors.clear();
  if (count == 0) return;
  keypoints_xy = keypoints_out_->read<float>(std::size_t(count) * 2);
  scores = scores_out_->read<float>(count);
  descriptors = descriptors_out_->read<float>(std::size_t(count) * dim_);
}

void SuperPointPlan::download_dense(std::vector<float>& scores, std::vector<float>& descriptors) const {
  scores = dense_scores_.download<float>(std::size_t(cells_h_) * cells_w_ * 64);
  descriptors = dense_descriptors_.download<float>(std::size_t(dim_) * cells_h_ * cells_w_);
}

}  // namespace vkvo::features
