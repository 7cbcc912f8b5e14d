#pragma once
// Model packs (.vkvopack): the network weights the Vulkan shaders read, written by `vkvo convert` (tools/convert)
// and read here.
//
// File layout (version 1, little-endian):
//   [0, 64)      header: magic "VKVOPACK", format version (u32), network kind (u32), file size (u64),
//                checksum (u64), metadata offset/size (u64, u64), data offset/size (u64, u64)
//   metadata     hyper-parameters (key -> number | string | number list) and the tensor table
//                (name, dtype, layout tag, shape, offset into the data block, byte size)
//   data block   starts at a multiple of kPackAlignment in the file; every tensor starts at a multiple of
//                kPackAlignment inside it, so one buffer upload of the block serves every tensor as a
//                (buffer, offset) binding (256 is >= minStorageBufferOffsetAlignment on every Vulkan device).
// The checksum covers the whole file with the checksum field read as zero: 64-bit FNV-1a in eight interleaved
// byte lanes (lane j takes the bytes at offsets = j mod 8), combined by FNV-1a over the eight lane states.
//
// Tensors are keyed by (logical name, dtype): every weight is stored once as fp32 and once as fp16 so that each
// shader precision variant (fp32 / fp16-storage / fp16) finds its data ready. Shapes are the logical (PyTorch)
// shapes; the layout tag says how the stored elements are ordered:
//   "o4"    conv weight OIHW regrouped as [ceil(O/4)][I][KH][KW][4] (runtime/tensor_layout.hpp), O padded with
//           zeros to a multiple of 4; a bias with this tag is padded with zeros to a multiple of 4
//   "oi"    linear weight, row-major [O][I]
//   "dense" row-major in the order of the shape
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace vkvo::io {

inline constexpr char kPackMagic[8] = {'V', 'K', 'V', 'O', 'P', 'A', 'C', 'K'};
inline constexpr std::uint32_t kPackFormatVersion = 1;
inline constexpr std::size_t kPackAlignment = 256;
inline constexpr std::size_t kPackHeaderBytes = 64;

enum class NetworkKind : std::uint32_t { superpoint = 1, superglue = 2 };
std::string_view to_string(NetworkKind kind);

enum class DType : std::uint8_t { fp32 = 1, fp16 = 2 };
std::string_view to_string(DType dtype);
inline constexpr std::size_t dtype_bytes(DType dtype) { return dtype == DType::fp32 ? 4 : 2; }

// Stored element count of a tensor with this logical shape and layout tag; throws std::invalid_argument for an
// unknown tag or a shape the tag does not fit.
std::size_t stored_element_count(std::string_view layout, std::span<const std::int64_t> shape);

// 64-bit FNV-1a, continuing from `state` (start with kFnvOffsetBasis).
inline constexpr std::uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ULL;
std::uint64_t fnv1a64(std::span<const std::byte> bytes, std::uint64_t state = kFnvOffsetBasis);

struct PackedTensor {
  std::string name;
  DType dtype = DType::fp32;
  std::string layout;               // "o4" | "oi" | "dense"
  std::vector<std::int64_t> shape;  // logical shape
  std::uint64_t offset = 0;         // bytes from the start of the data block, a multiple of kPackAlignment
  std::uint64_t byte_size = 0;      // stored bytes (layout padding included)

  std::size_t logical_element_count() const;
  std::size_t stored_element_count() const { return byte_size / dtype_bytes(dtype); }
};

using HyperValue = std::variant<double, std::string, std::vector<double>>;

class ModelPack {
 public:
  // Reads and verifies a pack: magic, format version, size (truncation), checksum, network kind and table
  // consistency. Throws std::runtime_error naming the file and the problem.
  static ModelPack load(const std::filesystem::path& path, NetworkKind expected);
  // Same checks on bytes already in memory; `source` names them in errors.
  static ModelPack parse(std::span<const std::byte> bytes, NetworkKind expected, const std::string& source);

  NetworkKind kind() const { return kind_; }
  std::uint32_t format_version() const { return version_; }
  const std::string& source() const { return source_; }

  // Tensors.
  const std::vector<PackedTensor>& tensors() const { return tensors_; }
  bool has_tensor(std::string_view name, DType dtype) const;
  // Throws naming the file and the missing tensor.
  const PackedTensor& tensor(std::string_view name, DType dtype) const;
  // The stored bytes of one tensor (kPackAlignment-aligned in memory).
  std::span<const std::byte> data(std::string_view name, DType dtype) const;
  // The stored elements of one tensor as floats (fp16 widened); layout padding included.
  std::vector<float> floats(std::string_view name, DType dtype) const;
  // All tensor data: upload once, bind each tensor at its `offset`.
  std::span<const std::byte> data_block() const { return {data_.get(), data_size_}; }

  // Hyper-parameters. Getters throw naming the file and the key when it is missing or of another type.
  const std::map<std::string, HyperValue, std::less<>>& hyper_parameters() const {
    return hyper_;
  }  // all (copying a pack)
  bool has(std::string_view key) const { return hyper_.find(key) != hyper_.end(); }
  double number(std::string_view key) const;
  std::int64_t integer(std::string_view key) const;  // a number that must be integral
  const std::string& string(std::string_view key) const;
  const std::vector<double>& numbers(std::string_view key) const;

 private:
  struct AlignedFree {
    void operator()(std::byte* p) const;
  };
  const HyperValue& hyper(std::string_view key) const;

  std::string source_;
  NetworkKind kind_ = NetworkKind::superpoint;
  std::uint32_t version_ = 0;
  std::map<std::string, HyperValue, std::less<>> hyper_;
  std::vector<PackedTensor> tensors_;
  std::unique_ptr<std::byte[], AlignedFree> data_;
  std::size_t data_size_ = 0;
};

// Builds a pack in memory and writes it.
class ModelPackWriter {
 public:
  explicit ModelPackWriter(NetworkKind kind) : kind_(kind) {}

  NetworkKind kind() const { return kind_; }
  void set_number(const std::string& key, double value) { hyper_[key] = value; }
  void set_string(const std::string& key, std::string value) { hyper_[key] = std::move(value); }
  void set_numbers(const std::string& key, std::vector<double> values) { hyper_[key] = std::move(values); }

  // Adds `values` (already in `layout` order, padding included) under `name` once per dtype in `dtypes`
  // (fp16 copies rounded to nearest even). Throws if the element count does not fit layout and shape, or if
  // (name, dtype) already exists.
  void add_tensor(const std::string& name, std::vector<std::int64_t> shape, const std::string& layout,
                  std::span<const float> values, std::initializer_list<DType> dtypes = {DType::fp32, DType::fp16});

  std::size_t tensor_count() const { return entries_.size(); }
  std::vector<std::byte> serialize() const;
  void write(const std::filesystem::path& path) const;

 private:
  struct Entry {
    PackedTensor info;  // offset filled in by serialize()
    std::vector<std::byte> bytes;
  };
  NetworkKind kind_;
  std::map<std::string, HyperValue, std::less<>> hyper_;
  std::vector<Entry> entries_;
};

}  // namespace vkvo::io
