#pragma once
// Cooperative matrices (tensor cores), in terms that do not depend on the extension that reports them:
// VK_NV_cooperative_matrix today, VK_KHR_cooperative_matrix later (its properties map onto the same shape).
#include <cstdint>
#include <string>
#include <string_view>

namespace vkvo::rt {

enum class CooperativeMatrixApi : std::uint8_t { none, nv };
enum class MatrixComponent : std::uint8_t { f16, f32, f64, s8, s16, s32, s64, u8, u16, u32, u64, other };
enum class MatrixScope : std::uint8_t { device, workgroup, subgroup, queue_family, other };

// One multiply-add D(MxN) = A(MxK) * B(KxN) + C(MxN) the device runs on its matrix units.
struct CooperativeMatrixShape {
  std::uint32_t m = 0, n = 0, k = 0;
  MatrixComponent a = MatrixComponent::other, b = MatrixComponent::other;
  MatrixComponent c = MatrixComponent::other, result = MatrixComponent::other;
  MatrixScope scope = MatrixScope::other;
  bool operator==(const CooperativeMatrixShape&) const = default;
};

// The shape vkvo's tensor-core kernels (gemm_coopmat.comp, conv3x3_coopmat.comp) are written for: fp16 operands,
// fp32 accumulation, 16x16x16 tiles held by one subgroup. Every NVIDIA GPU with tensor cores reports it.
inline constexpr CooperativeMatrixShape kCoopmatKernelShape{.m = 16,
                                                            .n = 16,
                                                            .k = 16,
                                                            .a = MatrixComponent::f16,
                                                            .b = MatrixComponent::f16,
                                                            .c = MatrixComponent::f32,
                                                            .result = MatrixComponent::f32,
                                                            .scope = MatrixScope::subgroup};

// What a workgroup of those kernels takes (shaders/include/coopmat_tile.glsl): four subgroups, and its staged tiles
// of A (64 x 40 fp16), B (32 x 72 fp16) and D (64 x 68 fp32) in shared memory.
inline constexpr std::uint32_t kCoopmatSubgroups = 4;
inline constexpr std::uint32_t kCoopmatSharedBytes = 64 * 40 * 2 + 32 * 72 * 2 + 64 * 68 * 4;

std::string_view to_string(MatrixComponent component);
std::string_view to_string(MatrixScope scope);
// "16x16x16 f16*f16+f32->f32 subgroup"
std::string to_string(const CooperativeMatrixShape& shape);

}  // namespace vkvo::rt
