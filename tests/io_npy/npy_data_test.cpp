// Reads the NumPy-written golden files: shapes, dtypes and value ranges as documented in golden/README.md.
#include "common/test_support.hpp"
#include "io/npy.hpp"

namespace vkvo::io {
namespace {

TEST(NpyData, ReadsGoldenKeypointsDescriptorsAndMatches) {
  VKVO_REQUIRE_DATA(golden, "golden");
  const NpyArray keypoints = read_npy(golden / "superpoint/euroc_0000/keypoints.npy");
  EXPECT_EQ(keypoints.dtype, "<f4");
  ASSERT_EQ(keypoints.shape, (std::vector<size_t>{400, 2}));
  const std::vector<float> xy = keypoints.to_floats();
  for (size_t i = 0; i < 400; ++i) {  // inside the 752x480 image minus the 4 px border
    EXPECT_GE(xy[2 * i], 4.0f);
    EXPECT_LT(xy[2 * i], 748.0f);
    EXPECT_GE(xy[2 * i + 1], 4.0f);
    EXPECT_LT(xy[2 * i + 1], 476.0f);
  }
  const NpyArray descriptors = read_npy(golden / "superpoint/euroc_0000/descriptors.npy");
  ASSERT_EQ(descriptors.shape, (std::vector<size_t>{400, 256}));
  const std::vector<float> d = descriptors.to_floats();
  double norm = 0.0;
  for (size_t k = 0; k < 256; ++k) norm += double(d[k]) * d[k];
  EXPECT_NEAR(norm, 1.0, 1e-4);  // L2-normalised rows

  const NpyArray matches = read_npy(golden / "superglue_synthetic/euroc_0000_0005/matches0.npy");
  ASSERT_EQ(matches.shape.size(), 1u);
  EXPECT_EQ(matches.shape[0], 400u);
  const std::vector<int32_t> m = matches.to_int32s();
  size_t matched = 0;
  for (int32_t j : m) {
    EXPECT_GE(j, -1);
    EXPECT_LT(j, 400);
    matched += j >= 0;
  }
  EXPECT_EQ(matched, 291u);  // golden/README.md: 291 matches
}

}  // namespace
}  // namespace vkvo::io
