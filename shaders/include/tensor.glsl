// Activation tensors are CHW planes with an optional zero border of `pad` pixels on every side, so 3x3
// convolutions read their neighbourhood without bounds checks. Element (c, y, x) of a C x H x W tensor with
// border p lives at  c * (H + 2p) * (W + 2p) + (y + p) * (W + 2p) + (x + p).
#ifndef VKVO_TENSOR_GLSL
#define VKVO_TENSOR_GLSL

uint plane_size(uint h, uint w, uint pad) { return (h + 2u * pad) * (w + 2u * pad); }
uint chw_index(uint c, uint y, uint x, uint h, uint w, uint pad) {
  return c * plane_size(h, w, pad) + (y + pad) * (w + 2u * pad) + (x + pad);
}

#endif
