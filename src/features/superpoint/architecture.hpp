#pragma once
// The SuperPoint architecture (DeTone et al. 2018, the Magic Leap release): its twelve convolutions in model-pack
// order. The network (features/superpoint/network.cpp) checks a pack against it; the ONNX converter
// (tools/convert/superpoint_converter.cpp) checks the graph it walks against it.
#include <array>
#include <cstddef>
#include <cstdint>

namespace vkvo::features {

enum SuperPointLayer { conv1a, conv1b, conv2a, conv2b, conv3a, conv3b, conv4a, conv4b, convPa, convPb, convDa, convDb };
inline constexpr std::size_t kSuperPointLayers = 12;
// conv1a..conv4b; the detector head (convPa, convPb) and the descriptor head (convDa, convDb) follow.
inline constexpr std::size_t kSuperPointEncoderLayers = 8;

struct SuperPointConvSpec {
  const char* name;
  std::uint32_t in, out, kernel;
};

// Encoder widths 64-64-128-128 (four levels of two 3x3 convolutions), two heads on the 128-channel trunk:
// the detector (64 cells + dustbin = 65 outputs) and the descriptor. convDb's width is the descriptor dimension:
// 256 in the release, which the converter requires; the network takes whatever width the pack has.
inline constexpr std::array<SuperPointConvSpec, kSuperPointLayers> kSuperPointArchitecture{{{"conv1a", 1, 64, 3},
                                                                                            {"conv1b", 64, 64, 3},
                                                                                            {"conv2a", 64, 64, 3},
                                                                                            {"conv2b", 64, 64, 3},
                                                                                            {"conv3a", 64, 128, 3},
                                                                                            {"conv3b", 128, 128, 3},
                                                                                            {"conv4a", 128, 128, 3},
                                                                                            {"conv4b", 128, 128, 3},
                                                                                            {"convPa", 128, 256, 3},
                                                                                            {"convPb", 256, 65, 1},
                                                                                            {"convDa", 128, 256, 3},
                                                                                            {"convDb", 256, 256, 1}}};

// A 2x2 max-pool follows each of these encoder convolutions.
inline constexpr std::array<SuperPointLayer, 3> kSuperPointPoolAfter{conv1b, conv2b, conv3b};

}  // namespace vkvo::features
