// SuperPoint on the device against the PyTorch golden outputs ($VKVO_DATA/golden/superpoint, fp32 CPU), in
// every precision the device supports and every case (fp16's 16-bit arithmetic is emulated on lavapipe, so its
// cases are the slow ones: docs/testing.md), with the tolerances of golden/README.md:
//   dense scores max abs error <= 2e-3; dense descriptors cosine >= 0.999 per cell (fp32 and fp16s; fp16 has
//   wider dense tolerances, see DenseTolerance);
//   >= 95% of reference keypoints found within 1 px; descriptor cosine >= 0.995 for those matches.
// Also: the same image at 25% brightness keeps >= 70% of its top-400 keypoints within 2 px; sub-pixel keypoints
// follow a sub-pixel shift of the image.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <ostream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "features/superpoint.hpp"
#include "io/npy.hpp"
#include "runtime/ops.hpp"
#include "superpoint/superpoint_reference.hpp"
#include "tools/convert/convert.hpp"

namespace vkvo::features {
namespace {

namespace fs = std::filesystem;

// The pack converted once per process from the shared ONNX file.
const io::ModelPack& superpoint_pack(const fs::path& onnx) {
  static std::unique_ptr<io::ModelPack> pack;
  if (!pack) {
    const fs::path out = test::temp_dir("superpoint_pack") / "superpoint.vkvopack";
    convert::convert_file(onnx, out, io::NetworkKind::superpoint);
    pack = std::make_unique<io::ModelPack>(io::ModelPack::load(out, io::NetworkKind::superpoint));
  }
  return *pack;
}

SuperPoint& superpoint(const io::ModelPack& pack, rt::Precision precision) {
  static std::map<rt::Precision, std::unique_ptr<SuperPoint>> instances;
  auto& sp = instances[precision];
  if (!sp) {
    SuperPointParams params;  // the golden settings: threshold 0.005, NMS 4, border 4, top 400
    params.precision = precision;
    sp = std::make_unique<SuperPoint>(test::gpu(), pack, params);
  }
  return *sp;
}

float cosine(const float* a, const float* b, std::size_t n, std::size_t stride_a = 1, std::size_t stride_b = 1) {
  double ab = 0, aa = 0, bb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ab += double(a[i * stride_a]) * b[i * stride_b];
    aa += double(a[i * stride_a]) * a[i * stride_a];
    bb += double(b[i * stride_b]) * b[i * stride_b];
  }
  return float(ab / std::sqrt(std::max(aa * bb, 1e-30)));
}

// Index of the nearest keypoint of `candidates` within `radius` px of `p`, or -1.
int nearest(const Eigen::Vector2f& p, const std::vector<Eigen::Vector2f>& candidates, float radius) {
  int best = -1;
  float best_d = radius;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    const float d = (candidates[j] - p).norm();
    if (d <= best_d) best = int(j), best_d = d;
  }
  return best;
}

struct Golden {
  cv::Mat image;
  std::vector<float> dense_scores, dense_descriptors, descriptors;
  std::vector<std::size_t> dense_scores_shape, dense_descriptors_shape;
  std::vector<Eigen::Vector2f> keypoints;
};

Golden load_golden(const fs::path& dir) {
  Golden g;
  g.image = cv::imread((dir / "image.png").string(), cv::IMREAD_GRAYSCALE);
  const auto ds = io::read_npy(dir / "dense_scores.npy");
  const auto dd = io::read_npy(dir / "dense_descriptors.npy");
  g.dense_scores = ds.to_floats(), g.dense_scores_shape = ds.shape;
  g.dense_descriptors = dd.to_floats(), g.dense_descriptors_shape = dd.shape;
  const auto kp = io::read_npy(dir / "keypoints.npy").to_floats();
  for (std::size_t i = 0; i + 1 < kp.size(); i += 2) g.keypoints.emplace_back(kp[i], kp[i + 1]);
  g.descriptors = io::read_npy(dir / "descriptors.npy").to_floats();
  return g;
}

struct Case {
  const char* name;
  rt::Precision precision;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name << " " << rt::to_string(c.precision); }

