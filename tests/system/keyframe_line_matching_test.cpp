// A new keyframe's lines paired with its reference keyframe's by appearance, on two rendered views of a textured
// wall with bars: the camera moves sideways, up and forward, so the bars' horizontal edges, which a rectified
// stereo pair cannot place, are seen from a baseline across them (the epipolar plane along them lies above the
// wall's visible part). Every edge finds its own image in the other view (also
// when that view is dim and noisy), an edge missing there stays unpaired, closed lines and given partners are left
// alone.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/core.hpp>

#include "system/keyframe_line_matching.hpp"

namespace vkvo::system {
namespace {

constexpr double kWallDepth = 3.0;  // the wall is the plane z = 3 of the first camera (the world)
const geometry::PinholeCamera kCamera{300.0, 300.0, 160.0, 120.0, 320, 240};

// A bar on the wall, [x0, x1] x [y0, y1] in metres, its grey varying along its length with its own period.
struct Bar {
  double x0, x1, y0, y1, grey, period;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

const std::vector<Bar> kBars = {
    {-0.90, -0.70, -0.50, 0.30, 130.0, 0.13},  // bar 1, vertical (edges 0-3: left, right, bottom, top)
    {0.10, 0.22, -0.35, 0.50, 120.0, 0.21},    // bar 2, vertical (4-7)
    {0.60, 0.75, -0.60, 0.10, 140.0, 0.08},    // bar 3, vertical (8-11)
    {-0.50, 0.40, 0.62, 0.72, 135.0, 0.17},    // bar 4, horizontal (12-15)
    {-0.70, 0.10, -0.85, -0.75, 125.0, 0.11},  // bar 5, horizontal (16-19)
};

double wall_grey(double x, double y) {
  for (const Bar& b : kBars)
    if (b.contains(x, y)) {
      const double along = b.x1 - b.x0 > b.y1 - b.y0 ? x : y;
      return b.grey + 45.0 * std::sin(2.0 * M_PI * along / b.period);
    }
  return 70.0 + 12.0 * std::sin(5.0 * y + 3.0 * x) + 8.0 * std::sin(11.0 * x);
}

// The wall seen from T_world_camera, 2 x 2 samples per pixel, scaled by `gain` with Gaussian noise of `noise` DN.
cv::Mat render(const Eigen::Isometry3d& T_world_camera, double gain = 1.0, double noise = 0.0) {
  cv::Mat image(kCamera.height, kCamera.width, CV_8UC1);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, noise);
  const Eigen::Vector3d C = T_world_camera.translation();
  for (int v = 0; v < kCamera.height; ++v)
    for (int u = 0; u < kCamera.width; ++u) {
      double sum = 0.0;
      for (const double du : {-0.25, 0.25})
        for (const double dv : {-0.25, 0.25}) {
          const Eigen::Vector3d r = T_world_camera.linear() * kCamera.backproject({u + du, v + dv});
          const Eigen::Vector3d X = C + (kWallDepth - C.z()) / r.z() * r;
          sum += wall_grey(X.x(), X.y());
        }
      const double grey = gain * sum / 4.0 + (noise > 0.0 ? n(rng) : 0.0);
      image.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(grey);
    }
  return image;
}

// The bars' edges as each camera sees them: per bar left, right, bottom, top.
std::vector<geometry::Segment2d> edges(const Eigen::Isometry3d& T_world_camera) {
  std::vector<geometry::Segment2d> out;
  const auto seen = [&](double x, double y) {
    return kCamera.project(T_world_camera.inverse() * Eigen::Vector3d(x, y, kWallDepth));
  };
  const auto edge = [&](double xa, double ya, double xb, double yb) {
    const Eigen::Vector2d a = seen(xa, ya), b = seen(xb, yb);
    out.emplace_back(a.x(), a.y(), b.x(), b.y());
  };
  for (const Bar& b : kBars) {
    edge(b.x0, b.y0, b.x0, b.y1);
    edge(b.x1, b.y0, b.x1, b.y1);
    edge(b.x0, b.y0, b.x1, b.y0);
    edge(b.x0, b.y1, b.x1, b.y1);
  }
  return out;
}

Eigen::Isometry3d second_pose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.25, 0.2, 0.35);
  return T;
}

