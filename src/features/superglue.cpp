#include "features/superglue.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "features/superglue/weights.hpp"
#include "io/config.hpp"
#include "runtime/buffer.hpp"
#include "runtime/half.hpp"
#include "runtime/host_transfer.hpp"
#include "runtime/kernel.hpp"
#include "runtime/ops.hpp"
#include "runtime/push_constants.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::features {
namespace {

// Query rows per invocation of superglue_attention_tiled.comp: the caller's choice, else the device profile's.
std::uint32_t attention_rows(const rt::Context& context, int chosen) {
  if (chosen < 0 || chosen > 16)
    throw std::invalid_argument(fmt::format("SuperGlue: attention_rows must be 0 (automatic) to 16, got {}", chosen));
  return chosen > 0 ? static_cast<std::uint32_t>(chosen) : context.profile().attention_rows;
}

// Shared memory of superglue_attention_shared.comp (its tile sizes): the key tile with a spare vec4 per row, the
// value tile, and 16 rows x 33 scores.
std::size_t shared_attention_bytes(std::uint32_t head_dim) {
  constexpr std::size_t kTileKeys = 32, kRows = 16, kVec4 = 16;
  const std::size_t head_vec4 = head_dim / 4;
  return kTileKeys * (head_vec4 + 1) * kVec4 + kTileKeys * head_vec4 * kVec4 + kRows * (kTileKeys + 1) * 4;
}

}  // namespace

SuperGlueParams load_superglue_params(const YAML::Node& section) {
  SuperGlueParams params;
  if (!section || section.IsNull()) return params;
  if (!section.IsMap()) throw std::runtime_error("config section 'point_matcher': expected a map");
  io::read_param(section, "match_threshold", params.match_threshold);
  io::read_param(section, "sinkhorn_iterations", params.sinkhorn_iterations);
  std::string precision = "auto";
  io::read_param(section, "precision", precision);
  if (precision != "auto") {
    params.precision = rt::parse_precision(precision);
    if (!params.precision)
      throw std::runtime_error(
          fmt::format("config key 'point_matcher.precision': expected auto, fp32, fp16s or fp16, got '{}'", precision));
  }
  return params;
}

SuperGlueConfig read_superglue_config(const io::ModelPack& pack) {
  SuperGlueConfig c;
  c.descriptor_dim = int(pack.integer("descriptor_dim"));
  c.heads = int(pack.integer("heads"));
  for (double w : pack.numbers("keypoint_encoder")) c.encoder_widths.push_back(int(w));
  const int layers = int(pack.integer("gnn_layers"));
  std::stringstream types(pack.string("gnn_layer_types"));
  for (std::string t; std::getline(types, t, ',');) {
    if (t != "self" && t != "cross")
      throw std::runtime_error(fmt::format("model pack '{}': unknown GNN layer type '{}'", pack.source(), t));
    c.cross_layers.push_back(t == "cross");
  }
  if (int(c.cross_layers.size()) != layers)
    throw std::runtime_error(fmt::format("model pack '{}': gnn_layers = {} but {} layer types", pack.source(), layers,
                                         c.cross_layers.size()));
  c.bin_score = float(pack.number("bin_score"));
  if (pack.has("sinkhorn_iterations")) c.sinkhorn_iterations = int(pack.integer("sinkhorn_iterations"));
  if (pack.has("attention_channel_order") && pack.string("attention_channel_order") != "dim_major")
    throw std::runtime_error(
        fmt::format("model pack '{}': attention_channel_order '{}' is not supported "
                    "(expected dim_major)",
                    pack.source(), pack.string("attention_channel_order")));
  if (c.descriptor_dim <= 0 || c.heads <= 0 || c.descriptor_dim % c.heads != 0)
    throw std::runtime_error(fmt::format("model pack '{}': descriptor_dim {} is not a multiple of heads {}",
                                         pack.source(), c.descriptor_dim, c.heads));
  return c;
}

// ---------------------------------------------------------------------------------------------------------------

struct SuperGlue::Impl {
  using Layer = PreparedLinear;
  using GnnLayer = SuperGlueWeights::GnnLayer;

