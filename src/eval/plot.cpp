#include "eval/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace vkvo::eval {

namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};
constexpr int kMarginLeft = 80, kMarginRight = 30, kMarginTop = 50, kMarginBottom = 60;
const cv::Scalar kGrid{225, 225, 225}, kText{40, 40, 40}, kWhite{255, 255, 255};

// A "nice" tick spacing (1, 2 or 5 times a power of ten) giving about `target` intervals over `range`.
double nice_step(double range, int target) {
  const double raw = range / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0})
    if (raw <= factor * magnitude) return factor * magnitude;
  return 10.0 * magnitude;
}

std::string tick_label(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(value) < step * 1e-6) value = 0;  // no "-0.0"
  return fmt::format("{:.{}f}", value, decimals);
}

struct Bounds {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = -Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  void add(const std::vector<Eigen::Vector3d>& points) {
    for (const auto& p : points) min = min.cwiseMin(p), max = max.cwiseMax(p);
  }
  bool valid() const { return (max.array() >= min.array()).all(); }
};

}  // namespace

PlotAxes choose_plot_axes(const std::vector<Eigen::Vector3d>& estimate,
                          const std::vector<Eigen::Vector3d>& groundtruth) {
  Bounds bounds;
  bounds.add(groundtruth);
  bounds.add(estimate);
  if (!bounds.valid()) return {};
  const Eigen::Vector3d extent = bounds.max - bounds.min;
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return extent[a] > extent[b]; });
  return {std::min(order[0], order[1]), std::max(order[0], order[1])};
}

cv::Mat render_trajectory_plot(const std::vector<Eigen::Vector3d>& estimate,
                               const std::vector<Eigen::Vector3d>& groundtruth, const PlotOptions& options) {
  cv::Mat canvas(options.height, options.width, CV_8UC3, kWhite);
  const PlotAxes axes = choose_plot_axes(estimate, groundtruth);
  Bounds bounds;
  bounds.add(groundtruth);
  bounds.add(estimate);
  if (!bounds.valid()) bounds.min.setZero(), bounds.max.setOnes();

  // Equal metres per pixel on both axes, data centred in the plot area, at least 1 mm of range.
  const int plot_w = options.width - kMarginLeft - kMarginRight;
  const int plot_h = options.height - kMarginTop - kMarginBottom;
  const double range_h = std::max(bounds.max[axes.horizontal] - bounds.min[axes.horizontal], 1e-3) * 1.08;
  const double range_v = std::max(bounds.max[axes.vertical] - bounds.min[axes.vertical], 1e-3) * 1.08;
  const double pixels_per_m = std::min(plot_w / range_h, plot_h / range_v);
  const double centre_h = 0.5 * (bounds.max[axes.horizontal] + bounds.min[axes.horizontal]);
  const double centre_v = 0.5 * (bounds.max[axes.vertical] + bounds.min[axes.vertical]);
  const auto to_pixel = [&](double h, double v) {
    return cv::Point2d(kMarginLeft + 0.5 * plot_w + (h - centre_h) * pixels_per_m,
                       kMarginTop + 0.5 * plot_h - (v - centre_v) * pixels_per_m);
  };
  const double view_h0 = centre_h - 0.5 * plot_w / pixels_per_m, view_h1 = centre_h + 0.5 * plot_w / pixels_per_m;
  const double view_v0 = centre_v - 0.5 * plot_h / pixels_per_m, view_v1 = centre_v + 0.5 * plot_h / pixels_per_m;

  // Grid and tick labels (metres).
  const double step = nice_step(std::max(view_h1 - view_h0, view_v1 - view_v0), 8);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (double h = std::ceil(view_h0 / step) * step; h <= view_h1; h += step) {
    const int x = static_cast<int>(std::lround(to_pixel(h, 0).x));
    cv::line(canvas, {x, kMarginTop}, {x, kMarginTop + plot_h}, kGrid, 1);
    cv::putText(canvas, tick_label(h, step), {x - 15, kMarginTop + plot_h + 20}, font, 0.45, kText, 1, cv::LINE_AA);
  }
  for (double v = std::ceil(view_v0 / step) * step; v <= view_v1; v += step) {
    const int y = static_cast<int>(std::lround(to_pixel(0, v).y));
    cv::line(canvas, {kMarginLeft, y}, {kMarginLeft + plot_w, y}, kGrid, 1);
    cv::putText(canvas, tick_label(v, step), {8, y + 5}, font, 0.45, kText, 1, cv::LINE_AA);
  }
  cv::rectangle(canvas, {kMarginLeft, kMarginTop}, {kMarginLeft + plot_w, kMarginTop + plot_h}, kText, 1);
  cv::putText(canvas, fmt::format("{} [m]", kAxisNames[axes.horizontal]),
              {kMarginLeft + plot_w / 2 - 20, options.height - 15}, font, 0.55, kText, 1, cv::LINE_AA);
  cv::putText(canvas, fmt::format("{} [m]", kAxisNames[axes.vertical]), {8, kMarginTop - 12}, font, 0.55, kText, 1,
              cv::LINE_AA);
  if (!options.title.empty()) cv::putText(canvas, options.title, {kMarginLeft, 30}, font, 0.6, kText, 1, cv::LINE_AA);

  // Curves: ground truth under the estimate; circle at the start, square at the end.
  const auto draw = [&](const std::vector<Eigen::Vector3d>& points, const cv::Scalar& colour, int thickness) {
    if (points.empty()) return;
    std::vector<cv::Point> polyline;
    for (const auto& p : points) {
      const cv::Point2d q = to_pixel(p[axes.horizontal], p[axes.vertical]);
      polyline.emplace_back(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y)));
    }
    cv::polylines(canvas, polyline, false, colour, thickness, cv::LINE_AA);
    cv::circle(canvas, polyline.front(), 6, colour, 2, cv::LINE_AA);
    cv::rectangle(canvas, polyline.back() - cv::Point(5, 5), polyline.back() + cv::Point(5, 5), colour, 2);
  };
  draw(groundtruth, kGroundTruthColour, 2);
  draw(estimate, kEstimateColour, 2);

  // Legend, top right inside the plot.
  const cv::Point legend(kMarginLeft + plot_w - 190, kMarginTop + 12);
  cv::rectangle(canvas, legend, legend + cv::Point(180, 54), kWhite, cv::FILLED);
  cv::rectangle(canvas, legend, legend + cv::Point(180, 54), kText, 1);
  const std::pair<const std::string*, cv::Scalar> entries[] = {{&options.groundtruth_label, kGroundTruthColour},
                                                               {&options.estimate_label, kEstimateColour}};
  for (int k = 0; k < 2; ++k) {
    const cv::Point row = legend + cv::Point(10, 18 + 22 * k);
    cv::line(canvas, row, row + cv::Point(30, 0), entries[k].second, 3, cv::LINE_AA);
    cv::putText(canvas, *entries[k].first, row + cv::Point(40, 5), font, 0.5, kText, 1, cv::LINE_AA);
  }
  return canvas;
}

void write_trajectory_plot(const std::filesystem::path& png, const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& groundtruth, const PlotOptions& options) {
  if (png.has_parent_path()) std::filesystem::create_directories(png.parent_path());
  const cv::Mat image = render_trajectory_plot(estimate, groundtruth, options);
  bool ok = false;
  try {
    ok = cv::imwrite(png.string(), image);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot write plot ({})", png.string(), e.what()));
  }
  if (!ok) throw std::runtime_error(fmt::format("{}: cannot write plot", png.string()));
}

}  // namespace vkvo::eval
