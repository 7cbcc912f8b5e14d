#include "system/opencv_frontend.hpp"

#include <algorithm>
#include <limits>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace vkvo::test {

OpencvFrontend::OpencvFrontend(const OpencvFrontendParams& params) : params_(params) {}

features::PointFeatures OpencvFrontend::detect(const cv::Mat& gray) {
  features::PointFeatures out;
  out.image_width = gray.cols;
  out.image_height = gray.rows;
  out.descriptors.resize(0, 256);
  if (gray.empty()) return out;

  // Over-detect, then keep an even share of the strongest corners per grid cell so that texture-rich corners
  // of the image do not take the whole budget (a pose needs points spread over the view).
  auto orb = cv::ORB::create(params_.max_keypoints * 4, 1.2f, params_.pyramid_levels, params_.patch_size, 0, 2,
                             cv::ORB::HARRIS_SCORE, params_.patch_size, params_.fast_threshold);
  std::vector<cv::KeyPoint> keypoints;
  orb->detect(gray, keypoints);
  const int cells = params_.grid_cells_x * params_.grid_cells_y;
  std::vector<std::vector<int>> per_cell(static_cast<std::size_t>(cells));
  for (int i = 0; i < static_cast<int>(keypoints.size()); ++i) {
    const auto& p = keypoints[static_cast<std::size_t>(i)].pt;
    const int cx = std::clamp(static_cast<int>(p.x * params_.grid_cells_x / gray.cols), 0, params_.grid_cells_x - 1);
    const int cy = std::clamp(static_cast<int>(p.y * params_.grid_cells_y / gray.rows), 0, params_.grid_cells_y - 1);
    per_cell[static_cast<std::size_t>(cy * params_.grid_cells_x + cx)].push_back(i);
  }
  auto stronger = [&](int a, int b) {
    return keypoints[static_cast<std::size_t>(a)].response > keypoints[static_cast<std::size_t>(b)].response;
  };
  // Round-robin over the cells, strongest first in each, until the budget is spent.
  for (auto& c : per_cell) std::sort(c.begin(), c.end(), stronger);
  std::vector<cv::KeyPoint> kept;
  for (std::size_t rank = 0; static_cast<int>(kept.size()) < params_.max_keypoints; ++rank) {
    bool any = false;
    for (const auto& c : per_cell) {
      if (rank >= c.size()) continue;
      any = true;
      kept.push_back(keypoints[static_cast<std::size_t>(c[rank])]);
      if (static_cast<int>(kept.size()) >= params_.max_keypoints) break;
    }
    if (!any) break;
  }
  cv::Mat descriptors;
  orb->compute(gray, kept, descriptors);  // may drop keypoints it cannot describe
  if (params_.subpixel && !kept.empty()) {
    // Corners of the finest level only: a coarser level's corner has no well-defined level-0 position.
    std::vector<cv::Point2f> corners;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < kept.size(); ++i)
      if (kept[i].octave == 0) {
        corners.push_back(kept[i].pt);
        which.push_back(i);
      }
    if (!corners.empty()) {
      cv::cornerSubPix(gray, corners, cv::Size(3, 3), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 0.01));
      for (std::size_t k = 0; k < which.size(); ++k)
        if (cv::norm(corners[k] - kept[which[k]].pt) < 1.5) kept[which[k]].pt = corners[k];
    }
  }
  std::vector<int> order(kept.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return kept[static_cast<std::size_t>(a)].response > kept[static_cast<std::size_t>(b)].response;
  });

  out.descriptors.resize(static_cast<Eigen::Index>(kept.size()), 256);
  for (std::size_t r = 0; r < order.size(); ++r) {
    const int i = order[r];
    const auto& k = kept[static_cast<std::size_t>(i)];
    out.keypoints.emplace_back(k.pt.x, k.pt.y);
    out.scores.push_back(k.response);
    const unsigned char* bits = descriptors.ptr<unsigned char>(i);
    for (int b = 0; b < 256; ++b)
      out.descriptors(static_cast<Eigen::Index>(r), b) = ((bits[b / 8] >> (b % 8)) & 1) ? 1.0f / 16 : -1.0f / 16;
  }
  return out;
}

features::PointMatches OpencvFrontend::match(const features::PointFeatures& a, const features::PointFeatures& b) {
  features::PointMatches out;
  out.matches0.assign(a.size(), -1);
  out.scores0.assign(a.size(), 0.0f);
  if (a.size() == 0 || b.size() == 0) return out;
  // hamming = 128 * (1 - dot) for the +-1/16 encoding.
  const Eigen::MatrixXf dot = a.descriptors * b.descriptors.transpose();
  const auto hamming = [&](Eigen::Index i, Eigen::Index j) { return 128.0f * (1.0f - dot(i, j)); };
  std::vector<int> best_of_b(b.size(), -1);
  std::vector<float> best_distance_b(b.size(), std::numeric_limits<float>::max());
  for (Eigen::Index i = 0; i < dot.rows(); ++i)
    for (Eigen::Index j = 0; j < dot.cols(); ++j)
      if (const float d = hamming(i, j); d < best_distance_b[static_cast<std::size_t>(j)]) {
        best_distance_b[static_cast<std::size_t>(j)] = d;
        best_of_b[static_cast<std::size_t>(j)] = static_cast<int>(i);
      }
  for (Eigen::Index i = 0; i < dot.rows(); ++i) {
    float best = std::numeric_limits<float>::max(), second = best;
    Eigen::Index best_j = -1;
    for (Eigen::Index j = 0; j < dot.cols(); ++j) {
      const float d = hamming(i, j);
      if (d < best) {
        second = best;
        best = d;
        best_j = j;
      } else if (d < second) {
        second = d;
      }
    }
    if (best_j < 0 || best > static_cast<float>(params_.max_hamming)) continue;
    if (params_.ratio < 1.0 && best > params_.ratio * second) continue;
    if (best_of_b[static_cast<std::size_t>(best_j)] != static_cast<int>(i)) continue;  // not mutual
    out.matches0[static_cast<std::size_t>(i)] = static_cast<int>(best_j);
    out.scores0[static_cast<std::size_t>(i)] = 1.0f - best / 256.0f;
  }
  return out;
}

}  // namespace vkvo::test