  const rt::Context& context;
  SuperGlueParams params;
  SuperGlueConfig config;
  rt::Precision precision;
  int iterations = 100;

  std::vector<Layer> encoder;
  std::vector<GnnLayer> gnn;
  Layer final_proj;
  std::unique_ptr<rt::Buffer> weights, biases;

  rt::Gemm gemm;
  rt::Kernel keypoints_kernel, softmax_kernel, scores_kernel, sinkhorn_kernel, assignment_kernel, argmax_kernel,
      mutual_kernel;
  // Sinkhorn through RGBA32F texel buffers, where the device reads them (see texel_sinkhorn_fits()).
  std::optional<rt::Kernel> couplings_pad_kernel, sinkhorn_tiled_kernel, sinkhorn_fused_kernel, sinkhorn_lines_kernel;
  // The fused attention and the score matrix through texel views of the storage precision, where the device
  // reads them.
  std::optional<rt::Kernel> attention_tiled_kernel, attention_shared_kernel, scores_tiled_kernel;
  std::uint32_t attention_rows_per_invocation = 0;  // of attention_tiled_kernel

  // Per-size state: buffers and the recorded sequence, reused while (n0, n1) stays the same.
  std::size_t n0 = 0, n1 = 0;
  bool recorded = false;
  bool profiling = false;  // per-dispatch timestamps (SuperGlue::set_profiling)
  std::unique_ptr<rt::Sequence> seq;
  std::vector<std::unique_ptr<rt::Buffer>> buffers;
  rt::Buffer *kpts = nullptr, *kscores = nullptr, *enc_in = nullptr, *enc_a = nullptr, *enc_b = nullptr,
             *state = nullptr, *qkv = nullptr, *hidden = nullptr, *attn0 = nullptr, *attn1 = nullptr, *z = nullptr,
             *z_rows = nullptr, *z_cols = nullptr, *u = nullptr, *v = nullptr, *best = nullptr, *best_value = nullptr,
             *matches = nullptr, *match_scores = nullptr;
  // The host's side of the per-call inputs and outputs, copied by the sequence where they are not mapped: a call is
  // one submission.
  std::optional<rt::HostInput> kpts_in, kscores_in, state_in;
  std::optional<rt::HostOutput> matches_out, match_scores_out;
  std::vector<rt::CommandTiming> timings;

