// Illumination events: parsing and the gain each kind prescribes (closed form per frame).
#include <cmath>

#include <gtest/gtest.h>

#include "tools/synth/illumination.hpp"

namespace vkvo::synth {
namespace {

TEST(IlluminationEvent, ParsesKindRangeAndKeys) {
  const IlluminationEvent e = parse_event("dim:50-120,gain=0.2");
  EXPECT_EQ(e.kind, EventKind::dimming);
  EXPECT_EQ(e.first_frame, 50);
  EXPECT_EQ(e.last_frame, 120);
  EXPECT_DOUBLE_EQ(e.gain, 0.2);

  const IlluminationEvent s = parse_event(" stereo:10-, gain=0.4 , cam=left ");
  EXPECT_EQ(s.kind, EventKind::stereo_exposure);
  EXPECT_EQ(s.first_frame, 10);
  EXPECT_EQ(s.last_frame, -1);
  EXPECT_EQ(s.cameras, CameraMask::left);

  const IlluminationEvent single = parse_event("off:7");
  EXPECT_EQ(single.first_frame, 7);
  EXPECT_EQ(single.last_frame, 7);
  EXPECT_DOUBLE_EQ(single.gain, 0.02);  // reference residual light when off

  // to_string round-trips.
  const IlluminationEvent f = parse_event("flicker:3-40,depth=0.5,period=4.5");
  const IlluminationEvent g = parse_event(to_string(f));
  EXPECT_EQ(g.kind, f.kind);
  EXPECT_EQ(g.first_frame, 3);
  EXPECT_EQ(g.last_frame, 40);
  EXPECT_DOUBLE_EQ(g.depth, 0.5);
  EXPECT_DOUBLE_EQ(g.period_frames, 4.5);
}

TEST(IlluminationEvent, RejectsBadSpecsWithAMessage) {
  EXPECT_THROW(parse_event("sunset:1-2"), std::runtime_error);
  EXPECT_THROW(parse_event("dim:9-3"), std::runtime_error);
  EXPECT_THROW(parse_event("dim:1-3,gain=abc"), std::runtime_error);
  EXPECT_THROW(parse_event("dim:1-3,colour=2"), std::runtime_error);
  EXPECT_THROW(parse_event("flicker:1-3,depth=1.5"), std::runtime_error);
  try {
    parse_event("dim:x-3");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("dim:x-3"), std::string::npos) << e.what();
  }
}

TEST(FrameGain, LightsOffIsAStepDownAndBack) {
  const std::vector<IlluminationEvent> events{parse_event("lights_off:10-14")};
  EXPECT_DOUBLE_EQ(frame_gain(events, 9, 0, 100, 100).global, 1.0);
  for (int k = 10; k <= 14; ++k) EXPECT_NEAR(frame_gain(events, k, 1, 100, 100).global, 0.02, 1e-12);
  EXPECT_TRUE(frame_gain(events, 15, 0, 100, 100).is_identity());
}

TEST(FrameGain, DimmingRampsLinearlyAndHolds) {
  const std::vector<IlluminationEvent> events{parse_event("dim:10-20")};
  EXPECT_DOUBLE_EQ(frame_gain(events, 10, 0, 1, 1).global, 1.0);
  EXPECT_NEAR(frame_gain(events, 15, 0, 1, 1).global, 0.55, 1e-12);
  EXPECT_NEAR(frame_gain(events, 20, 0, 1, 1).global, 0.1, 1e-12);
  EXPECT_NEAR(frame_gain(events, 90, 0, 1, 1).global, 0.1, 1e-12);
}

TEST(FrameGain, OverexposureRampsInAndOut) {
  const std::vector<IlluminationEvent> events{parse_event("overexposure:10-20,gain=3,ramp=2")};
  EXPECT_DOUBLE_EQ(frame_gain(events, 9, 0, 1, 1).global, 1.0);
  EXPECT_NEAR(frame_gain(events, 10, 0, 1, 1).global, 1.0 + 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(frame_gain(events, 15, 0, 1, 1).global, 3.0, 1e-12);
  EXPECT_NEAR(frame_gain(events, 20, 0, 1, 1).global, 1.0 + 2.0 / 3.0, 1e-12);
}

TEST(FrameGain, FlickerFollowsTheRaisedCosine) {
  const std::vector<IlluminationEvent> events{parse_event("flicker:5-50,depth=0.6,period=4")};
  EXPECT_NEAR(frame_gain(events, 5, 0, 1, 1).global, 1.0, 1e-12);
  EXPECT_NEAR(frame_gain(events, 7, 0, 1, 1).global, 0.4, 1e-12);  // half a period: darkest
  EXPECT_NEAR(frame_gain(events, 6, 0, 1, 1).global, 0.7, 1e-12);
}

TEST(FrameGain, StereoExposureTouchesOnlyTheRightCamera) {
  const std::vector<IlluminationEvent> events{parse_event("stereo:0-")};
  EXPECT_TRUE(frame_gain(events, 3, 0, 10, 10).is_identity());
  EXPECT_DOUBLE_EQ(frame_gain(events, 3, 1, 10, 10).global, 0.5);
  EXPECT_DOUBLE_EQ(frame_gain(events, 3000, 1, 10, 10).global, 0.5);
}

TEST(FrameGain, EventsMultiply) {
  const std::vector<IlluminationEvent> events{parse_event("dim:0-10,gain=0.5"), parse_event("stereo:0-,gain=0.5")};
  EXPECT_NEAR(frame_gain(events, 10, 1, 1, 1).global, 0.25, 1e-12);
}

TEST(FrameGain, SpotlightSweepsAcrossTheImage) {
  const std::vector<IlluminationEvent> events{parse_event("spotlight:0-100,gain=2,ambient=0.25,sigma=0.1")};
  const FrameGain start = frame_gain(events, 0, 0, 200, 100);
  const FrameGain end = frame_gain(events, 100, 0, 200, 100);
  ASSERT_EQ(start.beams.size(), 1u);
  EXPECT_NEAR(start.beams[0].cx, 30.0, 1e-9);  // 15% of the width
  EXPECT_NEAR(end.beams[0].cx, 170.0, 1e-9);   // 85%
  EXPECT_NEAR(start.at(start.beams[0].cx, start.beams[0].cy), 2.0, 1e-12);
  EXPECT_NEAR(start.at(199, 0), 0.25, 0.01);  // far from the beam: ambient
}

TEST(ApplyGain, MatchesThePointwiseGainField) {
  const std::vector<IlluminationEvent> events{parse_event("spotlight:0-10,sigma=0.2"), parse_event("dim:0-10")};
  const FrameGain gain = frame_gain(events, 4, 0, 64, 48);
  cv::Mat image(48, 64, CV_32F, cv::Scalar(100.f));
  apply_gain(gain, image);
  double worst = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) worst = std::max(worst, std::abs(image.at<float>(y, x) - 100.0 * gain.at(x, y)));
  EXPECT_LT(worst, 1e-3);  // float vs double evaluation of the same Gaussian
}

// Gamma flicker: gamma 0.5 and 2.0 on alternate frames, applied to intensities normalised by the full scale.
TEST(FrameGain, GammaFlickerAlternatesAndMapsIntensitiesExactly) {
  const std::vector<IlluminationEvent> events{parse_event("gamma:10-13")};
  EXPECT_EQ(frame_gain(events, 9, 0, 8, 8).gamma, 1.0);
  EXPECT_EQ(frame_gain(events, 10, 0, 8, 8).gamma, 0.5);
  EXPECT_EQ(frame_gain(events, 11, 1, 8, 8).gamma, 2.0);
  EXPECT_EQ(frame_gain(events, 14, 0, 8, 8).gamma, 1.0);
  cv::Mat image(2, 2, CV_32F, cv::Scalar(63.75f));  // a quarter of full scale
  apply_gain(frame_gain(events, 10, 0, 2, 2), image);
  EXPECT_NEAR(image.at<float>(0, 0), 127.5f, 1e-3f);  // 255 * 0.25^0.5
  cv::Mat image16(2, 2, CV_32F, cv::Scalar(32767.5f));
  apply_gain(frame_gain(events, 11, 0, 2, 2), image16, 65535.0);
  EXPECT_NEAR(image16.at<float>(0, 0), 16383.75f, 1e-1f);  // 65535 * 0.5^2
}

}  // namespace
}  // namespace vkvo::synth
