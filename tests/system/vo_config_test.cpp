// The image-size scaling of the map-initialisation thresholds (system/vo_config.hpp: scale_to_image).
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "system/vo_config.hpp"

namespace vkvo::system {
namespace {

TEST(VoConfig, InitialisationThresholdsScaleDownWithTheImageArea) {
  const VoConfig config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  ASSERT_EQ(config.tracking.init_min_keypoints, 150);
  ASSERT_EQ(config.tracking.init_min_stereo, 100);
  ASSERT_DOUBLE_EQ(config.tracking.reference_image_area, 752.0 * 480.0);

  const VoConfig euroc = scale_to_image(config, 752, 480);  // the reference size: unchanged
  EXPECT_EQ(euroc.tracking.init_min_keypoints, 150);
  EXPECT_EQ(euroc.tracking.init_min_stereo, 100);
  const VoConfig kitti = scale_to_image(config, 1241, 376);  // larger: never scaled up
  EXPECT_EQ(kitti.tracking.init_min_keypoints, 150);
  EXPECT_EQ(kitti.tracking.init_min_stereo, 100);
  // 320 x 240 (synth small preset) is 0.2128 of the area: 150 -> 32, 100 -> 21. Real SuperPoint finds 97
  // keypoints with 76 gated stereo matches on its first frame, which the unscaled 150 / 100 refused.
  const VoConfig small = scale_to_image(config, 320, 240);
  EXPECT_EQ(small.tracking.init_min_keypoints, 32);
  EXPECT_EQ(small.tracking.init_min_stereo, 21);
  EXPECT_EQ(small.keyframe.max_tracked, config.keyframe.max_tracked);
  // Tiny images: not below 2 x keyframe.min_tracked (= 20).
  const VoConfig tiny = scale_to_image(config, 80, 60);
  EXPECT_EQ(tiny.tracking.init_min_keypoints, 20);
  EXPECT_EQ(tiny.tracking.init_min_stereo, 20);

  VoConfig fixed = config;
  fixed.tracking.reference_image_area = 0;  // disabled
  EXPECT_EQ(scale_to_image(fixed, 320, 240).tracking.init_min_keypoints, 150);
}

}  // namespace
}  // namespace vkvo::system