  Impl(const rt::Context& ctx, const io::ModelPack& pack, const SuperGlueParams& p)
      : context(ctx),
        params(p),
        config(read_superglue_config(pack)),
        precision(p.precision.value_or(ctx.profile().precision)),
        gemm(ctx, precision),
        keypoints_kernel(ctx, {.op = rt::Op::superglue_keypoints, .precision = precision}),
        softmax_kernel(ctx, {.op = rt::Op::superglue_softmax, .precision = precision}),
        scores_kernel(ctx, {.op = rt::Op::superglue_scores, .precision = precision}),
        sinkhorn_kernel(ctx, {.op = rt::Op::superglue_sinkhorn}),
        assignment_kernel(ctx, {.op = rt::Op::superglue_assignment}),
        argmax_kernel(ctx, {.op = rt::Op::superglue_argmax}),
        mutual_kernel(ctx, {.op = rt::Op::superglue_mutual}) {
    ctx.caps().require(precision, "SuperGlue");
    iterations = params.sinkhorn_iterations > 0 ? params.sinkhorn_iterations : config.sinkhorn_iterations;
    attention_rows_per_invocation = attention_rows(ctx, params.attention_rows);
    const std::uint32_t head_dim = std::uint32_t(config.descriptor_dim / config.heads);
    const bool fused_attention = params.texel_kernels &&
                                 ctx.supports_uniform_texel_format(rt::packed_texel_format(precision)) &&
                                 head_dim % rt::values_per_packed_texel(precision) == 0;
    if (fused_attention && params.shared_attention.value_or(ctx.profile().shared_attention) &&
        shared_attention_bytes(head_dim) <= ctx.caps().max_shared_memory_bytes)
      attention_shared_kernel.emplace(ctx, rt::KernelSpec{.op = rt::Op::superglue_attention_shared,
                                                          .precision = precision,
                                                          .specialization = {head_dim / 4},
                                                          .texel_formats = {rt::packed_texel_format(precision)}});
    else if (fused_attention)
      attention_tiled_kernel.emplace(ctx,
                                     rt::KernelSpec{.op = rt::Op::superglue_attention_tiled,
                                                    .precision = precision,
                                                    .specialization = {head_dim / 4, attention_rows_per_invocation},
                                                    .texel_formats = {rt::packed_texel_format(precision)}});
    if (params.texel_kernels && ctx.supports_uniform_texel_format(rt::vec4_texel_format(precision))) {
      if (config.descriptor_dim % 4 == 0)
        scores_tiled_kernel.emplace(ctx, rt::KernelSpec{.op = rt::Op::superglue_scores_tiled,
                                                        .texel_formats = {rt::vec4_texel_format(precision)}});
    }
    if (params.texel_kernels && ctx.supports_uniform_texel_format(vk::Format::eR32G32B32A32Sfloat)) {
      constexpr auto kFloat4 = vk::Format::eR32G32B32A32Sfloat;
      couplings_pad_kernel.emplace(ctx, rt::KernelSpec{.op = rt::Op::superglue_couplings_pad});
      sinkhorn_tiled_kernel.emplace(
          ctx, rt::KernelSpec{.op = rt::Op::superglue_sinkhorn_tiled, .texel_formats = {kFloat4, kFloat4}});
      sinkhorn_fused_kernel.emplace(
          ctx, rt::KernelSpec{.op = rt::Op::superglue_sinkhorn_fused, .texel_formats = {kFloat4, kFloat4}});
      if (params.sinkhorn_workgroup_per_line.value_or(ctx.profile().sinkhorn_workgroup_per_line))
        sinkhorn_lines_kernel.emplace(
            ctx, rt::KernelSpec{.op = rt::Op::superglue_sinkhorn_lines, .texel_formats = {kFloat4, kFloat4}});
    }
    prepare_weights(pack);
  }

  // Z's rows and columns padded to whole texels of 4 entries, for the texel-buffer Sinkhorn.
  std::size_t rows_padded() const { return rt::round_up(n0 + 1, 4); }
  std::size_t cols_padded() const { return rt::round_up(n1 + 1, 4); }
  // Whether a whole buffer fits one texel view (Vulkan guarantees only 65536 texels): the tiled score matrix reads
  // the projected descriptors 4 values per texel, the fused attention qkv in 16-byte packed texels.
  bool fits_texel_view(const rt::Buffer& buffer, std::size_t texel_bytes) const {
    return buffer.size() / texel_bytes <= context.caps().max_texel_buffer_elements;
  }
  bool fits_vec4_texel_view(const rt::Buffer& buffer) const {
    return fits_texel_view(buffer, 4 * rt::storage_bytes(precision));
  }
  // Whether the texel-buffer Sinkhorn runs at the current size: the device reads RGBA32F texel buffers and both
  // padded copies of Z fit its texel-buffer limit (Vulkan guarantees only 65536 texels).
  bool texel_sinkhorn_fits() const {
    const std::size_t limit = context.caps().max_texel_buffer_elements;
    return sinkhorn_tiled_kernel && (n0 + 1) * cols_padded() / 4 <= limit && (n1 + 1) * rows_padded() / 4 <= limit;
  }

  // Whether Sinkhorn runs as one workgroup (superglue_sinkhorn_fused.comp) at the current size: its shared
  // potentials hold 1024 entries per set, dustbin and padding included. Automatic: up to the device profile's
  // number of couplings (CPU devices, where every dispatch wakes the worker threads while the fused kernel runs on
  // one of them; docs/performance-history.md, "SuperGlue").
  bool fused_sinkhorn_runs() const {
    if (!sinkhorn_fused_kernel || !texel_sinkhorn_fits() || rows_padded() > 1024 || cols_padded() > 1024) return false;
    if (params.fused_sinkhorn) return *params.fused_sinkhorn;
    return (n0 + 1) * (n1 + 1) <= context.profile().fused_sinkhorn_max_cells;
  }

