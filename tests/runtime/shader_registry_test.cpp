// The embedded SPIR-V: every op in every precision variant, and a portability rule the CI driver does not check.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <span>
#include <stdexcept>
#include <string>

#include "runtime/shader_registry.hpp"

namespace vkvo::rt {
namespace {

// SPIR-V encodings (SPIR-V specification, sections 2.3 and 3): header words, opcodes, Dim Buffer.
constexpr std::uint32_t kSpirvMagic = 0x07230203u;
constexpr std::size_t kHeaderWords = 5;
constexpr std::uint32_t kOpTypeImage = 25, kOpTypeSampledImage = 27;
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

TEST(ShaderRegistry, EveryOpHasEveryPrecisionVariant) {
  const auto ops = shader_ops();
  ASSERT_GT(ops.size(), 20u);
  for (const auto& op : ops)
    for (const Precision precision : {Precision::fp32, Precision::fp16s, Precision::fp16}) {
      const auto words = find_shader(op, precision);
      ASSERT_GT(words.size(), kHeaderWords) << op;
      EXPECT_EQ(words[0], kSpirvMagic) << op;
    }
  EXPECT_THROW(find_shader("no_such_op", Precision::fp32), std::exception);
}

// Texel buffers must be read as images (textureBuffer), never through a sampled image of Dim Buffer
// (samplerBuffer): SPIR-V 1.6 forbids the latter and Mesa 23+ reports it as a warning at pipeline creation,
// which fails every test under validation there, while Debian 12's Mesa 22.3 says nothing (shaders/include/
// texel_buffer.glsl).
TEST(ShaderRegistry, NoShaderReadsATexelBufferThroughASampler) {
  std::size_t modules = 0, with_texel_buffers = 0;
  for (const auto& shader : detail::embedded_shaders()) {
    const BufferImages images = buffer_images({shader.words, shader.word_count});
    ++modules;
    with_texel_buffers += !images.declared.empty();
    EXPECT_TRUE(images.sampled.empty()) << shader.op << " (" << shader.variant << ")";
  }
  EXPECT_EQ(modules, shader_ops().size() * 3);
  EXPECT_GT(with_texel_buffers, 30u) << "the check must see the texel-buffer kernels";
}

// The checker itself, on a hand-assembled stream: image %1 (Dim Buffer), sampled image %2 of it.
TEST(ShaderRegistry, CheckerFindsASampledBufferImage) {
  const std::uint32_t float_type = 3;
  const std::uint32_t words[] = {kSpirvMagic, 0x00010300u, 0, 10, 0,
                                 (9u << 16) | kOpTypeImage, 1, float_type, kDimBuffer, 0, 0, 0, 1, 0,
                                 (3u << 16) | kOpTypeSampledImage, 2, 1};
  EXPECT_EQ(buffer_images(words).sampled, std::set<std::uint32_t>{1});
  const std::uint32_t clean[] = {kSpirvMagic, 0x00010300u, 0, 10, 0,
                                 (9u << 16) | kOpTypeImage, 1, float_type, kDimBuffer, 0, 0, 0, 1, 0};
  const BufferImages images = buffer_images(clean);
  EXPECT_EQ(images.declared, std::set<std::uint32_t>{1});
  EXPECT_TRUE(images.sampled.empty());
}

}  // namespace
}  // namespace vkvo::rt
