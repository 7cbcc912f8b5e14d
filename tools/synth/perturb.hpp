#pragma once
// Applies illumination events to an existing stereo sequence, for stress tests on real data. The copy keeps
// everything but the pixels of affected frames byte-identical: calibration, ground truth, CSVs, timestamps, file
// names, and the images of frames no event touches. Supported layouts:
//   ASL/EuRoC: SRC/mav0/cam{0,1}/data.csv + data/*.png (SRC may also be the mav0 folder itself)
//   KITTI:     SRC/image_0 + image_1 (or image_l + image_r), calib.txt, poses.txt / times.txt when present
// Frame k is the k-th row of cam<c>/data.csv (ASL) or the k-th file in name order (KITTI).
#include <cstdint>
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "tools/synth/illumination.hpp"

namespace vkvo::synth {

struct PerturbOptions {
  double noise_sigma = 0.0;  // Gaussian read noise (DN) added to affected frames after the gain; 0: none
  uint64_t seed = 1;
};

enum class SequenceLayout { asl, kitti };

struct StereoImageLists {
  SequenceLayout layout = SequenceLayout::asl;
  std::filesystem::path left_dir, right_dir;
  std::vector<std::filesystem::path> left, right;  // relative to left_dir / right_dir, in frame order
};

// Finds the stereo image lists of a sequence folder; throws std::runtime_error when it is neither layout.
StereoImageLists find_stereo_images(const std::filesystem::path& sequence_dir);

// Gain (and noise) on one image of any depth (8/16-bit, float; 1 or 3 channels): same size, type and channels.
cv::Mat perturb_image(const cv::Mat& image, const FrameGain& gain, double noise_sigma, uint64_t noise_stream);

// Copies `src` to `dst` (created; must not lie inside src) and rewrites the images the events affect.
void perturb_sequence(const std::filesystem::path& src, const std::filesystem::path& dst,
                      const std::vector<IlluminationEvent>& events, const PerturbOptions& options = {});

}  // namespace vkvo::synth