  // Regroups and folds the pack's fp32 weights (superglue/weights.hpp) and uploads them at the storage precision:
  // all weights in one buffer, all biases (fp32) in another.
  void prepare_weights(const io::ModelPack& pack) {
    SuperGlueWeights prepared = prepare_superglue_weights(pack, config);
    encoder = std::move(prepared.encoder);
    gnn = std::move(prepared.gnn);
    final_proj = prepared.final_proj;
    const auto bytes = rt::encode_storage(prepared.weights, precision);
    weights = std::make_unique<rt::Buffer>(context, bytes.size(), rt::BufferKind::device, "superglue.weights");
    weights->upload(bytes.data(), bytes.size());
    const std::size_t bias_bytes = prepared.biases.size() * sizeof(float);
    biases = std::make_unique<rt::Buffer>(context, bias_bytes, rt::BufferKind::device, "superglue.biases");
    biases->upload(prepared.biases.data(), bias_bytes);
  }

  rt::Buffer* make_buffer(std::size_t bytes, const char* name) {
    buffers.push_back(
        std::make_unique<rt::Buffer>(context, std::max<std::size_t>(bytes, 16), rt::BufferKind::device, name));
    return buffers.back().get();
  }

  void allocate() {
    buffers.clear();
    z_rows = z_cols = nullptr;
    const std::size_t rows = n0 + n1, dim = std::size_t(config.descriptor_dim), sb = rt::storage_bytes(precision);
    std::size_t widest = 4;
    for (const Layer& l : encoder) widest = std::max<std::size_t>(widest, l.out);
    kpts = make_buffer(rows * 2 * 4, "superglue.keypoints");
    kscores = make_buffer(rows * 4, "superglue.scores");
    enc_in = make_buffer(rows * 4 * sb, "superglue.encoder_input");
    enc_a = make_buffer(rows * widest * sb, "superglue.encoder_a");
    enc_b = make_buffer(rows * widest * sb, "superglue.encoder_b");
    state = make_buffer(rows * 2 * dim * sb, "superglue.state");
    // kScoreAlign spare rows past the last keypoint: the attention's p.v reads V rows up to the padded key count
    // (see attention()); they stay zero, nothing writes them.
    qkv = make_buffer((rows + kScoreAlign) * 3 * dim * sb, "superglue.qkv");
    qkv->fill_zero();
    hidden = make_buffer(rows * 2 * dim * sb, "superglue.hidden");
    // Scores of one set's queries against either set (self or cross layers): rows x max(n0, n1) per head.
    const std::size_t widest_set = std::max(n0, n1);
    attn0 = make_buffer(std::size_t(config.heads) * n0 * padded_keys(widest_set) * sb, "superglue.attention0");
    attn1 = make_buffer(std::size_t(config.heads) * n1 * padded_keys(widest_set) * sb, "superglue.attention1");
    z = make_buffer((n0 + 1) * (n1 + 1) * 4, "superglue.couplings");
    // Potentials padded to whole texels (zeros) for the texel-buffer Sinkhorn, which also gets Z's padded copies.
    u = make_buffer(rows_padded() * 4, "superglue.u");
    v = make_buffer(cols_padded() * 4, "superglue.v");
    if (texel_sinkhorn_fits()) {
      z_rows = make_buffer((n0 + 1) * cols_padded() * 4, "superglue.couplings_by_row");
      z_cols = make_buffer((n1 + 1) * rows_padded() * 4, "superglue.couplings_by_column");
    }
    best = make_buffer(rows * 4, "superglue.best");
    best_value = make_buffer(rows * 4, "superglue.best_value");
    matches = make_buffer(n0 * 4, "superglue.matches0");
    match_scores = make_buffer(n0 * 4, "superglue.matching_scores0");
    kpts_in.emplace(context, *kpts);
    kscores_in.emplace(context, *kscores);
    state_in.emplace(context, *state);
    matches_out.emplace(context, *matches);
    match_scores_out.emplace(context, *match_scores);
  }

  rt::Binding bias_of(const Layer& l) const { return rt::Binding(*biases, l.bias_offset, std::size_t(l.out) * 4); }

