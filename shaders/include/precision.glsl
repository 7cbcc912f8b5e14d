// Precision variants: every shader includes this header and is compiled once per variant
// (cmake/VkvoShaders.cmake passes -DVKVO_VARIANT_<name>=1).
//   sfloat/svec4 : element types of tensors in storage buffers
//   afloat/avec4 : arithmetic type of the inner products
//   wvec4        : convolution weights in storage buffers (4 output channels). fp32 in the 16-bit-storage variant:
//                  SuperPoint's dense scores are far more sensitive to rounded weights than to rounded
//                  activations (runtime/ops.hpp, conv_weight_precision)
//   float/vec4   : accumulators and anything numerically delicate (softmax, norms, Sinkhorn) in every variant
#ifndef VKVO_PRECISION_GLSL
#define VKVO_PRECISION_GLSL

#if defined(VKVO_VARIANT_fp32)
#define sfloat float
#define svec2 vec2
#define svec4 vec4
#define afloat float
#define avec4 vec4
#define wvec4 vec4
#elif defined(VKVO_VARIANT_fp16s)
#extension GL_EXT_shader_16bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#define sfloat float16_t
#define svec2 f16vec2
#define svec4 f16vec4
#define afloat float
#define avec4 vec4
#define wvec4 vec4
#elif defined(VKVO_VARIANT_fp16)
#extension GL_EXT_shader_16bit_storage : require
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#define sfloat float16_t
#define svec2 f16vec2
#define svec4 f16vec4
#define afloat float16_t
#define avec4 f16vec4
#define wvec4 f16vec4
#define VKVO_FP16_MATH 1
#else
#error "compile with -DVKVO_VARIANT_fp32, _fp16s or _fp16"
#endif

#endif
