// The renderer: determinism, and each illumination event changing the images as specified (measured on the
// rendered 8-bit images against the same frame rendered without events).
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "synth/tiny_config.hpp"
#include "tools/synth/renderer.hpp"

namespace vkvo::synth {
namespace {

using testing::tiny_config;

// One scene shared by the tests of this file (generating it is the slow part).
std::shared_ptr<const Scene> tiny_scene() {
  static const auto scene =
      std::make_shared<const Scene>(generate_indoor_scene(tiny_config().scene, tiny_config().seed));
  return scene;
}

StereoRenderer renderer_with(const std::vector<std::string>& events, int frames = 12) {
  SynthConfig config = tiny_config(frames);
  config.events = parse_events(events);
  return StereoRenderer(config, tiny_scene());
}

double mean_of(const cv::Mat& image) { return cv::mean(image)[0]; }

bool identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(StereoRenderer, SameSeedGivesIdenticalBytesOtherSeedDiffers) {
  SynthConfig config = tiny_config(3);
  config.scene.num_boxes = 3;
  const StereoRenderer a(config), b(config);
  for (int k = 0; k < 3; ++k) {
    const StereoFrame fa = a.render(k), fb = b.render(k);
    EXPECT_TRUE(identical(fa.left, fb.left)) << "frame " << k;
    EXPECT_TRUE(identical(fa.right, fb.right)) << "frame " << k;
    EXPECT_EQ(fa.timestamp_ns, fb.timestamp_ns);
  }
  // Threading does not change a byte either.
  RenderOptions serial;
  serial.parallel = false;
  EXPECT_TRUE(identical(a.render(1, serial).left, b.render(1).left));

  config.seed = 2;
  const StereoRenderer c(config);
  EXPECT_GT(cv::norm(a.render(0).left, c.render(0).left, cv::NORM_L1), 0.0);
}

TEST(StereoRenderer, ImagesAreTexturedAndWellExposed) {
  const StereoRenderer r = renderer_with({});
  const StereoFrame f = r.render(0);
  ASSERT_EQ(f.left.type(), CV_8UC1);
  ASSERT_EQ(f.left.cols, 160);
  ASSERT_EQ(f.left.rows, 120);
  cv::Scalar mean, stddev;
  cv::meanStdDev(f.left, mean, stddev);
  EXPECT_GT(mean[0], 60.0);
  EXPECT_LT(mean[0], 190.0);
  EXPECT_GT(stddev[0], 15.0);                                       // structure, not a flat wall
  EXPECT_LT(cv::countNonZero(f.left == 255), f.left.total() / 50);  // no clipping without events
}

TEST(StereoRenderer, TimestampsFollowTheRate) {
  const StereoRenderer r = renderer_with({});
  EXPECT_EQ(r.timestamp_ns(1) - r.timestamp_ns(0), 50'000'000);  // 20 Hz
  EXPECT_EQ(r.timestamp_ns(11) - r.timestamp_ns(0), 550'000'000);
}

TEST(StereoRenderer, LightsOffDropsToNearBlackAndComesBack) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"lights_off:4-6"});
  const double lit = mean_of(clean.render(5).left);
  for (int k = 4; k <= 6; ++k) {
    const StereoFrame f = events.render(k);
    EXPECT_LT(mean_of(f.left), 6.0) << "frame " << k;  // 2% of ~100 DN plus clipped read noise
    EXPECT_LT(mean_of(f.right), 6.0) << "frame " << k;
  }
  EXPECT_GT(lit, 60.0);
  // Outside the event the frames are exactly the clean frames (same noise draws).
  EXPECT_TRUE(identical(events.render(3).left, clean.render(3).left));
  EXPECT_TRUE(identical(events.render(7).right, clean.render(7).right));
}

TEST(StereoRenderer, DimmingReachesTenPercent) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"dim:2-10"});
  const double full = mean_of(clean.render(10).left);
  EXPECT_NEAR(mean_of(events.render(10).left) / full, 0.1, 0.02);  // noise clipped at 0 biases dark means up
  EXPECT_NEAR(mean_of(events.render(6).left) / mean_of(clean.render(6).left), 0.55, 0.02);
  EXPECT_NEAR(mean_of(events.render(11).left) / mean_of(clean.render(11).left), 0.1, 0.02);  // holds
}

TEST(StereoRenderer, OverexposureClips) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"overexposure:3-8,gain=3,ramp=0"});
  const cv::Mat bright = events.render(5).left;
  const double clipped = cv::countNonZero(bright == 255) / static_cast<double>(bright.total());
  EXPECT_GT(clipped, 0.3);
  EXPECT_LT(cv::countNonZero(clean.render(5).left == 255), 0.02 * bright.total());
  // Unclipped pixels are three times brighter (up to noise and rounding).
  const cv::Mat reference = clean.render(5).left;
  const cv::Mat unclipped = (bright < 250) & (reference > 20);
  ASSERT_GT(cv::countNonZero(unclipped), 100);
  EXPECT_NEAR(cv::mean(bright, unclipped)[0] / cv::mean(reference, unclipped)[0], 3.0, 0.15);
}

TEST(StereoRenderer, FlickerModulatesFrameBrightness) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"flicker:0-11,depth=0.6,period=4"});
  for (int k = 0; k < 12; ++k) {
    const double expected = 1.0 - 0.6 * 0.5 * (1.0 - std::cos(2 * M_PI * k / 4.0));
    EXPECT_NEAR(mean_of(events.render(k).left) / mean_of(clean.render(k).left), expected, 0.02) << "frame " << k;
  }
}