  // y = x W^T + b for `rows` rows; x and y are column blocks of row-major matrices with leading dimensions.
  void linear(const Layer& l, const rt::Buffer& x, std::uint32_t ldx, const rt::Buffer& y, std::uint32_t ldy, bool relu,
              bool accumulate, const std::string& label) {
    const rt::Binding bias = bias_of(l);
    rt::GemmShape s{.m = std::uint32_t(n0 + n1),
                    .n = l.out,
                    .k = l.in,
                    .b_transposed = true,
                    .relu = relu,
                    .accumulate = accumulate,
                    .lda = ldx,
                    .ldb = l.in,
                    .ldc = ldy,
                    .b_offset = l.weight_offset};
    gemm.record(*seq, x, *weights, &bias, y, s, label);
  }

  // Score rows are padded to a multiple of kScoreAlign keys: the p.v GEMM then reads whole texels of P along K
  // for any key count (the tiled kernel; gemm.comp would serve unaligned counts several times slower) and the
  // softmax reads vec4s. The softmax sets the padding columns to zero, so the V rows they meet (the other
  // set's, or the zeroed spare rows of qkv) add nothing.
  static constexpr std::uint32_t kScoreAlign = 8;
  static std::uint32_t padded_keys(std::size_t keys) {
    return std::uint32_t((keys + kScoreAlign - 1) / kScoreAlign * kScoreAlign);
  }

  // Multi-head attention of keypoint set `a` (queries) over set `src` (keys, values); the heads' outputs go to the
  // message half of `a`'s state rows. One fused pass where qkv fits a texel view (superglue_attention_shared.comp
  // on GPUs, superglue_attention_tiled.comp elsewhere: the scores are never stored), else q.k GEMM, softmax in
  // place, p.v GEMM through `scores`.
  void attention(int a, int src, const rt::Buffer& scores, const std::string& label) {
    const std::uint32_t dim = config.descriptor_dim, heads = config.heads, head_dim = dim / heads;
    const std::uint32_t rows_a = a == 0 ? n0 : n1, rows_s = src == 0 ? n0 : n1;
    const std::uint32_t first_a = a == 0 ? 0 : n0, first_s = src == 0 ? 0 : n0;
    const shader::AttentionPush push{rows_a, rows_s, first_a, first_s, dim, 1.0f / std::sqrt(float(head_dim))};
    if (attention_shared_kernel && fits_texel_view(*qkv, rt::kPackedTexelBytes)) {
      seq->dispatch(*attention_shared_kernel, {rt::Binding(*qkv), rt::Binding(*state)}, push,
                    {rt::groups_for(rows_a, 16), heads, 1}, label);
      return;
    }
    if (attention_tiled_kernel && fits_texel_view(*qkv, rt::kPackedTexelBytes)) {
      seq->dispatch(*attention_tiled_kernel, {rt::Binding(*qkv), rt::Binding(*state)}, push,
                    {rt::groups_for(rt::groups_for(rows_a, attention_rows_per_invocation), 16), heads, 1}, label);
      return;
    }
    const std::uint32_t keys = padded_keys(rows_s);  // score row stride
    gemm.record(*seq, *qkv, *qkv, nullptr, scores,
                {.m = rows_a,
                 .n = rows_s,
                 .k = head_dim,
                 .b_transposed = true,
                 .alpha = 1.0f / std::sqrt(float(head_dim)),
                 .lda = 3 * dim,
                 .ldb = 3 * dim,
                 .ldc = keys,
                 .a_offset = first_a * 3 * dim,
                 .b_offset = first_s * 3 * dim + dim,
                 .batch = heads,
                 .a_batch_stride = head_dim,
                 .b_batch_stride = head_dim,
                 .c_batch_stride = rows_a * keys},
                label + " q.k");
    const shader::SoftmaxPush sp{heads * rows_a, rows_s, keys};
    seq->dispatch(softmax_kernel, {rt::Binding(scores)}, sp, {rt::groups_for(sp.rows, 64)}, label + " softmax");
    gemm.record(*seq, scores, *qkv, nullptr, *state,
                {.m = rows_a,
                 .n = head_dim,
                 .k = keys,
                 .lda = keys,
                 .ldb = 3 * dim,
                 .ldc = 2 * dim,
                 .b_offset = first_s * 3 * dim + 2 * dim,
                 .c_offset = first_a * 2 * dim + dim,
                 .batch = heads,
                 .a_batch_stride = rows_a * keys,
                 .b_batch_stride = head_dim,
                 .c_batch_stride = head_dim},
                label + " p.v");
  }

