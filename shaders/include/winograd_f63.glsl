// Winograd's minimal filtering F(6x6, 3x3) (Lavin & Gray 2016; interpolation points 0, +-1, +-2, +-1/2 and
// infinity): a 6 x 6 output tile from an 8 x 8 input tile, Y = A^T [U . (B^T d B)] A. 64 multiplies per tile and
// channel pair instead of 324 (direct) or F(4x4, 3x3)'s 36 per 16 outputs: 21 % fewer GEMM multiply-adds and
// transformed values than F(4x4, 3x3), at larger transform constants (rounding: fp32 only). The 1-D transforms act
// on vec4s: 4 channels at once. Interface as winograd_f43.glsl.
#ifndef VKVO_WINOGRAD_F63_GLSL
#define VKVO_WINOGRAD_F63_GLSL

const uint kWinogradTile = 6;     // output pixels per tile side
const uint kWinogradInput = 8;    // input pixels per tile side (tile + 2)
const uint kWinogradPoints = 64;  // transformed values per tile: the GEMM batch

// B^T d for one column (or row) of 8 input values. B^T rows: [1 0 -21/4 0 21/4 0 -1 0],
// [0 1 1 -17/4 -17/4 1 1 0], [0 -1 1 17/4 -17/4 -1 1 0], [0 1/2 1/4 -5/2 -5/4 2 1 0],
// [0 -1/2 1/4 5/2 -5/4 -2 1 0], [0 2 4 -5/2 -5 1/2 1 0], [0 -2 4 5/2 -5 -1/2 1 0], [0 -1 0 21/4 0 -21/4 0 1].
// Rows 1-2, 3-4 and 5-6 are sums and differences of an even and an odd part.
vec4[8] winograd_input_1d(const vec4 d[8]) {
  const vec4 even1 = d[2] + d[6] - 4.25 * d[4], odd1 = d[1] + d[5] - 4.25 * d[3];
  const vec4 even2 = 0.25 * d[2] - 1.25 * d[4] + d[6], odd2 = 0.5 * d[1] - 2.5 * d[3] + 2.0 * d[5];
  const vec4 even3 = 4.0 * d[2] - 5.0 * d[4] + d[6], odd3 = 2.0 * d[1] - 2.5 * d[3] + 0.5 * d[5];
  return vec4[8](d[0] - d[6] + 5.25 * (d[4] - d[2]), even1 + odd1, even1 - odd1, even2 + odd2, even2 - odd2,
                 even3 + odd3, even3 - odd3, d[7] - d[1] + 5.25 * (d[3] - d[5]));
}

// A^T m for one column (or row) of 8 transformed-domain values. A^T row a: [0 1 (-1)^a 2^a (-2)^a 2^-a (-2)^-a 0],
// plus m[0] in row 0 and m[7] in row 5.
vec4[6] winograd_output_1d(const vec4 m[8]) {
  const vec4 sum12 = m[1] + m[2], diff12 = m[1] - m[2];
  const vec4 sum34 = m[3] + m[4], diff34 = m[3] - m[4];
  const vec4 sum56 = m[5] + m[6], diff56 = m[5] - m[6];
  return vec4[6](m[0] + sum12 + sum34 + sum56, diff12 + 2.0 * diff34 + 0.5 * diff56,
                 sum12 + 4.0 * sum34 + 0.25 * sum56, diff12 + 8.0 * diff34 + 0.125 * diff56,
                 sum12 + 16.0 * sum34 + 0.0625 * sum56, diff12 + 32.0 * diff34 + 0.03125 * diff56 + m[7]);
}

#endif
