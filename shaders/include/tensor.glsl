// Activation tensors are CHW planes with an optional zero border of `pad` pixels on every side, so 3x3
// convolutions read their neighbourhood without bounds checks. A bordered tensor's rows are padded to a multiple
// of 4 elements, so the tiled 3x3 convolution reads 4 pixels per texel from rows that start on a texel; an
// unbordered one is dense. Element (c, y, x) of a C x H x W tensor with border p lives at
//   c * (H + 2p) * S + (y + p) * S + (x + p),   S = p > 0 ? round_up(W + 2p, 4) : W   (ActivationShape::row_stride)
#ifndef VKVO_TENSOR_GLSL
#define VKVO_TENSOR_GLSL

uint row_stride(uint w, uint pad) { return pad > 0u ? (w + 2u * pad + 3u) & ~3u : w; }
uint plane_size(uint h, uint w, uint pad) { return (h + 2u * pad) * row_stride(w, pad); }
uint chw_index(uint c, uint y, uint x, uint h, uint w, uint pad) {
  return c * plane_size(h, w, pad) + (y + pad) * row_stride(w, pad) + (x + pad);
}

#endif