  void record() {
    const std::uint32_t dim = config.descriptor_dim;
    const std::uint32_t rows = std::uint32_t(n0 + n1);
    if (!seq) seq = std::make_unique<rt::Sequence>(context, profiling ? 1024 : 0);
    seq->begin();
    for (const auto* in : {&*kpts_in, &*kscores_in, &*state_in}) in->record(*seq);
    // Image sizes are push constants: the sequence is re-recorded when they change (see match()).
    seq->dispatch(keypoints_kernel, {rt::Binding(*kpts), rt::Binding(*kscores), rt::Binding(*enc_in)}, image_push,
                  {rt::groups_for(rows, 64)}, "keypoints");
    const rt::Buffer* x = enc_in;
    std::uint32_t width = 4;
    for (std::size_t i = 0; i < encoder.size(); ++i) {
      const bool last = i + 1 == encoder.size();
      const rt::Buffer* y = last ? state : (x == enc_a ? enc_b : enc_a);
      linear(encoder[i], *x, width, *y, last ? 2 * dim : encoder[i].out, !last, last, "kenc");
      x = y;
      width = encoder[i].out;
    }
    for (std::size_t l = 0; l < gnn.size(); ++l) {
      const GnnLayer& layer = gnn[l];
      const std::string tag = layer.cross ? "cross" : "self";
      linear(layer.qkv, *state, 2 * dim, *qkv, 3 * dim, false, false, tag + " qkv");
      attention(0, layer.cross ? 1 : 0, *attn0, tag + " attn");
      attention(1, layer.cross ? 0 : 1, *attn1, tag + " attn");
      linear(layer.mlp0, *state, 2 * dim, *hidden, 2 * dim, true, false, tag + " mlp0");
      linear(layer.mlp1, *hidden, 2 * dim, *state, 2 * dim, false, true, tag + " mlp1");
    }
    linear(final_proj, *state, 2 * dim, *hidden, dim, false, false, "final_proj");

    const shader::ScoresPush sc{std::uint32_t(n0), std::uint32_t(n1), dim, 1.0f / std::sqrt(float(dim)),
                                config.bin_score};
    const bool texel_scores = scores_tiled_kernel && fits_vec4_texel_view(*hidden);
    seq->dispatch(texel_scores ? *scores_tiled_kernel : scores_kernel, {rt::Binding(*hidden), rt::Binding(*z)}, sc,
                  {rt::groups_for(rt::groups_for(n1 + 1, 4), 16), rt::groups_for(rt::groups_for(n0 + 1, 3), 4)},
                  "scores");
    seq->fill_zero(*u, "sinkhorn init");
    seq->fill_zero(*v, "sinkhorn init");
    const float norm = -std::log(float(n0 + n1));
    if (texel_sinkhorn_fits()) {
      record_texel_sinkhorn(norm);
    } else {
      for (int it = 0; it < iterations; ++it)
        for (std::uint32_t axis = 0; axis < 2; ++axis) {
          const shader::SinkhornPush push{std::uint32_t(n0 + 1), std::uint32_t(n1 + 1), axis, norm};
          seq->dispatch(sinkhorn_kernel, {rt::Binding(*z), rt::Binding(*u), rt::Binding(*v)}, push,
                        {rt::groups_for(axis == 0 ? n0 + 1 : n1 + 1, 64)}, "sinkhorn");
        }
    }
    const shader::AssignmentPush ap{std::uint32_t(n0 + 1), std::uint32_t(n1 + 1), norm};
    const std::size_t cells = (n0 + 1) * (n1 + 1);
    const std::uint32_t groups = rt::groups_for(cells, 64);
    const std::uint32_t gx = std::min<std::uint32_t>(groups, 65535), gy = rt::groups_for(groups, gx);
    seq->dispatch(assignment_kernel, {rt::Binding(*z), rt::Binding(*u), rt::Binding(*v)}, ap, {gx, gy},
                  "log_assignment");
    const shader::SetSizesPush pp{std::uint32_t(n0), std::uint32_t(n1)};
    seq->dispatch(argmax_kernel, {rt::Binding(*z), rt::Binding(*best), rt::Binding(*best_value)}, pp,
                  {rt::groups_for(rows, 64)}, "argmax");
    const shader::MutualPush mp{std::uint32_t(n0), std::uint32_t(n1), params.match_threshold};
    seq->dispatch(mutual_kernel,
                  {rt::Binding(*best), rt::Binding(*best_value), rt::Binding(*matches), rt::Binding(*match_scores)}, mp,
                  {rt::groups_for(n0, 64)}, "mutual");
    matches_out->record(*seq);
    match_scores_out->record(*seq);
    seq->end();
    recorded = true;
  }

