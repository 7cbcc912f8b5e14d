#include "viz/topdown.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace vkvo::viz {
namespace {

constexpr int kMargin = 40;  // pixels around the drawing, the top one for the title

Eigen::Vector2d ground(const Eigen::Vector3d& p) { return {p.x(), p.z()}; }

// The q-quantile (0..1) of `values` (reordered).
double quantile(std::vector<double>& values, double q) {
  const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

struct View {
  Eigen::Vector2d low = Eigen::Vector2d::Zero();
  double pixels_per_metre = 1;
  cv::Size size;
  cv::Point operator()(const Eigen::Vector3d& p) const {
    const Eigen::Vector2d g = (ground(p) - low) * pixels_per_metre;
    // z grows upwards in the picture.
    return {kMargin + static_cast<int>(std::lround(g.x())),
            size.height - kMargin - static_cast<int>(std::lround(g.y()))};
  }
};

View fit_view(const io::MapGeometry& map, cv::Size size) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d high = -low;
  const auto include = [&](const Eigen::Vector2d& g) {
    low = low.cwiseMin(g);
    high = high.cwiseMax(g);
  };
  for (const auto& p : map.trajectory) include(ground(p));
  if (!map.points.empty()) {
    for (int axis = 0; axis < 2; ++axis) {
      std::vector<double> values;
      for (const auto& p : map.points) values.push_back(ground(p)[axis]);
      low[axis] = std::min(low[axis], quantile(values, 0.02));
      high[axis] = std::max(high[axis], quantile(values, 0.98));
    }
  }
  if (!(low.array() <= high.array()).all()) low = high = Eigen::Vector2d::Zero();  // nothing to draw
  // At least a metre across, centred on what there is.
  const Eigen::Vector2d centre = 0.5 * (low + high);
  const Eigen::Vector2d extent = (high - low).cwiseMax(1.0);
  View view;
  view.size = size;
  view.pixels_per_metre = std::min((size.width - 2 * kMargin) / extent.x(), (size.height - 2 * kMargin) / extent.y());
  // Centre the drawing in the picture.
  const Eigen::Vector2d drawable(size.width - 2 * kMargin, size.height - 2 * kMargin);
  view.low = centre - 0.5 * drawable / view.pixels_per_metre;
  return view;
}

// A bar of a round length (1, 2 or 5 times a power of ten metres) about a fifth of the picture wide.
void draw_scale_bar(cv::Mat& image, double pixels_per_metre) {
  const double target = 0.2 * image.cols / pixels_per_metre;
  const double power = std::pow(10.0, std::floor(std::log10(target)));
  double metres = power;
  for (const double step : {2.0, 5.0})
    if (step * power <= target) metres = step * power;
  const int length = static_cast<int>(std::lround(metres * pixels_per_metre));
  const cv::Point left(kMargin, image.rows - kMargin / 2);
  cv::line(image, left, left + cv::Point(length, 0), {0, 0, 0}, 2);
  cv::putText(image, fmt::format("{:g} m", metres), left + cv::Point(length + 8, 5), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              {0, 0, 0}, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat draw_topdown(const io::MapGeometry& map, cv::Size size) {
  cv::Mat image(size, CV_8UC3, topdown_colour::background);
  const View view = fit_view(map, size);
  for (const auto& p : map.points) cv::circle(image, view(p), 1, topdown_colour::point, cv::FILLED);
  for (const auto& [a, b] : map.lines) cv::line(image, view(a), view(b), topdown_colour::line, 1);
  // The start under the path, the path, then a ring at its end (a short path still shows both).
  if (!map.trajectory.empty()) cv::circle(image, view(map.trajectory.front()), 5, topdown_colour::start, cv::FILLED);
  for (std::size_t i = 1; i < map.trajectory.size(); ++i)
    cv::line(image, view(map.trajectory[i - 1]), view(map.trajectory[i]), topdown_colour::trajectory, 2);
  if (!map.trajectory.empty()) cv::circle(image, view(map.trajectory.back()), 7, topdown_colour::trajectory, 2);
  cv::putText(image,
              fmt::format("top-down (x-z of the first camera): {} poses, {} map points, {} map lines",
                          map.trajectory.size(), map.points.size(), map.lines.size()),
              {kMargin / 2, kMargin / 2 + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
  draw_scale_bar(image, view.pixels_per_metre);
  return image;
}

}  // namespace vkvo::viz
