// The shader table as embedded: every op has the variants the table lists and only those, each a SPIR-V module
// whose reflected interface the runtime relies on; and a portability rule the CI driver does not check.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <span>
#include <stdexcept>
#include <string>

#include "common/test_support.hpp"
#include "runtime/push_constants.hpp"
#include "runtime/shader_registry.hpp"

namespace vkvo::rt {
namespace {

// SPIR-V encodings (SPIR-V specification, sections 2.3 and 3): header words, opcodes, Dim Buffer.
constexpr std::uint32_t kSpirvMagic = 0x07230203u;
constexpr std::size_t kHeaderWords = 5;
constexpr std::uint32_t kOpCapability = 17, kOpTypeImage = 25, kOpTypeSampledImage = 27;
constexpr std::uint32_t kCapabilityVulkanMemoryModel = 5345, kCapabilityCooperativeMatrixNV = 5357;
constexpr std::uint32_t kDimBuffer = 5;

// The image types with Dim Buffer that a module declares, and those of them an OpTypeSampledImage wraps.
struct BufferImages {
  std::set<std::uint32_t> declared, sampled;
};

BufferImages buffer_images(std::span<const std::uint32_t> words) {
  BufferImages images;
  for (std::size_t at = kHeaderWords; at < words.size();) {
    const std::uint32_t count = words[at] >> 16, opcode = words[at] & 0xffffu;
    if (count == 0 || at + count > words.size()) throw std::runtime_error("malformed instruction stream");
    if (opcode == kOpTypeImage && count > 3 && words[at + 3] == kDimBuffer) images.declared.insert(words[at + 1]);
    if (opcode == kOpTypeSampledImage && count > 2 && images.declared.contains(words[at + 2]))
      images.sampled.insert(words[at + 2]);
    at += count;
  }
  return images;
}

TEST(ShaderRegistry, EveryOpHasExactlyTheVariantsOfTheTable) {
  ASSERT_EQ(detail::op_table().size(), kOpCount);
  std::size_t variants = 0;
  for (std::size_t i = 0; i < kOpCount; ++i) {
    const Op op = static_cast<Op>(i);
    const OpInfo& info = op_info(op);
    if (!info.per_precision()) {
      const auto words = find_shader(op, std::nullopt).spirv();
      ASSERT_GT(words.size(), kHeaderWords) << info.name;
      EXPECT_EQ(words[0], kSpirvMagic) << info.name;
      EXPECT_THROW(find_shader(op, Precision::fp32), std::invalid_argument) << info.name;
      ++variants;
      continue;
    }
    EXPECT_THROW(find_shader(op, std::nullopt), std::invalid_argument) << info.name;
    for (const Precision p : kAllPrecisions) {
      if (!info.compiled_for(p)) {
        EXPECT_THROW(find_shader(op, p), std::invalid_argument) << info.name << " " << to_string(p);
        continue;
      }
      const auto words = find_shader(op, p).spirv();
      ASSERT_GT(words.size(), kHeaderWords) << info.name;
      EXPECT_EQ(words[0], kSpirvMagic) << info.name;
      ++variants;
    }
  }
  EXPECT_EQ(variants, detail::embedded_shaders().size());
}

// Winograd's transforms need more than 16 bits (runtime/winograd.hpp): only their fp32 variant is built.
TEST(ShaderRegistry, WinogradIsCompiledForFp32Only) {
  EXPECT_TRUE(op_info(Op::winograd_f43_input).compiled_for(Precision::fp32));
  EXPECT_FALSE(op_info(Op::winograd_f43_input).compiled_for(Precision::fp16s));
  const std::string error = test::error_of([] { find_shader(Op::winograd_f63_output, Precision::fp16); });
  EXPECT_NE(error.find("shader winograd_f63_output has no fp16 variant: the shader table compiles it for fp32 only"),
            std::string::npos)
      << error;
  EXPECT_EQ(op_info(Op::winograd_f43_input_wide).feature, ShaderFeature::int64);
  EXPECT_EQ(op_info(Op::winograd_f43_input).feature, ShaderFeature::none);
}

std::set<std::uint32_t> capabilities(std::span<const std::uint32_t> words) {
  std::set<std::uint32_t> result;
  for (std::size_t at = kHeaderWords; at < words.size();) {
    const std::uint32_t count = words[at] >> 16, opcode = words[at] & 0xffffu;
    if (count == 0 || at + count > words.size()) throw std::runtime_error("malformed instruction stream");
    if (opcode == kOpCapability && count == 2) result.insert(words[at + 1]);
    at += count;
  }
  return result;
}

// The tensor-core kernels are the NV cooperative-matrix form (which declares the Vulkan memory model the context
// enables with it), built at the 16-bit storage precisions only, and need the device's shape; no other op uses
// cooperative matrices, so the fallbacks run everywhere.
TEST(ShaderRegistry, TensorCoreKernelsAreTheOnlyCooperativeMatrixOps) {
  for (const Op op : {Op::gemm_coopmat, Op::conv3x3_coopmat}) {
    const OpInfo& info = op_info(op);
    EXPECT_EQ(info.feature, ShaderFeature::cooperative_matrix) << info.name;
    EXPECT_FALSE(info.compiled_for(Precision::fp32)) << info.name;
    for (const Precision p : {Precision::fp16s, Precision::fp16}) {
      ASSERT_TRUE(info.compiled_for(p)) << info.name;
      const auto caps = capabilities(find_shader(op, p).spirv());
      EXPECT_TRUE(caps.contains(kCapabilityCooperativeMatrixNV)) << info.name;
      EXPECT_TRUE(caps.contains(kCapabilityVulkanMemoryModel)) << info.name;
    }
  }
  for (const auto& shader : detail::embedded_shaders()) {
    const bool cooperative = capabilities(shader.spirv()).contains(kCapabilityCooperativeMatrixNV);
    EXPECT_EQ(cooperative, op_info(shader.op).feature == ShaderFeature::cooperative_matrix) << to_string(shader.op);
  }
  // Their interfaces are those of the SIMT kernels they stand in for.
  const ShaderInterface& gemm = *find_shader(Op::gemm_coopmat, Precision::fp16s).interface;
  ASSERT_EQ(gemm.binding_count, 4u);
  EXPECT_TRUE(gemm.bindings[3].read && gemm.bindings[3].write);  // C, read when accumulating
  EXPECT_EQ(gemm.push_constant_bytes, sizeof(shader::GemmPush));
  const ShaderInterface& conv = *find_shader(Op::conv3x3_coopmat, Precision::fp16).interface;
  ASSERT_EQ(conv.binding_count, 4u);
  EXPECT_FALSE(conv.bindings[3].read);
  EXPECT_EQ(conv.push_constant_bytes, sizeof(shader::Conv3x3Push));
  EXPECT_EQ(conv.specialization_constants, 1u);  // the workgroup size: four subgroups
}

// The interfaces the build reflected from the SPIR-V, for a few ops whose GLSL declares them plainly: the counts,
// kinds and access the host once typed by hand.
TEST(ShaderRegistry, ReflectedInterfacesMatchTheShaders) {
  const ShaderInterface& gemm = *find_shader(Op::gemm_tiled, Precision::fp16s).interface;
  ASSERT_EQ(gemm.binding_count, 4u);
  EXPECT_EQ(gemm.bindings[0].kind, BindingKind::uniform_texel_buffer);  // A
  EXPECT_EQ(gemm.bindings[1].kind, BindingKind::uniform_texel_buffer);  // B
  EXPECT_EQ(gemm.bindings[2].kind, BindingKind::storage_buffer);        // bias, readonly
  EXPECT_TRUE(gemm.bindings[2].read);
  EXPECT_FALSE(gemm.bindings[2].write);
  EXPECT_TRUE(gemm.bindings[3].read);  // C, read when accumulating
  EXPECT_TRUE(gemm.bindings[3].write);
  EXPECT_EQ(gemm.push_constant_bytes, sizeof(shader::GemmPush));
  EXPECT_EQ(gemm.specialization_constants, 4u);

  const ShaderInterface& sinkhorn = *find_shader(Op::superglue_sinkhorn, std::nullopt).interface;
  ASSERT_EQ(sinkhorn.binding_count, 3u);
  EXPECT_FALSE(sinkhorn.bindings[0].write);  // Z, readonly
  EXPECT_TRUE(sinkhorn.bindings[1].write);   // u
  EXPECT_TRUE(sinkhorn.bindings[2].write);   // v
  EXPECT_EQ(sinkhorn.push_constant_bytes, sizeof(shader::SinkhornPush));

  const ShaderInterface& mutual = *find_shader(Op::superglue_mutual, std::nullopt).interface;
  ASSERT_EQ(mutual.binding_count, 4u);
  EXPECT_FALSE(mutual.bindings[2].read);  // matches, writeonly
  EXPECT_TRUE(mutual.bindings[2].write);
  EXPECT_EQ(mutual.specialization_constants, 0u);
}

// Texel buffers must be read as images (textureBuffer), never through a sampled image of Dim Buffer
// (samplerBuffer): SPIR-V 1.6 forbids the latter and Mesa 23+ reports it as a warning at pipeline creation,
// which fails every test under validation there, while Debian 12's Mesa 22.3 says nothing (shaders/include/
// texel_buffer.glsl).
TEST(ShaderRegistry, NoShaderReadsATexelBufferThroughASampler) {
  std::size_t with_texel_buffers = 0;
  for (const auto& shader : detail::embedded_shaders()) {
    const BufferImages images = buffer_images(shader.spirv());
    with_texel_buffers += !images.declared.empty();
    EXPECT_TRUE(images.sampled.empty()) << to_string(shader.op) << " ("
                                        << (shader.precision ? to_string(*shader.precision) : "any") << ")";
  }
  EXPECT_GT(with_texel_buffers, 30u) << "the check must see the texel-buffer kernels";
}

// The checker itself, on a hand-assembled stream: image %1 (Dim Buffer), sampled image %2 of it.
TEST(ShaderRegistry, CheckerFindsASampledBufferImage) {
  const std::uint32_t float_type = 3;
  const std::uint32_t words[] = {
      kSpirvMagic, 0x00010300u, 0, 10, 0, (9u << 16) | kOpTypeImage,        1, float_type, kDimBuffer,
      0,           0,           0, 1,  0, (3u << 16) | kOpTypeSampledImage, 2, 1};
  EXPECT_EQ(buffer_images(words).sampled, std::set<std::uint32_t>{1});
  const std::uint32_t clean[] = {
      kSpirvMagic, 0x00010300u, 0, 10, 0, (9u << 16) | kOpTypeImage, 1, float_type, kDimBuffer, 0, 0, 0, 1, 0};
  const BufferImages images = buffer_images(clean);
  EXPECT_EQ(images.declared, std::set<std::uint32_t>{1});
  EXPECT_TRUE(images.sampled.empty());
}

}  // namespace
}  // namespace vkvo::rt