TEST(StereoRenderer, SpotlightLightsPartOfTheImage) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"spotlight:0-10,gain=1.6,ambient=0.3,sigma=0.15"});
  const int k = 0;  // the beam sits at 15% of the width, mid-height
  const cv::Mat lit = events.render(k).left, ref = clean.render(k).left;
  const cv::Rect in_beam(14, 50, 20, 20), away(130, 10, 25, 25);
  EXPECT_NEAR(cv::mean(lit(in_beam))[0] / cv::mean(ref(in_beam))[0], 1.5, 0.15);
  EXPECT_NEAR(cv::mean(lit(away))[0] / cv::mean(ref(away))[0], 0.3, 0.05);
  // Later the beam has moved right: the left part darkens.
  const cv::Mat later = events.render(10).left, later_ref = clean.render(10).left;
  EXPECT_LT(cv::mean(later(in_beam))[0] / cv::mean(later_ref(in_beam))[0], 0.5);
}

TEST(StereoRenderer, StereoExposureDiffersBetweenCameras) {
  const StereoRenderer clean = renderer_with({});
  const StereoRenderer events = renderer_with({"stereo:0-,gain=0.5"});
  const StereoFrame f = events.render(4), c = clean.render(4);
  EXPECT_TRUE(identical(f.left, c.left));
  EXPECT_NEAR(mean_of(f.right) / mean_of(c.right), 0.5, 0.02);
}

TEST(StereoRenderer, MotionBlurSmoothsWithoutChangingBrightness) {
  SynthConfig config = tiny_config(4);
  config.trajectory.speed = 1.5;
  config.trajectory.yaw_rate_deg = 60;
  config.sensor.read_noise = 0;
  config.sensor.shot_noise = 0;
  const StereoRenderer sharp(config, tiny_scene());
  config.sensor.motion_blur = true;
  config.sensor.exposure_time = 0.04;
  const StereoRenderer blurred(config, tiny_scene());
  const cv::Mat a = sharp.render(2).left, b = blurred.render(2).left;
  EXPECT_NEAR(mean_of(a), mean_of(b), 2.0);
  auto gradient_energy = [](const cv::Mat& m) {
    cv::Mat f, dx;
    m.convertTo(f, CV_32F);
    cv::absdiff(f(cv::Rect(1, 0, f.cols - 1, f.rows)), f(cv::Rect(0, 0, f.cols - 1, f.rows)), dx);
    return cv::mean(dx)[0];
  };
  EXPECT_LT(gradient_energy(b), 0.9 * gradient_energy(a));
}

TEST(SynthPreset, DefaultMatchesTheDemoSpecification) {
  const SynthConfig config = synth_preset("default");
  EXPECT_EQ(config.rig.width, 752);
  EXPECT_EQ(config.rig.height, 480);
  EXPECT_DOUBLE_EQ(config.rate_hz, 20.0);
  EXPECT_GE(config.num_frames, 180);
  ASSERT_EQ(config.events.size(), 1u);
  EXPECT_EQ(config.events[0].kind, EventKind::lights_off);
  EXPECT_GT(config.events[0].first_frame, config.num_frames / 3);
  EXPECT_LT(config.events[0].last_frame, 2 * config.num_frames / 3);
  EXPECT_EQ(synth_preset("small").num_frames, 40);
  EXPECT_THROW(synth_preset("huge"), std::runtime_error);
}

// The low-texture preset renders the default room with flat surfaces: from the same viewpoint it has a fraction of
// the textured room's corners (FAST, threshold 20) but keeps its long edges (straight Canny edge runs: the room's
// corners, the boxes, the skirting board, the frames). 320x240, coarse textures: what tiny_config renders, larger.
TEST(SynthPreset, LowTextureKeepsTheEdgesAndLosesTheCorners) {
  const SynthConfig preset = synth_preset("low_texture");
  EXPECT_TRUE(preset.scene.plain_surfaces);
  EXPECT_EQ(preset.scene.posters_per_wall, 0);
  EXPECT_TRUE(preset.events.empty());
  EXPECT_EQ(preset.rig.width, synth_preset("default").rig.width);

  SynthConfig textured = tiny_config(1);
  textured.rig = RigParams{320, 240, 200.0, 200.0, 159.5, 119.5, 0.11};
  SynthConfig plain = textured;
  plain.scene.plain_surfaces = true;
  plain.scene.posters_per_wall = 0;
  const cv::Mat a = StereoRenderer(textured).render(0).left, b = StereoRenderer(plain).render(0).left;
  const auto corners = [](const cv::Mat& image) {
    std::vector<cv::KeyPoint> keypoints;
    cv::FAST(image, keypoints, 20, true);
    return static_cast<double>(keypoints.size());
  };
  const auto edge_lines = [](const cv::Mat& image) {
    cv::Mat edges;
    cv::Canny(image, edges, 40, 120);
    std::vector<cv::Vec4i> lines;
    cv::HoughLinesP(edges, lines, 1, CV_PI / 180, 30, 40, 2);
    return static_cast<double>(lines.size());
  };
  const double corners_textured = corners(a), corners_plain = corners(b);
  const double lines_textured = edge_lines(a), lines_plain = edge_lines(b);
  RecordProperty("corners", fmt::format("{} textured, {} plain", corners_textured, corners_plain));
  RecordProperty("lines", fmt::format("{} textured, {} plain", lines_textured, lines_plain));
  EXPECT_LT(corners_plain, 0.25 * corners_textured) << corners_textured;
  EXPECT_GE(lines_plain, 5.0);
  EXPECT_GT(lines_plain, 0.5 * lines_textured) << lines_textured;
}

}  // namespace
}  // namespace vkvo::synth