struct TwoViews {
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity(), T2 = second_pose();
  cv::Mat image1 = render(T1), image2 = render(T2);
  std::vector<geometry::Segment2d> lines1 = edges(T1), lines2 = edges(T2);
  std::vector<bool> open1 = std::vector<bool>(lines1.size(), true), open2 = std::vector<bool>(lines2.size(), true);

  std::vector<int> pair(std::vector<int> partner = {}) const {
    if (partner.empty()) partner.assign(lines2.size(), -1);
    geometry::TriangulationParams gates;  // depth in [0.1, 10] m, planes 1 degree apart
    add_keyframe_partners_by_appearance(kCamera, {image2, lines2, open2, T2}, {image1, lines1, open1, T1}, gates,
                                        features::KeyframeLineMatchParams{}, partner);
    return partner;
  }
};

// Lines paired with their own image (line i of one view is line i of the other); fails on any other partner.
int correctly_paired(const std::vector<int>& partner) {
  int paired = 0;
  for (std::size_t l = 0; l < partner.size(); ++l) {
    if (partner[l] < 0) continue;
    EXPECT_EQ(partner[l], static_cast<int>(l)) << "line " << l << " paired with another edge";
    ++paired;
  }
  return paired;
}

// Short edges whose strips are steps with little along them to tell them apart are left unpaired by the margin
// rather than paired wrongly (bar 2's top edge against bar 4's short right edge: ZNCC 1.00 and 0.96); the long
// horizontal edges (bars 4 and 5), which a stereo pair cannot place, all pair.
TEST(KeyframeLineMatching, EdgesFindTheirOwnImagesInTheReferenceKeyframe) {
  const TwoViews views;
  const std::vector<int> partner = views.pair();
  EXPECT_GE(correctly_paired(partner), 18);
  for (const int horizontal : {14, 15, 18, 19}) EXPECT_EQ(partner[horizontal], horizontal);
}

TEST(KeyframeLineMatching, HoldsInADimNoisyView) {
  TwoViews views;
  views.image2 = render(views.T2, 0.15, 2.0);  // a seventh of the light, 2 DN of noise
  EXPECT_GE(correctly_paired(views.pair()), 16);
}

TEST(KeyframeLineMatching, AnEdgeMissingFromTheReferenceStaysUnpaired) {
  TwoViews views;
  const std::vector<int> all_open = views.pair();
  ASSERT_EQ(all_open[0], 0);
  // The first bar's left edge is not detected in the reference keyframe; the other three of its edges are.
  views.open1[0] = false;
  std::vector<int> partner = views.pair();
  EXPECT_EQ(partner[0], -1);
  partner[0] = all_open[0];
  EXPECT_EQ(partner, all_open);
}

TEST(KeyframeLineMatching, KeepsGivenPartnersAndLeavesClosedLines) {
  TwoViews views;
  const std::vector<int> all_open = views.pair();
  views.open2[4] = false;  // the second bar's left edge already has a map line
  std::vector<int> given(views.lines2.size(), -1);
  given[1] = 1;  // paired through the point matches
  std::vector<int> partner = views.pair(given);
  EXPECT_EQ(partner[1], 1);
  EXPECT_EQ(partner[4], -1);
  partner[4] = all_open[4];
  EXPECT_EQ(partner, all_open);
}

TEST(KeyframeLineMatching, RejectsWrongInputs) {
  const TwoViews views;
  std::vector<int> partner(3, -1);
  EXPECT_THROW(
      add_keyframe_partners_by_appearance(kCamera, {views.image2, views.lines2, views.open2, views.T2},
                                          {views.image1, views.lines1, views.open1, views.T1}, {}, {}, partner),
      std::invalid_argument);
}

}  // namespace
}  // namespace vkvo::system
