// Model pack format: round trip of small synthetic tensors, fp16 rounding, checksum, and the precise errors for
// truncated, corrupted, wrong-kind, wrong-version and incomplete packs.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "convert/convert_test_support.hpp"
#include "io/model_pack.hpp"
#include "runtime/tensor_layout.hpp"

namespace vkvo::io {
namespace {

using convert::test::expect_error;

std::vector<float> random_values(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> dist(0.0f, 0.5f);
  std::vector<float> values(count);
  for (auto& v : values) v = dist(rng);
  return values;
}

std::vector<std::byte> read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(chars.size());
  std::memcpy(bytes.data(), chars.data(), chars.size());
  return bytes;
}

void write_file(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A small superpoint-kind pack: a 5x2x3x3 conv in "o4" (O padded to 8), its bias, a 3x4 "oi" linear, and a
// 2x3 dense tensor stored as fp32 only.
struct SmallPack {
  std::vector<float> conv_oihw = random_values(5 * 2 * 3 * 3, 1);
  std::vector<float> conv_bias = random_values(5, 2);
  std::vector<float> linear = random_values(3 * 4, 3);
  std::vector<float> dense = {1.0f, -2.0f, 0.5f, 1.0f / 3.0f, 65504.0f, std::ldexp(1.0f, -24)};

  ModelPackWriter writer() const {
    ModelPackWriter w(NetworkKind::superpoint);
    w.set_number("descriptor_dim", 256);
    w.set_number("bin_score", 1.25);
    w.set_string("source", "unit test");
    w.set_numbers("widths", {32, 64, 128});
    w.add_tensor("conv.weight", {5, 2, 3, 3}, "o4", rt::pack_conv_o4(conv_oihw, 5, 2, 3, 3));
    w.add_tensor("conv.bias", {5}, "o4", rt::pad_bias_o4(conv_bias));
    w.add_tensor("linear.weight", {3, 4}, "oi", linear);
    w.add_tensor("table", {2, 3}, "dense", dense, {DType::fp32});
    return w;
  }
  std::filesystem::path write(const std::string& tag) const {
    const auto path = test::temp_dir(tag) / "small.vkvopack";
    writer().write(path);
    return path;
  }
};

TEST(ModelPack, Fnv1a64MatchesPublishedVectors) {
  auto hash = [](const std::string& text) {
    return fnv1a64(std::span(reinterpret_cast<const std::byte*>(text.data()), text.size()));
  };
  // Reference values of the 64-bit FNV-1a test suite (Fowler/Noll/Vo).
  EXPECT_EQ(hash(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(hash("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(hash("foobar"), 0x85944171f73967e8ULL);
}

TEST(ModelPack, StoredElementCountPadsO4) {
  const std::vector<std::int64_t> conv{65, 256, 1, 1}, bias{65}, linear{3, 4};
  EXPECT_EQ(stored_element_count("o4", conv), 68u * 256u);
  EXPECT_EQ(stored_element_count("o4", bias), 68u);
  EXPECT_EQ(stored_element_count("oi", linear), 12u);
  EXPECT_THROW(stored_element_count("nchw", linear), std::invalid_argument);
  EXPECT_THROW(stored_element_count("oi", conv), std::invalid_argument);
}

TEST(ModelPack, RoundTripKeepsHyperParametersAndTensors) {
  const SmallPack small;
  const auto path = small.write("pack_round_trip");
  const ModelPack pack = ModelPack::load(path, NetworkKind::superpoint);

  EXPECT_EQ(pack.kind(), NetworkKind::superpoint);
  EXPECT_EQ(pack.format_version(), kPackFormatVersion);
  EXPECT_EQ(pack.integer("descriptor_dim"), 256);
  EXPECT_EQ(pack.number("bin_score"), 1.25);
  EXPECT_EQ(pack.string("source"), "unit test");
  EXPECT_EQ(pack.numbers("widths"), (std::vector<double>{32, 64, 128}));
  EXPECT_EQ(pack.tensors().size(), 7u);  // three tensors twice (fp32 + fp16), one fp32 only

  // fp32 copies are bit-exact; o4 packing is the runtime's.
  EXPECT_EQ(pack.floats("conv.weight", DType::fp32), rt::pack_conv_o4(small.conv_oihw, 5, 2, 3, 3));
  EXPECT_EQ(pack.floats("conv.bias", DType::fp32), rt::pad_bias_o4(small.conv_bias));
  EXPECT_EQ(pack.floats("linear.weight", DType::fp32), small.linear);
  EXPECT_EQ(pack.floats("table", DType::fp32), small.dense);
  EXPECT_FALSE(pack.has_tensor("table", DType::fp16));

  const PackedTensor& conv = pack.tensor("conv.weight", DType::fp16);
  EXPECT_EQ(conv.layout, "o4");
  EXPECT_EQ(conv.shape, (std::vector<std::int64_t>{5, 2, 3, 3}));
  EXPECT_EQ(conv.byte_size, 8u * 2 * 3 * 3 * 2);
  EXPECT_EQ(conv.logical_element_count(), 90u);
  EXPECT_EQ(conv.stored_element_count(), 144u);

  // fp16 copies are the round-to-nearest halves of the fp32 values: relative error <= 2^-11 for normal values.
  const auto f32 = pack.floats("linear.weight", DType::fp32);
  const auto f16 = pack.floats("linear.weight", DType::fp16);
  ASSERT_EQ(f16.size(), f32.size());
  for (std::size_t i = 0; i < f32.size(); ++i) EXPECT_LE(std::abs(f16[i] - f32[i]), std::ldexp(std::abs(f32[i]), -11));

  // Every tensor starts on the upload alignment, in the file and in memory.
  for (const auto& t : pack.tensors()) {
    EXPECT_EQ(t.offset % kPackAlignment, 0u) << t.name;
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(pack.data(t.name, t.dtype).data()) % kPackAlignment, 0u) << t.name;
    EXPECT_LE(t.offset + t.byte_size, pack.data_block().size());
  }
}

TEST(ModelPack, SerializeIsDeterministic) {
  const SmallPack small;
  EXPECT_EQ(small.writer().serialize(), small.writer().serialize());
}

TEST(ModelPack, WriterRejectsWrongCountsAndDuplicates) {
  ModelPackWriter w(NetworkKind::superglue);
  const std::vector<float> six(6, 1.0f);
  EXPECT_THROW(w.add_tensor("x", {5}, "o4", six), std::invalid_argument);  // o4 of 5 stores 8
  w.add_tensor("x", {2, 3}, "oi", six);
  EXPECT_THROW(w.add_tensor("x", {2, 3}, "oi", six, {DType::fp16}), std::invalid_argument);
}

TEST(ModelPack, TruncatedPackIsReported) {
  const auto path = SmallPack{}.write("pack_truncated");
  auto bytes = read_file(path);
  const auto full = bytes.size();
  bytes.resize(full - 100);
  write_file(path, bytes);
  expect_error([&] { ModelPack::load(path, NetworkKind::superpoint); },
               {path.string(), "truncated", std::to_string(full), std::to_string(full - 100)});
  bytes.resize(20);
  write_file(path, bytes);
  expect_error([&] { ModelPack::load(path, NetworkKind::superpoint); }, {path.string(), "truncated", "header"});
}

TEST(ModelPack, CorruptedPackFailsTheChecksum) {
  const auto path = SmallPack{}.write("pack_corrupted");
  const auto original = read_file(path);
  // One flipped bit in the data block, then one in the tensor table.
  for (const std::size_t at : {original.size() - 7, kPackHeaderBytes + 30}) {
    auto bytes = original;
    bytes[at] ^= std::byte{0x10};
    write_file(path, bytes);
    expect_error([&] { ModelPack::load(path, NetworkKind::superpoint); }, {path.string(), "checksum mismatch"});
  }
}

TEST(ModelPack, WrongKindIsReported) {
  const auto path = SmallPack{}.write("pack_wrong_kind");
  expect_error([&] { ModelPack::load(path, NetworkKind::superglue); },
               {path.string(), "holds a superpoint network", "superglue network was asked for"});
}

TEST(ModelPack, WrongVersionIsReported) {
  const auto path = SmallPack{}.write("pack_wrong_version");
  auto bytes = read_file(path);
  const std::uint32_t future = kPackFormatVersion + 1;
  std::memcpy(bytes.data() + 8, &future, sizeof(future));
  write_file(path, bytes);
  expect_error([&] { ModelPack::load(path, NetworkKind::superpoint); },
               {path.string(), "format version " + std::to_string(future), "reads version 1"});
}

TEST(ModelPack, ForeignFileAndMissingFileAreReported) {
  const auto dir = test::temp_dir("pack_foreign");
  const auto path = dir / "not_a_pack.onnx";
  write_file(path, std::vector<std::byte>(128, std::byte{0x42}));
  expect_error([&] { ModelPack::load(path, NetworkKind::superpoint); }, {path.string(), "bad magic"});
  expect_error([&] { ModelPack::load(dir / "absent.vkvopack", NetworkKind::superpoint); },
               {"absent.vkvopack", "cannot open"});
}

// Issue 36: a directory given as the model used to end in std::bad_alloc.
TEST(ModelPack, DirectoryIsReportedByName) {
  const auto dir = test::temp_dir("pack_directory");
  expect_error([&] { ModelPack::load(dir, NetworkKind::superpoint); }, {dir.string(), "is a directory"});
}

TEST(ModelPack, MissingTensorAndHyperParameterAreNamed) {
  const auto path = SmallPack{}.write("pack_missing");
  const ModelPack pack = ModelPack::load(path, NetworkKind::superpoint);
  expect_error([&] { pack.tensor("convPb.weight", DType::fp32); }, {path.string(), "convPb.weight", "fp32"});
  expect_error([&] { pack.data("table", DType::fp16); }, {"table", "fp16"});
  expect_error([&] { pack.number("gnn_layers"); }, {path.string(), "gnn_layers"});
  expect_error([&] { pack.string("descriptor_dim"); }, {"descriptor_dim", "not a string"});
  expect_error([&] { pack.integer("bin_score"); }, {"bin_score", "not an integer"});
}

}  // namespace
}  // namespace vkvo::io
