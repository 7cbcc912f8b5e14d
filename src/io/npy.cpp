#include "io/npy.hpp"

#include <cstring>
#include <fstream>
#include <istream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace vkvo::io {
namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw std::runtime_error("npy file " + path.string() + ": " + problem);
}

size_t dtype_item_size(const std::string& dtype) {
  if (dtype == "<f4" || dtype == "<i4" || dtype == "<u4") return 4;
  if (dtype == "<f8" || dtype == "<i8" || dtype == "<u8") return 8;
  if (dtype == "<i2" || dtype == "<u2" || dtype == "<f2") return 2;
  if (dtype == "|u1" || dtype == "|i1" || dtype == "|b1") return 1;
  return 0;  // unsupported
}

// Returns the text after `'key':` in the header dict (leading spaces skipped), or fails.
std::string value_after_key(const std::string& header, const std::string& key, const std::filesystem::path& path) {
  const std::string quoted = "'" + key + "'";
  size_t pos = header.find(quoted);
  if (pos == std::string::npos) fail(path, "header lacks key " + quoted);
  pos = header.find(':', pos + quoted.size());
  if (pos == std::string::npos) fail(path, "header key " + quoted + " has no value");
  ++pos;
  while (pos < header.size() && header[pos] == ' ') ++pos;
  return header.substr(pos);
}

std::string parse_descr(const std::string& header, const std::filesystem::path& path) {
  const std::string rest = value_after_key(header, "descr", path);
  if (rest.empty() || rest[0] != '\'') fail(path, "descr is not a quoted string");
  const size_t end = rest.find('\'', 1);
  if (end == std::string::npos) fail(path, "unterminated descr string");
  return rest.substr(1, end - 1);
}

bool parse_fortran_order(const std::string& header, const std::filesystem::path& path) {
  const std::string rest = value_after_key(header, "fortran_order", path);
  if (rest.rfind("False", 0) == 0) return false;
  if (rest.rfind("True", 0) == 0) return true;
  fail(path, "fortran_order is neither True nor False");
}

std::vector<size_t> parse_shape(const std::string& header, const std::filesystem::path& path) {
  const std::string rest = value_after_key(header, "shape", path);
  if (rest.empty() || rest[0] != '(') fail(path, "shape is not a tuple");
  const size_t end = rest.find(')');
  if (end == std::string::npos) fail(path, "unterminated shape tuple");
  std::vector<size_t> shape;
  std::stringstream tuple(rest.substr(1, end - 1));
  std::string item;
  while (std::getline(tuple, item, ',')) {
    const size_t first = item.find_first_not_of(' ');
    if (first == std::string::npos) continue;  // trailing comma of a 1-tuple
    const std::string digits = item.substr(first, item.find_last_not_of(' ') - first + 1);
    // stoull accepts a leading '-' (wrapping the value), so only plain digits are let through.
    if (digits.find_first_not_of("0123456789") != std::string::npos)
      fail(path, "shape entry '" + digits + "' is not a non-negative integer");
    unsigned long long value = 0;
    try {
      value = std::stoull(digits);
    } catch (const std::exception&) {
      fail(path, "shape entry '" + digits + "' is out of range");
    }
    shape.push_back(static_cast<size_t>(value));
  }
  return shape;
}

std::string shape_text(const std::vector<size_t>& shape) {
  std::string text = "(";
  for (size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + ")";
}

template <typename T>
T load_element(const std::byte* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));  // x86/ARM hosts are little-endian like the '<' dtypes we accept
  return value;
}

// Reorders Fortran-order (column-major) element bytes into C order: the C-order walk over the multi-index, with
// each index's Fortran offset kept alongside.
std::vector<std::byte> fortran_to_c_order(const std::vector<std::byte>& fortran, const std::vector<size_t>& shape,
                                          size_t item_size) {
  if (fortran.empty() || shape.size() < 2) return fortran;  // one axis: both orders are the same
  std::vector<std::byte> c_order(fortran.size());
  std::vector<size_t> fortran_stride(shape.size(), item_size);  // bytes per step of each axis in the file
  for (size_t axis = 1; axis < shape.size(); ++axis) fortran_stride[axis] = fortran_stride[axis - 1] * shape[axis - 1];
  std::vector<size_t> index(shape.size(), 0);
  size_t source = 0;
  for (size_t target = 0; target < c_order.size(); target += item_size) {
    std::memcpy(c_order.data() + target, fortran.data() + source, item_size);
    // Next C-order index: the last axis runs fastest.
    for (size_t axis = shape.size(); axis-- > 0;) {
      if (++index[axis] < shape[axis]) {
        source += fortran_stride[axis];
        break;
      }
      source -= (shape[axis] - 1) * fortran_stride[axis];
      index[axis] = 0;
    }
  }
  return c_order;
}

