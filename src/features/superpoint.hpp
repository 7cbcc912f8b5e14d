#pragma once
// SuperPoint (DeTone et al. 2018) on the Vulkan device: the whole network *and* its post-processing (softmax,
// depth-to-space, max-pool NMS, border removal, threshold, top-k, descriptor sampling) run as compute shaders in
// one submitted sequence; only the final keypoints, scores and descriptors (and on request the dense maps) come
// back. Buffers and the recorded sequence are kept per image size and reused.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <opencv2/core/mat.hpp>

#include "features/point_features.hpp"
#include "features/superpoint_params.hpp"
#include "io/model_pack.hpp"
#include "runtime/context.hpp"
#include "runtime/sequence.hpp"
#include "runtime/winograd.hpp"

namespace vkvo::features {

// The network's dense outputs, before NMS (the layout of the golden outputs, $VKVO_DATA/golden/superpoint/*).
struct SuperPointDense {
  int cells_h = 0, cells_w = 0;    // H/8, W/8 (floor)
  std::vector<float> scores;       // (cells_h*8) x (cells_w*8), row-major
  std::vector<float> descriptors;  // descriptor_dim x cells_h x cells_w, L2-normalised per cell
};

struct SuperPointNetwork;  // weights + pipelines (features/superpoint/network.hpp)
class SuperPointPlan;      // buffers + recorded sequence for one image size

class SuperPoint {
 public:
  // Uploads the weights of `pack` (kind superpoint) at the chosen precision. Throws if the device lacks it.
  SuperPoint(const rt::Context& context, const io::ModelPack& pack, const SuperPointParams& params = {});
  ~SuperPoint();
  SuperPoint(const SuperPoint&) = delete;
  SuperPoint& operator=(const SuperPoint&) = delete;

  // `image`: 8-bit grayscale (CV_8UC1), at least 16x16. Keypoints are score-descending. `dense`, when given,
  // receives the dense maps.
  PointFeatures detect(const cv::Mat& image, SuperPointDense* dense = nullptr);

  const SuperPointParams& params() const { return params_; }
  rt::Precision precision() const { return precision_; }
  int descriptor_dim() const { return descriptor_dim_; }
  // GPU time of each command of the last detect(), labelled by layer: empty unless profiling is on (and the device
  // has timestamps). Off by default, as for SuperGlue and the NN matcher: each timestamp costs lavapipe a context
  // flush (rt::Sequence). Takes effect at the next detect() (the per-size plans are rebuilt).
  void set_profiling(bool on);
  std::vector<rt::CommandTiming> last_timings() const;
  // Number of NMS candidates above the threshold in the last detect() (before top-k).
  std::uint32_t last_candidate_count() const { return last_candidates_; }
  // Floating-point operations of the network's convolutions for an image of this size.
  static double network_flops(int width, int height);

 private:
  SuperPointPlan& plan_for(int width, int height);

  const rt::Context& context_;
  SuperPointParams params_;
  rt::Precision precision_;
  int descriptor_dim_ = 256;
  std::unique_ptr<SuperPointNetwork> network_;  // weights + pipelines (superpoint/network.hpp)
  std::map<std::pair<int, int>, std::unique_ptr<SuperPointPlan>> plans_;
  SuperPointPlan* last_plan_ = nullptr;
  std::uint32_t last_candidates_ = 0;
  bool profiling_ = false;
};

}  // namespace vkvo::features
