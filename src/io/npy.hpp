#pragma once
// Minimal reader/writer for NumPy .npy files (format versions 1.0-3.0, little-endian).
// Enough for exchanging keypoints, descriptors and matches with the Python reference tools; not a general
// NumPy implementation (no structured dtypes, no big-endian data). Fortran-order files (NumPy writes them for
// transposed arrays) are read into C order; files are always written in C order.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace vkvo::io {

struct NpyArray {
  std::vector<size_t> shape;    // empty for a 0-d array
  std::string dtype;            // NumPy descr, e.g. "<f4", "<i4", "<f8", "<i8", "|u1"
  std::vector<std::byte> data;  // raw element bytes, C order (whatever the file's order)

  size_t element_count() const;  // product of shape (1 for a 0-d array)
  size_t item_size() const;      // bytes per element, from dtype

  // Element values converted to the requested type. Accepted sources: to_floats from <f4/<f8/<i4;
  // to_int32s from <i4/<i8 (values must fit). Anything else throws std::runtime_error naming the dtype.
  std::vector<float> to_floats() const;
  std::vector<int32_t> to_int32s() const;
};

// Reads a whole .npy file. Throws std::runtime_error naming the file on any malformed or unsupported content.
NpyArray read_npy(const std::filesystem::path& path);
// Reads a .npy image from a seekable stream; `name` is the file named in error messages.
NpyArray read_npy(std::istream& in, const std::filesystem::path& name);

// Writes a C-order .npy file (format 1.0) with the given shape; `values` holds product(shape) elements.
void write_npy(const std::filesystem::path& path, const std::vector<size_t>& shape, const float* values);
void write_npy(const std::filesystem::path& path, const std::vector<size_t>& shape, const int32_t* values);

}  // namespace vkvo::io
