#pragma once
// SuperPoint's settings and their YAML loader, apart from the network (features/superpoint.hpp) so that
// configuration code does not parse the Vulkan headers.
#include <optional>
#include <string_view>

#include <yaml-cpp/yaml.h>

#include "runtime/precision.hpp"
#include "runtime/winograd_tile.hpp"

namespace vkvo::features {

struct SuperPointParams {
  float keypoint_threshold = 0.005f;  // on the softmax score (>= 0)
  int nms_radius = 4;                 // max-pool NMS window is (2r+1) x (2r+1)
  int remove_borders = 4;             // pixels dropped at every side of the dense score map
  int max_keypoints = 400;            // top-k by score; <= 0 keeps every keypoint
  // Keypoints at the sub-pixel peak of the score map (a parabola through the log scores of each and its neighbours,
  // per axis) rather than on the pixel grid: disparities stop being whole pixels. Off: the reference network's.
  bool subpixel = false;
  std::optional<rt::Precision> precision;  // nullopt: the device's preferred precision
  // The texel-buffer ("tiled") kernels where the device reads their formats; false runs the storage-buffer
  // kernels every device has (the fallback; tests run the network both ways).
  bool tiled_kernels = true;
  // Winograd F(m x m, 3x3) (runtime/winograd.hpp) for the 3x3 layers with a multiple of 4 input channels (all but
  // conv1a, which then runs inside conv1b's input transform): `automatic` where it measured faster, fp32 on CPU
  // devices; `on` wherever the precision is fp32 and the tiled kernels run; `off` never.
  enum class Winograd { automatic, on, off } winograd = Winograd::automatic;
  // Its output tile side m: F(6x6, 3x3) does 21 % fewer GEMM multiply-adds and stores 21 % fewer transformed values
  // than F(4x4, 3x3) (faster on lavapipe: docs/performance-history.md).
  rt::WinogradTile winograd_tile = rt::WinogradTile::f63;
};

// YAML section `point_detector`: keypoint_threshold, nms_radius, remove_borders, max_keypoints, subpixel,
// precision (auto | fp32 | fp16s | fp16), winograd (auto | on | off), winograd_tile (4 | 6). Missing keys keep the
// defaults; wrong types and values throw naming the key.
SuperPointParams load_superpoint_params(const YAML::Node& section);
// "auto", "on", "off"; nullopt for anything else.
std::optional<SuperPointParams::Winograd> parse_winograd(std::string_view text);
// 4 or 6 (the output tile side); nullopt for anything else.
std::optional<rt::WinogradTile> winograd_tile_from_side(int side);

}  // namespace vkvo::features