void write_npy_bytes(const std::filesystem::path& path, const std::vector<size_t>& shape, const std::string& dtype,
                     const void* values, size_t item_size) {
  std::string shape_text = "(";
  size_t count = 1;
  for (size_t i = 0; i < shape.size(); ++i) {
    shape_text += std::to_string(shape[i]) + (shape.size() == 1 ? "," : (i + 1 < shape.size() ? ", " : ""));
    count *= shape[i];
  }
  shape_text += ")";
  std::string header = "{'descr': '" + dtype + "', 'fortran_order': False, 'shape': " + shape_text + ", }";
  // Pad with spaces and a final newline so that magic + version + length + header is a multiple of 64 bytes.
  const size_t preamble = kMagicSize + 2 + 2;
  const size_t total = ((preamble + header.size() + 1 + 63) / 64) * 64;
  header.append(total - preamble - header.size() - 1, ' ');
  header.push_back('\n');
  if (header.size() > std::numeric_limits<uint16_t>::max()) fail(path, "header too long for format 1.0");

  std::ofstream out(path, std::ios::binary);
  if (!out) fail(path, "cannot open for writing");
  const uint16_t header_length = static_cast<uint16_t>(header.size());
  const char version[2] = {1, 0};
  const char length_bytes[2] = {static_cast<char>(header_length & 0xff), static_cast<char>(header_length >> 8)};
  out.write(kMagic, kMagicSize);
  out.write(version, 2);
  out.write(length_bytes, 2);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  if (count > 0) out.write(static_cast<const char*>(values), static_cast<std::streamsize>(count * item_size));
  if (!out) fail(path, "write failed");
}

}  // namespace

size_t NpyArray::element_count() const {
  size_t count = 1;
  for (size_t dim : shape) count *= dim;
  return count;
}

size_t NpyArray::item_size() const { return dtype_item_size(dtype); }

namespace {
// Throws unless the array's data holds exactly product(shape) * item size bytes (arrays can be built by hand).
void check_data_size(const NpyArray& array) {
  const auto& shape = array.shape;
  const size_t item = array.item_size();
  size_t bytes = item;
  for (size_t dim : shape) {
    if (dim != 0 && bytes > std::numeric_limits<size_t>::max() / dim)
      throw std::runtime_error("npy array shape " + shape_text(shape) + " overflows the byte count");
    bytes *= dim;
  }
  if (bytes != array.data.size())
    throw std::runtime_error("npy array shape " + shape_text(shape) + " of dtype " + array.dtype + " needs " +
                             std::to_string(bytes) + " bytes, it holds " + std::to_string(array.data.size()));
}
}  // namespace

std::vector<float> NpyArray::to_floats() const {
  check_data_size(*this);
  const size_t n = element_count();
  std::vector<float> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (dtype == "<f4") {
      out[i] = load_element<float>(data.data() + 4 * i);
    } else if (dtype == "<f8") {
      out[i] = static_cast<float>(load_element<double>(data.data() + 8 * i));
    } else if (dtype == "<i4") {
      out[i] = static_cast<float>(load_element<int32_t>(data.data() + 4 * i));
    } else {
      throw std::runtime_error("npy array of dtype " + dtype + " cannot be read as float32");
    }
  }
  return out;
}

