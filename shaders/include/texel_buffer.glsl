// Texel buffers are declared as textureBuffer / utextureBuffer (Vulkan GLSL's image without a sampler) and read
// with texelFetch: SPIR-V then fetches from the image itself. A samplerBuffer would wrap it in an
// OpTypeSampledImage of Dim Buffer, which SPIR-V 1.6 forbids and Mesa 23 and later warn about at pipeline
// creation (a validation message, so a failed test, on Debian 13's lavapipe). Same descriptor type either way.
#ifndef VKVO_TEXEL_BUFFER_GLSL
#define VKVO_TEXEL_BUFFER_GLSL
#extension GL_EXT_samplerless_texture_functions : require
#endif