// Dense-output tolerances: golden/README.md's (max abs score error 2e-3, descriptor cosine 0.999) for fp32 and
// fp16s. fp16s stores the activations in 16 bits and keeps the weights in fp32 (rt::conv_weight_precision) with
// the input as exact pixel values (shaders/superpoint_input.comp), which is what brings it within them: 16-bit
// weights cost far more than 16-bit activations (tools/superpoint_fp16_error.py). fp16 multiplies in 16 bits, so
// its weights are rounded to 16 bits whatever they are stored as; it is held to what it reaches, with room, and
// misses golden/README.md's dense acceptance (docs/accuracy.md has the errors of each variant). The keypoint
// checks (recall, descriptor cosine) are golden/README.md's for every variant. The tensor-core kernels
// (rt::use_cooperative_matrix: fp16s and fp16 on NVIDIA GPUs) also multiply 16-bit weights, with fp32 sums: they
// are held to fp16's dense bounds and, like every variant, to the keypoint checks (issue 39's acceptance).
struct DenseTolerance {
  float score_max_abs;
  float descriptor_min_cosine;
};
DenseTolerance dense_tolerance(rt::Precision precision, bool tensor_cores) {
  return precision != rt::Precision::fp16 && !tensor_cores ? DenseTolerance{2e-3f, 0.999f}
                                                           : DenseTolerance{2.5e-2f, 0.993f};
}

class SuperPointGolden : public ::testing::TestWithParam<Case> {};

TEST_P(SuperPointGolden, MatchesPyTorchReference) {
  const Case c = GetParam();
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  VKVO_REQUIRE_DATA(dir, fs::path("golden/superpoint") / c.name);
  auto& gpu = test::gpu();
  if (!gpu.caps().supports(c.precision)) GTEST_SKIP() << gpu.caps().name << " lacks " << rt::to_string(c.precision);

  const Golden g = load_golden(dir);
  ASSERT_FALSE(g.image.empty());
  SuperPoint& sp = superpoint(superpoint_pack(onnx), c.precision);
  SuperPointDense dense;
  const PointFeatures result = sp.detect(g.image, &dense);

  const DenseTolerance tolerance = dense_tolerance(c.precision, rt::use_cooperative_matrix(gpu, c.precision));
  // Dense scores: same shape (floor to multiples of 8), max abs error within the variant's tolerance.
  ASSERT_EQ(g.dense_scores_shape,
            (std::vector<std::size_t>{std::size_t(dense.cells_h) * 8, std::size_t(dense.cells_w) * 8}));
  float max_err = 0;
  for (std::size_t i = 0; i < g.dense_scores.size(); ++i)
    max_err = std::max(max_err, std::abs(g.dense_scores[i] - dense.scores[i]));
  EXPECT_LE(max_err, tolerance.score_max_abs) << "dense scores";

  // Dense descriptors: cosine within the variant's tolerance in every cell.
  ASSERT_EQ(g.dense_descriptors_shape,
            (std::vector<std::size_t>{256, std::size_t(dense.cells_h), std::size_t(dense.cells_w)}));
  const std::size_t cells = std::size_t(dense.cells_h) * dense.cells_w;
  float min_cos = 1;
  for (std::size_t cell = 0; cell < cells; ++cell)
    min_cos = std::min(min_cos, cosine(&g.dense_descriptors[cell], &dense.descriptors[cell], 256, cells, cells));
  EXPECT_GE(min_cos, tolerance.descriptor_min_cosine) << "dense descriptors";

  // Keypoints: >= 95% of the reference found within 1 px; their descriptors cosine >= 0.995. A keypoint found
  // 1 px from the reference's (an NMS tie decided the other way by fp16 rounding) has its descriptor sampled 1 px
  // away, which alone costs up to ~0.6 % of cosine; so each descriptor is compared with the reference's dense
  // descriptors sampled at the same position (for keypoints at the reference's position that is the reference's
  // own keypoint descriptor, checked below). The cosine to the reference keypoint's descriptor is recorded too.
  ASSERT_FALSE(g.keypoints.empty());
  EXPECT_EQ(result.size(), g.keypoints.size());
  for (std::size_t i = 1; i < result.size(); ++i) ASSERT_GE(result.scores[i - 1], result.scores[i]) << "sorted";
  std::size_t found = 0;
  float min_desc_cos = 1, min_desc_cos_to_reference_keypoint = 1;
  for (std::size_t i = 0; i < g.keypoints.size(); ++i) {
    const int j = nearest(g.keypoints[i], result.keypoints, 1.0f);
    if (j < 0) continue;
    ++found;
    const Eigen::Vector2f& at = result.keypoints[j];
    const auto reference =
        features::reference::sample_descriptor(g.dense_descriptors, dense.cells_h, dense.cells_w, at.x(), at.y());
    if (at == g.keypoints[i]) {
      ASSERT_GE(cosine(reference.data(), &g.descriptors[i * 256], 256), 0.99999f) << "sampler differs from PyTorch's";
    }
    min_desc_cos = std::min(min_desc_cos, cosine(reference.data(), result.descriptors.row(j).data(), 256));
    min_desc_cos_to_reference_keypoint = std::min(
        min_desc_cos_to_reference_keypoint, cosine(&g.descriptors[i * 256], result.descriptors.row(j).data(), 256));
  }
  const double recall = double(found) / g.keypoints.size();
  EXPECT_GE(recall, 0.95) << found << " of " << g.keypoints.size();
  EXPECT_GE(min_desc_cos, 0.995f);
  RecordProperty("tensor_cores", rt::use_cooperative_matrix(gpu, c.precision) ? "yes" : "no");
  RecordProperty("dense_score_max_err", std::to_string(max_err));
  RecordProperty("keypoint_recall", std::to_string(recall));
  RecordProperty("dense_descriptor_min_cosine", std::to_string(min_cos));
  RecordProperty("keypoint_descriptor_min_cosine", std::to_string(min_desc_cos));
  RecordProperty("keypoint_descriptor_min_cosine_to_reference_keypoint",
                 std::to_string(min_desc_cos_to_reference_keypoint));
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const auto p : {rt::Precision::fp32, rt::Precision::fp16s, rt::Precision::fp16}) {
    for (const char* name : {"euroc_0000_crop", "euroc_0005_crop", "euroc_0000", "euroc_0005", "kitti01_0000"})
      cases.push_back({name, p});
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Golden, SuperPointGolden, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(info.param.name) + "_" + std::string(rt::to_string(info.param.precision));
                         });

