#include "features/nn_matcher.hpp"

#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "io/config.hpp"
#include "runtime/buffer.hpp"
#include "runtime/host_transfer.hpp"
#include "runtime/kernel.hpp"
#include "runtime/ops.hpp"
#include "runtime/push_constants.hpp"

namespace vkvo::features {

NnMatcherParams load_nn_matcher_params(const YAML::Node& section) {
  NnMatcherParams params;
  if (!section || section.IsNull()) return params;
  if (!section.IsMap()) throw std::runtime_error("config section 'nn_matcher': expected a map");
  if (section["max_cosine_distance"] && section["min_similarity"])
    throw std::runtime_error("config section 'nn_matcher': give max_cosine_distance or min_similarity, not both");
  io::read_param(section, "max_cosine_distance", params.max_cosine_distance);
  if (section["min_similarity"]) {
    float min_similarity = 0;
    io::read_param(section, "min_similarity", min_similarity);
    params.max_cosine_distance = 1.0f - min_similarity;
  }
  io::read_param(section, "ratio", params.ratio);
  return params;
}

struct NnMatcher::Impl {
  const rt::Context& context;
  NnMatcherParams params;
  rt::Gemm gemm;
  rt::Kernel best_kernel, select_kernel;
  std::unique_ptr<rt::Sequence> seq;  // made at the first recording, with timestamps when profiling
  std::size_t n0 = 0, n1 = 0, dim = 0;
  bool recorded = false;
  bool profiling = false;
  std::unique_ptr<rt::Buffer> desc0, desc1, similarity, best, best_value, second, matches, scores;
  // Inputs and outputs recorded into the sequence where the device does not map them: a call is one submission.
  std::optional<rt::HostInput> desc0_in, desc1_in;
  std::optional<rt::HostOutput> matches_out, scores_out;
  std::vector<rt::CommandTiming> timings;

  Impl(const rt::Context& ctx, const NnMatcherParams& p)
      : context(ctx),
        params(p),
        gemm(ctx, rt::Precision::fp32),
        best_kernel(ctx, {.op = rt::Op::nn_best}),
        select_kernel(ctx, {.op = rt::Op::nn_select}) {}

  std::unique_ptr<rt::Buffer> make(std::size_t bytes, const char* name) const {
    return std::make_unique<rt::Buffer>(context, std::max<std::size_t>(bytes, 16), rt::BufferKind::device, name);
  }

  void record() {
    const std::size_t rows = n0 + n1;
    desc0 = make(n0 * dim * 4, "nn.descriptors0");
    desc1 = make(n1 * dim * 4, "nn.descriptors1");
    similarity = make(n0 * n1 * 4, "nn.similarity");
    best = make(rows * 4, "nn.best");
    best_value = make(rows * 4, "nn.best_value");
    second = make(rows * 4, "nn.second");
    matches = make(n0 * 4, "nn.matches0");
    scores = make(n0 * 4, "nn.scores0");
    desc0_in.emplace(context, *desc0);
    desc1_in.emplace(context, *desc1);
    matches_out.emplace(context, *matches);
    scores_out.emplace(context, *scores);
    if (!seq) seq = std::make_unique<rt::Sequence>(context, profiling ? 16 : 0);
    seq->begin();
    desc0_in->record(*seq);
    desc1_in->record(*seq);
    gemm.record(*seq, *desc0, *desc1, nullptr, *similarity,
                {.m = std::uint32_t(n0), .n = std::uint32_t(n1), .k = std::uint32_t(dim), .b_transposed = true},
                "similarity");
    const shader::SetSizesPush bp{std::uint32_t(n0), std::uint32_t(n1)};
    seq->dispatch(best_kernel,
                  {rt::Binding(*similarity), rt::Binding(*best), rt::Binding(*best_value), rt::Binding(*second)}, bp,
                  {rt::groups_for(rows, 64)}, "nearest");
    const shader::NnSelectPush sp{std::uint32_t(n0), std::uint32_t(n1), params.max_cosine_distance, params.ratio};
    seq->dispatch(select_kernel,
                  {rt::Binding(*best), rt::Binding(*best_value), rt::Binding(*second), rt::Binding(*matches),
                   rt::Binding(*scores)},
                  sp, {rt::groups_for(n0, 64)}, "select");
    matches_out->record(*seq);
    scores_out->record(*seq);
    seq->end();
    recorded = true;
  }
};

NnMatcher::NnMatcher(const rt::Context& context, const NnMatcherParams& params)
    : impl_(std::make_unique<Impl>(context, params)) {}
NnMatcher::~NnMatcher() = default;

void NnMatcher::set_profiling(bool on) {
  if (on == impl_->profiling) return;
  impl_->profiling = on;
  impl_->seq.reset();
  impl_->recorded = false;
}

std::vector<rt::CommandTiming> NnMatcher::last_timings() const { return impl_->timings; }

PointMatches NnMatcher::match(const PointFeatures& a, const PointFeatures& b) {
  Impl& s = *impl_;
  PointMatches result;
  result.matches0.assign(a.size(), -1);
  result.scores0.assign(a.size(), 0.0f);
  s.timings.clear();
  if (a.size() == 0 || b.size() == 0) return result;
  if (a.descriptors.cols() != b.descriptors.cols() || a.descriptors.rows() != Eigen::Index(a.size()) ||
      b.descriptors.rows() != Eigen::Index(b.size()))
    throw std::invalid_argument(fmt::format(
        "NnMatcher: descriptor matrices {}x{} and {}x{} do not fit {} and {} "
        "keypoints",
        a.descriptors.rows(), a.descriptors.cols(), b.descriptors.rows(), b.descriptors.cols(), a.size(), b.size()));
  const std::size_t dim = std::size_t(a.descriptors.cols());
  if (a.size() != s.n0 || b.size() != s.n1 || dim != s.dim || !s.recorded) {
    s.n0 = a.size();
    s.n1 = b.size();
    s.dim = dim;
    s.record();
  }
  s.desc0_in->write(a.descriptors.data(), s.n0 * dim * 4);
  s.desc1_in->write(b.descriptors.data(), s.n1 * dim * 4);
  s.seq->submit();
  s.timings = s.seq->timings();
  const auto m = s.matches_out->read<std::int32_t>(s.n0);
  result.matches0.assign(m.begin(), m.end());
  result.scores0 = s.scores_out->read<float>(s.n0);
  return result;
}

}  // namespace vkvo::features
