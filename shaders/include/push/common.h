// Push-constant blocks are declared once, in the common subset of GLSL and C++, and included by both:
//   VKVO_PUSH_CONSTANTS(GemmPush) { uint m, n, k; ... } VKVO_PUSH_INSTANCE;
// is `layout(push_constant) uniform GemmPush { ... } p;` in a shader and `struct vkvo::shader::GemmPush { ... };` in
// C++ (runtime/push_constants.hpp includes every block). Members are 32-bit scalars (uint, float), which std430 and
// C++ lay out alike; the build asserts that each struct has the size its shaders' SPIR-V declares
// (shaders/gen/spirv_embed.cpp). A shader includes only its own block: GLSL allows one push-constant block.
#ifndef VKVO_PUSH_COMMON_H
#define VKVO_PUSH_COMMON_H

#ifdef __cplusplus
#include <cstdint>
#define VKVO_SHADER_NAMESPACE_BEGIN namespace vkvo::shader { using uint = std::uint32_t;
#define VKVO_SHADER_NAMESPACE_END }
#define VKVO_PUSH_CONSTANTS(name) struct name
#define VKVO_PUSH_INSTANCE
#else
#define VKVO_SHADER_NAMESPACE_BEGIN
#define VKVO_SHADER_NAMESPACE_END
#define VKVO_PUSH_CONSTANTS(name) layout(push_constant) uniform name
#define VKVO_PUSH_INSTANCE p
#endif

#endif