std::vector<int32_t> NpyArray::to_int32s() const {
  check_data_size(*this);
  const size_t n = element_count();
  std::vector<int32_t> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (dtype == "<i4") {
      out[i] = load_element<int32_t>(data.data() + 4 * i);
    } else if (dtype == "<i8") {
      const int64_t value = load_element<int64_t>(data.data() + 8 * i);
      if (value < std::numeric_limits<int32_t>::min() || value > std::numeric_limits<int32_t>::max())
        throw std::runtime_error("npy int64 value " + std::to_string(value) + " does not fit int32");
      out[i] = static_cast<int32_t>(value);
    } else {
      throw std::runtime_error("npy array of dtype " + dtype + " cannot be read as int32");
    }
  }
  return out;
}

NpyArray read_npy(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path)) fail(path, "is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open for reading");
  return read_npy(in, path);
}

NpyArray read_npy(std::istream& in, const std::filesystem::path& path) {
  char magic[kMagicSize];
  in.read(magic, kMagicSize);
  if (!in || std::memcmp(magic, kMagic, kMagicSize) != 0) fail(path, "not a .npy file (bad magic)");
  unsigned char version[2];
  in.read(reinterpret_cast<char*>(version), 2);
  if (!in) fail(path, "truncated before the version");
  size_t header_length = 0;
  if (version[0] == 1) {
    unsigned char bytes[2];
    in.read(reinterpret_cast<char*>(bytes), 2);
    header_length = bytes[0] | (size_t{bytes[1]} << 8);
  } else if (version[0] == 2 || version[0] == 3) {
    unsigned char bytes[4];
    in.read(reinterpret_cast<char*>(bytes), 4);
    header_length = bytes[0] | (size_t{bytes[1]} << 8) | (size_t{bytes[2]} << 16) | (size_t{bytes[3]} << 24);
  } else {
    fail(path, "unsupported format version " + std::to_string(version[0]));
  }
  if (!in) fail(path, "truncated header length");
  // NumPy itself refuses headers over 10000 bytes by default; 1 MiB keeps a corrupt length from allocating GiBs.
  constexpr size_t kMaxHeaderLength = size_t{1} << 20;
  if (header_length > kMaxHeaderLength)
    fail(path, "header length " + std::to_string(header_length) + " exceeds the limit of " +
                   std::to_string(kMaxHeaderLength) + " bytes");
  std::string header(header_length, '\0');
  in.read(header.data(), static_cast<std::streamsize>(header_length));
  if (!in) fail(path, "truncated header");

  NpyArray array;
  array.dtype = parse_descr(header, path);
  const bool fortran_order = parse_fortran_order(header, path);
  array.shape = parse_shape(header, path);
  const size_t item = array.item_size();
  if (item == 0) fail(path, "unsupported dtype '" + array.dtype + "' (little-endian numeric types only)");

  // The header is outside input: the byte count is computed with overflow checks and compared with what the
  // stream holds before anything is allocated.
  size_t bytes = item;
  for (size_t dim : array.shape) {
    if (dim != 0 && bytes > std::numeric_limits<size_t>::max() / dim)
      fail(path, "shape " + shape_text(array.shape) + " overflows the byte count");
    bytes *= dim;
  }
  const std::streampos data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streampos stream_end = in.tellg();
  in.seekg(data_start);
  if (data_start < 0 || stream_end < 0 || !in) fail(path, "cannot determine the data size");
  const auto available = static_cast<size_t>(stream_end - data_start);
  if (bytes > available)
    fail(path, "data truncated: shape " + shape_text(array.shape) + " needs " + std::to_string(bytes) +
                   " bytes, the file holds " + std::to_string(available));
  array.data.resize(bytes);
  in.read(reinterpret_cast<char*>(array.data.data()), static_cast<std::streamsize>(bytes));
  if (static_cast<size_t>(in.gcount()) != bytes)
    fail(path, "data truncated: expected " + std::to_string(bytes) + " bytes, got " + std::to_string(in.gcount()));
  if (fortran_order) array.data = fortran_to_c_order(array.data, array.shape, item);
  return array;
}

void write_npy(const std::filesystem::path& path, const std::vector<size_t>& shape, const float* values) {
  write_npy_bytes(path, shape, "<f4", values, sizeof(float));
}

void write_npy(const std::filesystem::path& path, const std::vector<size_t>& shape, const int32_t* values) {
  write_npy_bytes(path, shape, "<i4", values, sizeof(int32_t));
}

}  // namespace vkvo::io