  // Z's padded row and column copies, then each half-iteration walks the lines of one of them.
  void record_texel_sinkhorn(float norm) {
    const auto rows = std::uint32_t(n0 + 1), cols = std::uint32_t(n1 + 1);
    const auto rows_p = std::uint32_t(rows_padded()), cols_p = std::uint32_t(cols_padded());
    const shader::CouplingsPadPush pad{rows, cols, rows_p, cols_p};
    seq->dispatch(*couplings_pad_kernel, {rt::Binding(*z), rt::Binding(*z_rows), rt::Binding(*z_cols)}, pad,
                  {rt::groups_for(cols_p, 16), rt::groups_for(rows_p, 4)}, "sinkhorn init");
    if (fused_sinkhorn_runs()) {
      const shader::SinkhornFusedPush fused{rows, cols, cols_p / 4, rows_p / 4, std::uint32_t(iterations), norm};
      seq->dispatch(*sinkhorn_fused_kernel,
                    {rt::Binding(*z_rows), rt::Binding(*z_cols), rt::Binding(*u), rt::Binding(*v)}, fused, {1},
                    "sinkhorn");
      return;
    }
    const shader::SinkhornHalfPush by_row{rows, cols, cols_p / 4, norm}, by_column{cols, rows, rows_p / 4, norm};
    // A workgroup per line (sinkhorn_lines_kernel), or 64 lines per workgroup.
    const rt::Kernel& half = sinkhorn_lines_kernel ? *sinkhorn_lines_kernel : *sinkhorn_tiled_kernel;
    const std::uint32_t row_groups = sinkhorn_lines_kernel ? rows : rt::groups_for(rows, 64);
    const std::uint32_t column_groups = sinkhorn_lines_kernel ? cols : rt::groups_for(cols, 64);
    for (int it = 0; it < iterations; ++it) {
      seq->dispatch(half, {rt::Binding(*z_rows), rt::Binding(*v), rt::Binding(*u)}, by_row, {row_groups}, "sinkhorn");
      seq->dispatch(half, {rt::Binding(*z_cols), rt::Binding(*u), rt::Binding(*v)}, by_column, {column_groups},
                    "sinkhorn");
    }
  }

  shader::KeypointsPush image_push{};
};

SuperGlue::SuperGlue(const rt::Context& context, const io::ModelPack& pack, const SuperGlueParams& params)
    : impl_(std::make_unique<Impl>(context, pack, params)) {}

SuperGlue::~SuperGlue() = default;

rt::Precision SuperGlue::precision() const { return impl_->precision; }
const SuperGlueConfig& SuperGlue::config() const { return impl_->config; }
std::string SuperGlue::attention_form() const {
  return impl_->attention_shared_kernel ? "shared" : impl_->attention_tiled_kernel ? "registers" : "three-pass";
}
void SuperGlue::set_profiling(bool on) {
  if (on == impl_->profiling) return;
  impl_->profiling = on;
  impl_->seq.reset();  // re-created with or without timestamps at the next recording
  impl_->recorded = false;
}

std::vector<rt::CommandTiming> SuperGlue::last_timings() const { return impl_->timings; }

