// perturb_sequence on the shared real sequences (label `data`): EuRoC MH_01 subset and KITTI 01 subset.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_support.hpp"
#include "tools/synth/perturb.hpp"

namespace vkvo::synth {
namespace {

namespace fs = std::filesystem;

double mean_of(const fs::path& image) { return cv::mean(cv::imread(image.string(), cv::IMREAD_UNCHANGED))[0]; }

TEST(PerturbData, EurocLightsOffKeepsCalibrationAndTimestamps) {
  VKVO_REQUIRE_DATA(euroc, "datasets/euroc_mh01_subset/MH_01_easy");
  const fs::path dst = vkvo::test::temp_dir("synth_perturb_euroc") / "MH_01_easy";
  perturb_sequence(euroc, dst, parse_events({"lights_off:60-61", "spotlight:100-110"}));
  for (const char* f : {"mav0/cam0/data.csv", "mav0/cam1/data.csv", "mav0/cam0/sensor.yaml", "mav0/cam1/sensor.yaml",
                        "mav0/body.yaml", "mav0/leica0/data.csv"})
    EXPECT_EQ(test::read_text(euroc / f), test::read_text(dst / f)) << f;
  const StereoImageLists lists = find_stereo_images(euroc);
  ASSERT_EQ(lists.left.size(), 130u);
  const fs::path off = fs::path("mav0/cam0") / lists.left[60];
  EXPECT_NEAR(mean_of(dst / off), 0.02 * mean_of(euroc / off), 0.6);
  const fs::path untouched = fs::path("mav0/cam1") / lists.right[59];
  EXPECT_EQ(test::read_text(euroc / untouched), test::read_text(dst / untouched));
}

TEST(PerturbData, KittiOverexposureClips) {
  VKVO_REQUIRE_DATA(kitti, "datasets/kitti_seq01_f000-050/KITTI_sequence_2");
  const fs::path dst = vkvo::test::temp_dir("synth_perturb_kitti_data") / "seq";
  perturb_sequence(kitti, dst, parse_events({"overexposure:10-12,gain=4,ramp=0"}));
  EXPECT_EQ(test::read_text(kitti / "calib.txt"), test::read_text(dst / "calib.txt"));
  EXPECT_EQ(test::read_text(kitti / "poses.txt"), test::read_text(dst / "poses.txt"));
  const cv::Mat bright = cv::imread((dst / "image_l/000011.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat original = cv::imread((kitti / "image_l/000011.png").string(), cv::IMREAD_GRAYSCALE);
  // KITTI 01 already saturates its sky (~13% of the pixels); x4 exposure clips a large part of the road too.
  const double clipped = cv::countNonZero(bright == 255) / static_cast<double>(bright.total());
  const double clipped_before = cv::countNonZero(original == 255) / static_cast<double>(original.total());
  EXPECT_GT(clipped, 0.35);
  EXPECT_GT(clipped, 3 * clipped_before);
  const cv::Mat dark = original < 60;  // x4 stays below 255: exact gain up to rounding
  EXPECT_NEAR(cv::mean(bright, dark)[0] / cv::mean(original, dark)[0], 4.0, 0.02);
  EXPECT_EQ(test::read_text(kitti / "image_r/000009.png"), test::read_text(dst / "image_r/000009.png"));
}

}  // namespace
}  // namespace vkvo::synth
