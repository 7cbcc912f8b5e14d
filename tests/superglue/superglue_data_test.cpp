// SuperGlue on the device against the PyTorch golden cases (../shared/golden/superglue_synthetic), with the shared
// synthetic model converted by tools/convert, in every precision the device supports. Acceptance as in
// golden/README.md: log-assignment max abs error <= 1e-3 (fp32) / 0.05 (fp16 storage or math), >= 97% identical
// matches0.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "features/superglue.hpp"
#include "io/npy.hpp"
#include "tools/convert/convert.hpp"

namespace vkvo::features {
namespace {

using test::gpu;

PointFeatures load_set(const std::filesystem::path& dir, int index, int width, int height) {
  const auto kp = io::read_npy(dir / fmt::format("keypoints{}.npy", index)).to_floats();
  const auto desc_array = io::read_npy(dir / fmt::format("descriptors{}.npy", index));
  PointFeatures f;
  f.image_width = width;
  f.image_height = height;
  f.scores = io::read_npy(dir / fmt::format("scores{}.npy", index)).to_floats();
  for (std::size_t i = 0; i < f.scores.size(); ++i) f.keypoints.emplace_back(kp[2 * i], kp[2 * i + 1]);
  const auto desc = desc_array.to_floats();
  f.descriptors.resize(Eigen::Index(f.scores.size()), Eigen::Index(desc_array.shape.at(1)));
  std::copy(desc.begin(), desc.end(), f.descriptors.data());
  return f;
}

class SuperGlueGolden : public ::testing::TestWithParam<rt::Precision> {};

TEST_P(SuperGlueGolden, MatchesPyTorchReference) {
  VKVO_REQUIRE_DATA(model, "models/superglue_synthetic.onnx");
  VKVO_REQUIRE_DATA(golden, "golden/superglue_synthetic");
  if (!gpu().caps().supports(GetParam())) GTEST_SKIP() << "precision not supported";
  const auto pack_path = test::temp_dir("superglue_golden") / "superglue_synthetic.vkvopack";
  if (!std::filesystem::exists(pack_path)) convert::convert_file(model, pack_path, io::NetworkKind::superglue);
  const auto pack = io::ModelPack::load(pack_path, io::NetworkKind::superglue);
  SuperGlue net(gpu(), pack, {.precision = GetParam()});
  ASSERT_EQ(net.config().cross_layers.size(), 18u);
  const double tolerance = GetParam() == rt::Precision::fp32 ? 1e-3 : 0.05;

  for (const char* name : {"euroc_0000_0005", "euroc_small_unequal"}) {
    SCOPED_TRACE(name);
    const auto dir = golden / name;
    const int width = name == std::string("euroc_0000_0005") ? 752 : 160;
    const int height = name == std::string("euroc_0000_0005") ? 480 : 120;
    const PointFeatures a = load_set(dir, 0, width, height), b = load_set(dir, 1, width, height);
    Eigen::MatrixXf la;
    const PointMatches got = net.match(a, b, &la);

    const auto la_ref = io::read_npy(dir / "log_assignment.npy");
    ASSERT_EQ(std::size_t(la.rows()), la_ref.shape.at(0));
    ASSERT_EQ(std::size_t(la.cols()), la_ref.shape.at(1));
    const auto ref = la_ref.to_floats();
    double err = 0;
    for (Eigen::Index i = 0; i < la.rows(); ++i)
      for (Eigen::Index j = 0; j < la.cols(); ++j)
        err = std::max(err, double(std::abs(la(i, j) - ref[std::size_t(i * la.cols() + j)])));
    EXPECT_LE(err, tolerance) << "log-assignment max abs error";

    const auto m_ref = io::read_npy(dir / "matches0.npy").to_int32s();
    const auto s_ref = io::read_npy(dir / "matching_scores0.npy").to_floats();
    ASSERT_EQ(got.matches0.size(), m_ref.size());
    std::size_t same = 0;
    double score_err = 0;
    for (std::size_t i = 0; i < m_ref.size(); ++i) {
      same += got.matches0[i] == m_ref[i];
      if (got.matches0[i] == m_ref[i]) score_err = std::max(score_err, double(std::abs(got.scores0[i] - s_ref[i])));
    }
    EXPECT_GE(double(same), 0.97 * double(m_ref.size())) << same << " of " << m_ref.size() << " identical matches0";
    EXPECT_LE(score_err, 2 * tolerance) << "matching_scores0 of identical matches";
  }
}

INSTANTIATE_TEST_SUITE_P(AllPrecisions, SuperGlueGolden, ::testing::ValuesIn(rt::kAllPrecisions),
                         [](const auto& info) { return std::string(rt::to_string(info.param)); });

}  // namespace
}  // namespace vkvo::features
