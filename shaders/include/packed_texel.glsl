// Operands read through 16-byte texels, as many values per fetch as the storage precision allows: fp32 four per
// RGBA32F texel, 16-bit storage eight halves per RGBA32UI texel (unpacked here). A texel fetch costs lavapipe
// about the same whatever the format, so packing 8 halves halves the fetches per multiply-add where an RGBA16F
// view would hold 4. The host binds the view with rt::packed_texel_format() and checks that every offset it
// fetches at is a multiple of kPerTexel elements.
//   PACKED_TEXELS(binding, name)  declares the view
//   FETCH(texels, index, dst)     dst[0 .. kVecs - 1] = the avec4s of texel `index`
//   FETCH_AS(type, texels, index, dst)  the same as vectors of `type` (vec4: fp32 math in every variant)
#ifndef VKVO_PACKED_TEXEL_GLSL
#define VKVO_PACKED_TEXEL_GLSL
#include "texel_buffer.glsl"
#include "precision.glsl"

#if defined(VKVO_VARIANT_fp32)
#define PACKED_TEXELS(binding_index, name) layout(binding = binding_index) uniform textureBuffer name
const uint kPerTexel = 4;
#define FETCH_AS(type, texels, index, dst) dst[0] = type(texelFetch(texels, int(index)))
#else
#define PACKED_TEXELS(binding_index, name) layout(binding = binding_index) uniform utextureBuffer name
const uint kPerTexel = 8;
#define FETCH_AS(type, texels, index, dst)                                          \
  {                                                                                 \
    const uvec4 halves = texelFetch(texels, int(index));                            \
    dst[0] = type(unpackHalf2x16(halves.x), unpackHalf2x16(halves.y));              \
    dst[1] = type(unpackHalf2x16(halves.z), unpackHalf2x16(halves.w));              \
  }
#endif
#define FETCH(texels, index, dst) FETCH_AS(avec4, texels, index, dst)
const uint kVecs = kPerTexel / 4;  // vec4s per texel

#endif
