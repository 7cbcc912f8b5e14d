#include "runtime/tensor_layout.hpp"

#include <stdexcept>

namespace vkvo::rt {
namespace {

// Index of OIHW weight (o, i, tap t) in the o4 layout.
std::size_t o4_index(std::size_t o, std::size_t i, std::size_t t, std::size_t in_channels, std::size_t taps) {
  return (((o / 4) * in_channels + i) * taps + t) * 4 + o % 4;
}

}  // namespace

std::vector<float> pack_conv_o4(std::span<const float> oihw, std::size_t out_channels, std::size_t in_channels,
                                std::size_t kernel_h, std::size_t kernel_w) {
  const std::size_t taps = kernel_h * kernel_w;
  if (oihw.size() != out_channels * in_channels * taps)
    throw std::invalid_argument("pack_conv_o4: weight count does not match O*I*KH*KW");
  const std::size_t blocks = round_up(out_channels, 4) / 4;
  std::vector<float> packed(blocks * in_channels * taps * 4, 0.0f);
  for (std::size_t o = 0; o < out_channels; ++o)
    for (std::size_t i = 0; i < in_channels; ++i)
      for (std::size_t t = 0; t < taps; ++t)
        packed[o4_index(o, i, t, in_channels, taps)] = oihw[(o * in_channels + i) * taps + t];
  return packed;
}

std::vector<float> unpack_conv_o4(std::span<const float> o4, std::size_t out_channels, std::size_t in_channels,
                                  std::size_t kernel_h, std::size_t kernel_w) {
  const std::size_t taps = kernel_h * kernel_w;
  if (o4.size() != round_up(out_channels, 4) * in_channels * taps)
    throw std::invalid_argument("unpack_conv_o4: weight count does not match ceil(O/4)*4*I*KH*KW");
  std::vector<float> oihw(out_channels * in_channels * taps);
  for (std::size_t o = 0; o < out_channels; ++o)
    for (std::size_t i = 0; i < in_channels; ++i)
      for (std::size_t t = 0; t < taps; ++t)
        oihw[(o * in_channels + i) * taps + t] = o4[o4_index(o, i, t, in_channels, taps)];
  return oihw;
}

std::vector<float> pad_bias_o4(std::span<const float> bias) {
  std::vector<float> padded(round_up(bias.size(), 4), 0.0f);
  std::copy(bias.begin(), bias.end(), padded.begin());
  return padded;
}

}  // namespace vkvo::rt
