#pragma once
// Top-view plot of an estimated trajectory against ground truth, drawn with OpenCV (no plotting dependency).
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace vkvo::eval {

struct PlotOptions {
  int width = 1000;
  int height = 800;
  std::string title;
  std::string estimate_label = "estimate";
  std::string groundtruth_label = "ground truth";
};

// The two world axes (0 = x, 1 = y, 2 = z) with the largest extent over both trajectories, in index order.
struct PlotAxes {
  int horizontal = 0;
  int vertical = 1;
};
PlotAxes choose_plot_axes(const std::vector<Eigen::Vector3d>& estimate,
                          const std::vector<Eigen::Vector3d>& groundtruth);

// Estimate (blue) and ground truth (black) projected on the chosen axes with equal scale, a metre grid with
// labelled ticks, start (circle) and end (square) markers and a legend. Either trajectory may be empty.
cv::Mat render_trajectory_plot(const std::vector<Eigen::Vector3d>& estimate,
                               const std::vector<Eigen::Vector3d>& groundtruth, const PlotOptions& options = {});

// Renders and writes a PNG (parent folders created). Throws std::runtime_error naming the file on failure.
void write_trajectory_plot(const std::filesystem::path& png, const std::vector<Eigen::Vector3d>& estimate,
                           const std::vector<Eigen::Vector3d>& groundtruth, const PlotOptions& options = {});

// Colours (BGR) used for the two curves, exposed for tests.
inline const cv::Scalar kEstimateColour{200, 90, 20};
inline const cv::Scalar kGroundTruthColour{30, 30, 30};

}  // namespace vkvo::eval
