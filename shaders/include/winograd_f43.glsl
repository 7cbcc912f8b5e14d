// Winograd's minimal filtering F(4x4, 3x3) (Lavin & Gray, "Fast Algorithms for Convolutional Neural Networks",
// 2016): a 4 x 4 output tile of a 3x3 convolution is Y = A^T [U . (B^T d B)] A, with d the 6 x 6 input tile, U =
// G g G^T the transformed filter (computed on the host: runtime/winograd.cpp) and "." the element-wise product
// summed over input channels, which is a batch of 36 GEMMs. 36 multiplies per tile and channel pair instead of
// 144. The 1-D transforms below act on vec4s: 4 channels at once; winograd_f63.glsl has the same interface.
#ifndef VKVO_WINOGRAD_F43_GLSL
#define VKVO_WINOGRAD_F43_GLSL

const uint kWinogradTile = 4;    // output pixels per tile side
const uint kWinogradInput = 6;   // input pixels per tile side (tile + 2)
const uint kWinogradPoints = 36; // transformed values per tile: the GEMM batch

// B^T d for one column (or row) of 6 input values. B^T rows: [4 0 -5 0 1 0], [0 -4 -4 1 1 0], [0 4 -4 -1 1 0],
// [0 -2 -1 2 1 0], [0 2 -1 -2 1 0], [0 4 0 -5 0 1].
vec4[6] winograd_input_1d(const vec4 d[6]) {
  return vec4[6](4.0 * d[0] - 5.0 * d[2] + d[4],
                 d[3] + d[4] - 4.0 * (d[1] + d[2]),
                 d[4] - d[3] + 4.0 * (d[1] - d[2]),
                 d[4] - d[2] + 2.0 * (d[3] - d[1]),
                 d[4] - d[2] + 2.0 * (d[1] - d[3]),
                 4.0 * d[1] - 5.0 * d[3] + d[5]);
}

// A^T m for one column (or row) of 6 transformed-domain values. A^T rows: [1 1 1 1 1 0], [0 1 -1 2 -2 0],
// [0 1 1 4 4 0], [0 1 -1 8 -8 1].
vec4[4] winograd_output_1d(const vec4 m[6]) {
  const vec4 sum12 = m[1] + m[2], diff12 = m[1] - m[2];
  const vec4 sum34 = m[3] + m[4], diff34 = m[3] - m[4];
  return vec4[4](m[0] + sum12 + sum34, diff12 + 2.0 * diff34, sum12 + 4.0 * sum34, diff12 + 8.0 * diff34 + m[5]);
}

#endif
