#pragma once
// TEST / DEVELOPMENT ONLY. A fast CPU PointFrontend built from OpenCV ORB (FAST corners on a pyramid + rotated
// BRIEF) and brute-force mutual nearest-neighbour Hamming matching. It exists so the VO (tracker, keyframes,
// stereo initialisation, BA, recovery) can be exercised end to end on real-looking images in seconds, without
// waiting for SuperPoint on a CPU Vulkan driver. It lives in tests/ and is deliberately not linked into the
// library or the CLI: the product always runs the real SuperPoint network.
#include <opencv2/core.hpp>

#include "system/point_frontend.hpp"

namespace vkvo::test {

struct OpencvFrontendParams {
  int max_keypoints = 600;  // strongest responses kept, after spreading over a grid
  int grid_cells_x = 8;     // keypoints are spread over grid_cells_x x grid_cells_y cells (same quota each)
  int grid_cells_y = 6;
  int fast_threshold = 12;  // FAST intensity threshold (ORB's default is 20; low-contrast scenes need less)
  int pyramid_levels = 4;
  bool subpixel = true;  // refine level-0 corners with cv::cornerSubPix (stereo depth needs sub-pixel x)
  int patch_size = 23;   // ORB patch; also the border that stays free of keypoints
  int max_hamming = 64;  // of 256 bits: matches farther apart are rejected
  double ratio = 0.9;    // best / second-best Hamming distance; 1 disables the ratio test
};

class OpencvFrontend final : public system::PointFrontend {
 public:
  explicit OpencvFrontend(const OpencvFrontendParams& params = {});

  // Keypoints sorted by FAST/Harris response, descriptors as 256 columns of +-1/16 (the ORB bits, unit rows):
  // the dot product of two rows is 1 - 2 * hamming / 256.
  features::PointFeatures detect(const cv::Mat& gray) override;
  // Mutual nearest neighbours in Hamming distance with the distance and ratio gates.
  features::PointMatches match(const features::PointFeatures& a, const features::PointFeatures& b) override;

 private:
  OpencvFrontendParams params_;
};

}  // namespace vkvo::test
