// .npy reader/writer: round trips, headers as NumPy writes them, and clear errors on bad files.
#include <cstring>
#include <fstream>
#include <string>

#include "common/test_support.hpp"
#include "io/npy.hpp"

namespace vkvo::io {
namespace {

// Builds a format-1.0 file the way NumPy does, from a header dict and raw data bytes.
std::string npy_bytes(const std::string& dict, const std::string& data) {
  std::string header = dict;
  while ((10 + header.size() + 1) % 64 != 0) header.push_back(' ');
  header.push_back('\n');
  std::string out = std::string("\x93NUMPY", 6) + std::string("\x01\x00", 2);
  out.push_back(static_cast<char>(header.size() & 0xff));
  out.push_back(static_cast<char>(header.size() >> 8));
  return out + header + data;
}

TEST(Npy, FloatRoundTripKeepsShapeAndValues) {
  const auto path = test::temp_dir("npy") / "kp.npy";
  const std::vector<float> values = {1.5f, -2.25f, 3.0f, 4.125f, 0.0f, -0.5f};
  write_npy(path, {3, 2}, values.data());
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.dtype, "<f4");
  ASSERT_EQ(array.shape, (std::vector<size_t>{3, 2}));
  EXPECT_EQ(array.to_floats(), values);
}

TEST(Npy, Int32RoundTripOneDimensional) {
  const auto path = test::temp_dir("npy") / "m.npy";
  const std::vector<int32_t> values = {-1, 0, 7, 2147483647, -2147483647 - 1};
  write_npy(path, {values.size()}, values.data());
  const NpyArray array = read_npy(path);
  EXPECT_EQ(array.dtype, "<i4");
  ASSERT_EQ(array.shape, (std::vector<size_t>{5}));
  EXPECT_EQ(array.to_int32s(), values);
}

TEST(Npy, HeaderIsAlignedTo64BytesLikeNumpy) {
  const auto path = test::temp_dir("npy") / "a.npy";
  const std::vector<float> values(8, 1.0f);
  write_npy(path, {2, 4}, values.data());
  // 10 bytes preamble + 60 bytes dict + padding + newline = 128 (NumPy's 64-byte alignment), then 8 floats.
  EXPECT_EQ(std::filesystem::file_size(path), 128u + 8u * 4u);
  std::ifstream in(path, std::ios::binary);
  std::string head(128, '\0');
  in.read(head.data(), 128);
  EXPECT_NE(head.find("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 4), }"), std::string::npos);
  EXPECT_EQ(head.back(), '\n');
}

TEST(Npy, ReadsNumpyWrittenInt64AndZeroLengthArrays) {
  const auto dir = test::temp_dir("npy");
  std::string data(16, '\0');
  const int64_t a = -1, b = 123456;
  std::memcpy(data.data(), &a, 8);
  std::memcpy(data.data() + 8, &b, 8);
  test::write_text(dir / "i8.npy", npy_bytes("{'descr': '<i8', 'fortran_order': False, 'shape': (2,), }", data));
  EXPECT_EQ(read_npy(dir / "i8.npy").to_int32s(), (std::vector<int32_t>{-1, 123456}));

  test::write_text(dir / "empty.npy", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (0, 2), }", ""));
  const NpyArray empty = read_npy(dir / "empty.npy");
  EXPECT_EQ(empty.shape, (std::vector<size_t>{0, 2}));
  EXPECT_TRUE(empty.to_floats().empty());
}

// Fortran order stores the first axis fastest: element (i, j, k) of a (2, 3, 4) array at i + 2 j + 6 k. The files
// are built by hand from that rule; the expected C-order values are i j k as decimal digits.
std::string fortran_data(const std::vector<size_t>& shape) {
  std::vector<float> values;
  const size_t depth = shape.size() == 3 ? shape[2] : 1;
  for (size_t k = 0; k < depth; ++k)
    for (size_t j = 0; j < shape[1]; ++j)
      for (size_t i = 0; i < shape[0]; ++i) values.push_back(static_cast<float>(100 * i + 10 * j + k));
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

TEST(Npy, ReadsFortranOrderIntoCOrder) {
  const auto dir = test::temp_dir("npy");
  test::write_text(dir / "f2.npy",
                   npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", fortran_data({2, 3})));
  const NpyArray matrix = read_npy(dir / "f2.npy");
  ASSERT_EQ(matrix.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(matrix.to_floats(), (std::vector<float>{0, 10, 20, 100, 110, 120}));

  test::write_text(dir / "f3.npy",
                   npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3, 4), }", fortran_data({2, 3, 4})));
  const NpyArray cube = read_npy(dir / "f3.npy");
  ASSERT_EQ(cube.shape, (std::vector<size_t>{2, 3, 4}));
  std::vector<float> expected;  // C order: the last axis fastest
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) expected.push_back(static_cast<float>(100 * i + 10 * j + k));
  EXPECT_EQ(cube.to_floats(), expected);

  // One axis: the same bytes either way.
  const std::vector<float> line = {1.5f, -2.0f, 3.25f};
  test::write_text(dir / "f1.npy", npy_bytes("{'descr': '<f4', 'fortran_order': True, 'shape': (3,), }",
                                             std::string(reinterpret_cast<const char*>(line.data()), 12)));
  EXPECT_EQ(read_npy(dir / "f1.npy").to_floats(), line);
}

TEST(Npy, ErrorsNameTheFileAndTheProblem) {
  const auto dir = test::temp_dir("npy");
  auto expect_error = [](const std::filesystem::path& path, const std::string& fragment) {
    try {
      read_npy(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
  };
  expect_error(dir / "missing.npy", "cannot open");
  test::write_text(dir / "bad_magic.npy", "PNG....");
  expect_error(dir / "bad_magic.npy", "bad magic");
  test::write_text(dir / "big_endian.npy",
                   npy_bytes("{'descr': '>f4', 'fortran_order': False, 'shape': (1,), }", std::string(4, '\0')));
  expect_error(dir / "big_endian.npy", "unsupported dtype");
  test::write_text(dir / "short.npy",
                   npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (4,), }", std::string(8, '\0')));
  expect_error(dir / "short.npy", "truncated");
}

// Issue 36: a header whose shape overflows the byte count used to pass the size check and crash the reader.
TEST(Npy, HostileShapesAreRejectedBeforeAnyAllocation) {
  const auto dir = test::temp_dir("npy_hostile");
  auto expect_error = [&](const std::string& name, const std::string& shape, const std::string& fragment) {
    const auto path = dir / name;
    test::write_text(
        path, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }", std::string(16, '\0')));
    try {
      read_npy(path);
      ADD_FAILURE() << "no error for shape " << shape;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
  };
  expect_error("overflow.npy", "(4611686018427387904, 4)", "overflows the byte count");
  expect_error("huge.npy", "(1000000000, 1000000000)", "data truncated");
  expect_error("negative.npy", "(-1, 2)", "not a non-negative integer");
  expect_error("too_long.npy", "(99999999999999999999999,)", "out of range");
  expect_error("directory_is_fine_name.npy", "(2, 3)", "needs 24 bytes");
  EXPECT_THROW(read_npy(dir), std::runtime_error);
}

TEST(Npy, HandBuiltArrayWithTooLittleDataThrows) {
  NpyArray array{{4}, "<f4", std::vector<std::byte>(8)};
  EXPECT_THROW(array.to_floats(), std::runtime_error);
}

TEST(Npy, ConversionToTheWrongTypeThrows) {
  NpyArray array{{2}, "<f4", std::vector<std::byte>(8)};
  EXPECT_THROW(array.to_int32s(), std::runtime_error);
  array.dtype = "|u1";
  EXPECT_THROW(array.to_floats(), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::io
