#pragma once
// Weight layouts the convolution/GEMM shaders read (the converter writes packs in these layouts).
//
// conv "o4": OIHW weights regrouped as [ceil(O/4)][I][KH][KW][4]: each vec4 holds one tap of four consecutive
// output channels, so an invocation that computes a block of output channels streams its weights as vec4s.
// Output channels beyond O are zero (e.g. SuperPoint's 65-channel detector head is padded to 68).
#include <cstddef>
#include <span>
#include <vector>

namespace vkvo::rt {

inline constexpr std::size_t round_up(std::size_t value, std::size_t multiple) {
  return (value + multiple - 1) / multiple * multiple;
}

// oihw: O*I*KH*KW floats in PyTorch order. Returns round_up(O,4)*I*KH*KW floats in the "o4" layout.
std::vector<float> pack_conv_o4(std::span<const float> oihw, std::size_t out_channels, std::size_t in_channels,
                                std::size_t kernel_h, std::size_t kernel_w);
// The inverse of pack_conv_o4: O*I*KH*KW floats in PyTorch order (for a 1x1 layer, the O x I matrix row-major).
std::vector<float> unpack_conv_o4(std::span<const float> o4, std::size_t out_channels, std::size_t in_channels,
                                  std::size_t kernel_h, std::size_t kernel_w);
// Bias padded with zeros to round_up(O, 4).
std::vector<float> pad_bias_o4(std::span<const float> bias);

}  // namespace vkvo::rt