double SuperGlue::flops(std::size_t n0, std::size_t n1) const {
  const double rows = double(n0 + n1), dim = impl_->config.descriptor_dim;
  double total = 0;
  for (const auto& l : impl_->encoder) total += 2.0 * rows * l.out * l.in;
  for (const auto& l : impl_->gnn) {
    total +=
        2.0 * rows * (double(l.qkv.out) * l.qkv.in + double(l.mlp0.out) * l.mlp0.in + double(l.mlp1.out) * l.mlp1.in);
    total += 2.0 * 2.0 * 2.0 * double(n0) * double(n1) * dim;  // q.k and p.v, both directions
  }
  total += 2.0 * rows * dim * dim + 2.0 * double(n0) * double(n1) * dim;  // final projection, scores
  return total;
}

PointMatches SuperGlue::match(const PointFeatures& a, const PointFeatures& b) { return match(a, b, nullptr); }

PointMatches SuperGlue::match(const PointFeatures& a, const PointFeatures& b, Eigen::MatrixXf* log_assignment) {
  Impl& s = *impl_;
  PointMatches result;
  result.matches0.assign(a.size(), -1);
  result.scores0.assign(a.size(), 0.0f);
  s.timings.clear();
  if (log_assignment) log_assignment->resize(0, 0);
  if (a.size() == 0 || b.size() == 0) return result;

  const int dim = s.config.descriptor_dim;
  for (const PointFeatures* f : {&a, &b}) {
    if (f->descriptors.rows() != Eigen::Index(f->size()) || f->descriptors.cols() != dim ||
        f->scores.size() != f->size())
      throw std::invalid_argument(fmt::format(
          "SuperGlue: {} keypoints need {} scores and {} x {} descriptors "
          "(got {} scores, {} x {})",
          f->size(), f->size(), f->size(), dim, f->scores.size(), f->descriptors.rows(), f->descriptors.cols()));
    if (f->image_width <= 0 || f->image_height <= 0)
      throw std::invalid_argument("SuperGlue: image_width and image_height are needed to normalise keypoints");
  }
  if (a.size() != s.n0 || b.size() != s.n1) {
    s.n0 = a.size();
    s.n1 = b.size();
    s.allocate();
    s.recorded = false;
  }
  const shader::KeypointsPush image{std::uint32_t(s.n0),   std::uint32_t(s.n1),  float(a.image_width),
                                    float(a.image_height), float(b.image_width), float(b.image_height)};
  if (image.width0 != s.image_push.width0 || image.height0 != s.image_push.height0 ||
      image.width1 != s.image_push.width1 || image.height1 != s.image_push.height1 || image.n0 != s.image_push.n0 ||
      image.n1 != s.image_push.n1) {
    s.image_push = image;
    s.recorded = false;
  }

  const std::size_t rows = s.n0 + s.n1;
  std::vector<float> kp(rows * 2), sc(rows), st(rows * 2 * std::size_t(dim), 0.0f);
  std::size_t r = 0;
  for (const PointFeatures* f : {&a, &b})
    for (std::size_t i = 0; i < f->size(); ++i, ++r) {
      kp[2 * r] = f->keypoints[i].x();
      kp[2 * r + 1] = f->keypoints[i].y();
      sc[r] = f->scores[i];
      for (int c = 0; c < dim; ++c) st[r * 2 * dim + c] = f->descriptors(Eigen::Index(i), c);
    }
  s.kpts_in->write(kp.data(), kp.size() * sizeof(float));
  s.kscores_in->write(sc.data(), sc.size() * sizeof(float));
  const auto state_bytes = rt::encode_storage(st, s.precision);
  s.state_in->write(state_bytes.data(), state_bytes.size());

  if (!s.recorded) s.record();
  s.seq->submit();
  s.timings = s.seq->timings();

  const auto m = s.matches_out->read<std::int32_t>(s.n0);
  result.matches0.assign(m.begin(), m.end());
  result.scores0 = s.match_scores_out->read<float>(s.n0);
  if (log_assignment) {  // on request only: a transfer of its own
    const auto dense = s.z->download<float>((s.n0 + 1) * (s.n1 + 1));
    *log_assignment = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        dense.data(), Eigen::Index(s.n0 + 1), Eigen::Index(s.n1 + 1));
  }
  return result;
}

}  // namespace vkvo::features