// Robustness: at 25% brightness most of the strongest keypoints survive (fp16s, the CPU default).
TEST(SuperPointRobustness, DarkImageKeepsKeypoints) {
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  VKVO_REQUIRE_DATA(dir, "golden/superpoint/euroc_0000");
  const rt::Precision precision = test::gpu().profile().precision;
  SuperPoint& sp = superpoint(superpoint_pack(onnx), precision);
  const cv::Mat image = cv::imread((dir / "image.png").string(), cv::IMREAD_GRAYSCALE);
  cv::Mat dark;
  image.convertTo(dark, CV_8U, 0.25);
  const PointFeatures bright = sp.detect(image);
  const PointFeatures dim = sp.detect(dark);
  ASSERT_EQ(bright.size(), 400u);
  std::size_t kept = 0;
  for (const auto& k : bright.keypoints) kept += nearest(k, dim.keypoints, 2.0f) >= 0;
  EXPECT_GE(double(kept) / bright.size(), 0.70) << kept << " of " << bright.size();
}

// Sub-pixel keypoints: the image shifted by -(0.25, 0.15) and by +(0.25, 0.15) px (bilinear, so both are blurred
// alike) moves its keypoints by (0.5, 0.3) px. The median displacement of the keypoints found in both within 1.5 px
// must come within 0.2 px of it on each axis (measured on lavapipe: 0.38 / 0.26 px); whole pixels move by 0.
TEST(SuperPointSubpixel, KeypointsFollowASubpixelShift) {
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  VKVO_REQUIRE_DATA(dir, "golden/superpoint/euroc_0000");
  const cv::Mat image = cv::imread((dir / "image.png").string(), cv::IMREAD_GRAYSCALE);
  const Eigen::Vector2f shift(0.5f, 0.3f);
  const auto shifted = [&](float sign) {
    const cv::Matx23f translate(1, 0, sign * shift.x() / 2, 0, 1, sign * shift.y() / 2);
    cv::Mat out;
    cv::warpAffine(image, out, translate, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    return out;
  };
  const cv::Mat before = shifted(-1.0f), after = shifted(1.0f);
  const auto median_shift = [&](bool subpixel) {
    SuperPointParams params;
    params.subpixel = subpixel;
    params.precision = test::gpu().profile().precision;
    SuperPoint sp(test::gpu(), superpoint_pack(onnx), params);
    const PointFeatures a = sp.detect(before), b = sp.detect(after);
    std::vector<float> dx, dy;
    for (const auto& k : a.keypoints) {
      const int j = nearest(k + shift, b.keypoints, 1.5f);
      if (j < 0) continue;
      dx.push_back(b.keypoints[j].x() - k.x());
      dy.push_back(b.keypoints[j].y() - k.y());
    }
    if (dx.size() <= 200) {
      ADD_FAILURE() << "only " << dx.size() << " keypoints found again; most should be";
      return Eigen::Vector2f(Eigen::Vector2f::Constant(std::nanf("")));
    }
    const auto median = [](std::vector<float> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    return Eigen::Vector2f(median(dx), median(dy));
  };
  const Eigen::Vector2f subpixel = median_shift(true), whole = median_shift(false);
  EXPECT_NEAR(subpixel.x(), shift.x(), 0.2f);
  EXPECT_NEAR(subpixel.y(), shift.y(), 0.2f);
  EXPECT_GT((whole - shift).cwiseAbs().maxCoeff(), 0.2f) << "whole pixels cannot follow the shift";
  std::cout << "median keypoint shift, true (0.5, 0.3): sub-pixel (" << subpixel.transpose() << "), whole pixels ("
            << whole.transpose() << ")\n";
}

}  // namespace
}  // namespace vkvo::features
