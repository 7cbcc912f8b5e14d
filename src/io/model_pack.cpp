#include "io/model_pack.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <stdexcept>

#include <fmt/format.h>

#include "runtime/half.hpp"

namespace vkvo::io {

// The file is little-endian and written/read with plain memcpy.
static_assert(std::endian::native == std::endian::little, "model packs assume a little-endian host");

namespace {

// Header field offsets (see model_pack.hpp).
constexpr std::size_t kVersionAt = 8, kKindAt = 12, kFileSizeAt = 16, kChecksumAt = 24, kMetaOffsetAt = 32,
                      kMetaSizeAt = 40, kDataOffsetAt = 48, kDataSizeAt = 56;

enum class HyperTag : std::uint8_t { number = 0, string = 1, numbers = 2 };

std::size_t round_up(std::size_t value, std::size_t multiple) { return (value + multiple - 1) / multiple * multiple; }

template <typename T>
void put(std::vector<std::byte>& out, T value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}
void put_string(std::vector<std::byte>& out, std::string_view text) {
  put<std::uint32_t>(out, static_cast<std::uint32_t>(text.size()));
  const auto* p = reinterpret_cast<const std::byte*>(text.data());
  out.insert(out.end(), p, p + text.size());
}
template <typename T>
void put_at(std::vector<std::byte>& out, std::size_t at, T value) {
  std::memcpy(out.data() + at, &value, sizeof(T));
}
template <typename T>
T get_at(std::span<const std::byte> bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// Checksum of a whole pack with the checksum field read as zero: eight interleaved FNV-1a lanes (lane j hashes
// the bytes at positions = j mod 8), then FNV-1a over the eight lane states. The lanes are independent multiply
// chains, which makes this several times faster than one byte-serial FNV-1a over tens of MB.
std::uint64_t pack_checksum(std::span<const std::byte> file) {
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::uint64_t lanes[8];
  std::fill(std::begin(lanes), std::end(lanes), kFnvOffsetBasis);
  auto byte_at = [&](std::size_t i) {
    return i >= kChecksumAt && i < kChecksumAt + 8 ? std::uint64_t{0} : static_cast<std::uint64_t>(file[i]);
  };
  std::size_t i = 0;
  for (; i < kChecksumAt + 8; ++i) lanes[i % 8] = (lanes[i % 8] ^ byte_at(i)) * kPrime;
  for (; i + 8 <= file.size(); i += 8)
    for (std::size_t j = 0; j < 8; ++j) lanes[j] = (lanes[j] ^ static_cast<std::uint64_t>(file[i + j])) * kPrime;
  for (; i < file.size(); ++i) lanes[i % 8] = (lanes[i % 8] ^ static_cast<std::uint64_t>(file[i])) * kPrime;
  return fnv1a64(std::as_bytes(std::span(lanes)));
}

// Bounds-checked reader over the metadata region; errors become "corrupt metadata" failures of the pack.
class MetaReader {
 public:
  MetaReader(std::span<const std::byte> bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  template <typename T>
  T get(const char* what) {
    need(sizeof(T), what);
    T value = get_at<T>(bytes_, pos_);
    pos_ += sizeof(T);
    return value;
  }
  std::string get_string(const char* what) {
    const auto size = get<std::uint32_t>(what);
    need(size, what);
    std::string text(reinterpret_cast<const char*>(bytes_.data() + pos_), size);
    pos_ += size;
    return text;
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  void need(std::size_t size, const char* what) const {
    if (size > bytes_.size() - pos_)
      throw std::runtime_error(
          fmt::format("model pack '{}': corrupt metadata: {} runs past the end of the table", source_, what));
  }
  std::span<const std::byte> bytes_;
  const std::string& source_;
  std::size_t pos_ = 0;
};

}  // namespace

std::string_view to_string(NetworkKind kind) {
  switch (kind) {
    case NetworkKind::superpoint: return "superpoint";
    case NetworkKind::superglue: return "superglue";
  }
  return "unknown";
}

std::string_view to_string(DType dtype) { return dtype == DType::fp32 ? "fp32" : "fp16"; }

std::size_t stored_element_count(std::string_view layout, std::span<const std::int64_t> shape) {
  std::size_t count = 1;
  for (const auto d : shape) {
    if (d < 0) throw std::invalid_argument("negative dimension in tensor shape");
    count *= static_cast<std::size_t>(d);
  }
  if (layout == "dense") return count;
  if (layout == "oi") {
    if (shape.size() != 2) throw std::invalid_argument("layout 'oi' needs a rank-2 shape [O, I]");
    return count;
  }
  if (layout == "o4") {
    if (shape.size() != 1 && shape.size() != 4)
      throw std::invalid_argument("layout 'o4' needs a bias [O] or a weight [O, I, KH, KW]");
    if (shape[0] == 0) return 0;
    return count / static_cast<std::size_t>(shape[0]) * round_up(static_cast<std::size_t>(shape[0]), 4);
  }
  throw std::invalid_argument(fmt::format("unknown layout tag '{}'", layout));
}

std::uint64_t fnv1a64(std::span<const std::byte> bytes, std::uint64_t state) {
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  for (const std::byte b : bytes) state = (state ^ static_cast<std::uint64_t>(b)) * kPrime;
  return state;
}

std::size_t PackedTensor::logical_element_count() const {
  std::size_t count = 1;
  for (const auto d : shape) count *= static_cast<std::size_t>(d);
  return count;
}

// ---------------------------------------------------------------------------------------------------------------
// Reading

void ModelPack::AlignedFree::operator()(std::byte* p) const {
  ::operator delete[](p, std::align_val_t{kPackAlignment});
}

ModelPack ModelPack::load(const std::filesystem::path& path, NetworkKind expected) {
  // A directory opens as a stream on Linux and reports a nonsense size; refuse it by name first.
  if (std::filesystem::is_directory(path))
    throw std::runtime_error(fmt::format("model pack '{}': is a directory, not a file", path.string()));
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(fmt::format("model pack '{}': cannot open the file", path.string()));
  const std::streamoff end = in.tellg();
  if (end < 0) throw std::runtime_error(fmt::format("model pack '{}': cannot determine the file size", path.string()));
  const auto size = static_cast<std::size_t>(end);
  std::vector<std::byte> bytes(size);
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    throw std::runtime_error(fmt::format("model pack '{}': read error", path.string()));
  return parse(bytes, expected, path.string());
}

ModelPack ModelPack::parse(std::span<const std::byte> bytes, NetworkKind expected, const std::string& source) {
  auto fail = [&](const std::string& problem) {
    return std::runtime_error(fmt::format("model pack '{}': {}", source, problem));
  };
  if (bytes.size() < kPackHeaderBytes)
    throw fail(fmt::format("truncated: {} bytes, shorter than the {}-byte header", bytes.size(), kPackHeaderBytes));
  if (std::memcmp(bytes.data(), kPackMagic, sizeof(kPackMagic)) != 0)
    throw fail("not a vkvo model pack (bad magic; expected \"VKVOPACK\")");

  ModelPack pack;
  pack.source_ = source;
  pack.version_ = get_at<std::uint32_t>(bytes, kVersionAt);
  if (pack.version_ != kPackFormatVersion)
    throw fail(
        fmt::format("format version {} is not supported (this build reads version {}); convert the model "
                    "again with this build's `vkvo convert`",
                    pack.version_, kPackFormatVersion));

  const auto file_size = get_at<std::uint64_t>(bytes, kFileSizeAt);
  if (bytes.size() < file_size)
    throw fail(fmt::format("truncated: the header says {} bytes, the file has {}", file_size, bytes.size()));
  if (bytes.size() > file_size)
    throw fail(fmt::format("{} bytes of trailing data after the {} bytes the header declares", bytes.size() - file_size,
                           file_size));

  const auto stored_checksum = get_at<std::uint64_t>(bytes, kChecksumAt);
  const auto computed_checksum = pack_checksum(bytes);
  if (stored_checksum != computed_checksum)
    throw fail(fmt::format("checksum mismatch (stored {:016x}, computed {:016x}): the file is corrupted",
                           stored_checksum, computed_checksum));

  const auto kind_value = get_at<std::uint32_t>(bytes, kKindAt);
  if (kind_value != static_cast<std::uint32_t>(NetworkKind::superpoint) &&
      kind_value != static_cast<std::uint32_t>(NetworkKind::superglue))
    throw fail(fmt::format("unknown network kind {}", kind_value));
  pack.kind_ = static_cast<NetworkKind>(kind_value);
  if (pack.kind_ != expected)
    throw fail(
        fmt::format("holds a {} network, but a {} network was asked for", to_string(pack.kind_), to_string(expected)));

  const auto meta_offset = get_at<std::uint64_t>(bytes, kMetaOffsetAt);
  const auto meta_size = get_at<std::uint64_t>(bytes, kMetaSizeAt);
  const auto data_offset = get_at<std::uint64_t>(bytes, kDataOffsetAt);
  const auto data_size = get_at<std::uint64_t>(bytes, kDataSizeAt);
  if (meta_offset < kPackHeaderBytes || meta_offset > file_size || meta_size > file_size - meta_offset)
    throw fail("corrupt header: the metadata region lies outside the file");
  if (data_offset % kPackAlignment != 0 || data_offset < meta_offset + meta_size || data_offset > file_size ||
      data_size != file_size - data_offset)
    throw fail("corrupt header: the data region is misplaced");

  MetaReader meta(bytes.subspan(meta_offset, meta_size), pack.source_);
  const auto hyper_count = meta.get<std::uint32_t>("hyper-parameter count");
  for (std::uint32_t i = 0; i < hyper_count; ++i) {
    std::string key = meta.get_string("hyper-parameter key");
    const auto tag = static_cast<HyperTag>(meta.get<std::uint8_t>("hyper-parameter type"));
    if (tag == HyperTag::number) {
      pack.hyper_[key] = meta.get<double>("hyper-parameter value");
    } else if (tag == HyperTag::string) {
      pack.hyper_[key] = meta.get_string("hyper-parameter value");
    } else if (tag == HyperTag::numbers) {
      const auto count = meta.get<std::uint32_t>("hyper-parameter list size");
      std::vector<double> values;
      for (std::uint32_t k = 0; k < count; ++k) values.push_back(meta.get<double>("hyper-parameter list value"));
      pack.hyper_[key] = std::move(values);
    } else {
      throw fail(fmt::format("corrupt metadata: hyper-parameter '{}' has unknown type {}", key, int(tag)));
    }
  }

  const auto tensor_count = meta.get<std::uint32_t>("tensor count");
  for (std::uint32_t i = 0; i < tensor_count; ++i) {
    PackedTensor t;
    t.name = meta.get_string("tensor name");
    const auto dtype = meta.get<std::uint8_t>("tensor dtype");
    if (dtype != static_cast<std::uint8_t>(DType::fp32) && dtype != static_cast<std::uint8_t>(DType::fp16))
      throw fail(fmt::format("tensor '{}' has unknown dtype {}", t.name, int(dtype)));
    t.dtype = static_cast<DType>(dtype);
    t.layout = meta.get_string("tensor layout");
    const auto rank = meta.get<std::uint32_t>("tensor rank");
    for (std::uint32_t k = 0; k < rank; ++k) t.shape.push_back(meta.get<std::int64_t>("tensor shape"));
    t.offset = meta.get<std::uint64_t>("tensor offset");
    t.byte_size = meta.get<std::uint64_t>("tensor byte size");

    std::size_t expected_bytes = 0;
    try {
      expected_bytes = stored_element_count(t.layout, t.shape) * dtype_bytes(t.dtype);
    } catch (const std::invalid_argument& e) {
      throw fail(fmt::format("tensor '{}' ({}): {}", t.name, to_string(t.dtype), e.what()));
    }
    if (t.byte_size != expected_bytes)
      throw fail(fmt::format("tensor '{}' ({}): {} bytes stored, its shape and layout '{}' need {}", t.name,
                             to_string(t.dtype), t.byte_size, t.layout, expected_bytes));
    if (t.offset % kPackAlignment != 0 || t.offset > data_size || t.byte_size > data_size - t.offset)
      throw fail(fmt::format("tensor '{}' ({}): data range [{}, +{}) is misaligned or outside the data block", t.name,
                             to_string(t.dtype), t.offset, t.byte_size));
    if (pack.has_tensor(t.name, t.dtype))
      throw fail(fmt::format("tensor '{}' ({}) appears twice in the table", t.name, to_string(t.dtype)));
    pack.tensors_.push_back(std::move(t));
  }
  if (!meta.at_end()) throw fail("corrupt metadata: unread bytes after the tensor table");

  pack.data_size_ = data_size;
  pack.data_.reset(
      static_cast<std::byte*>(::operator new[](std::max<std::size_t>(data_size, 1), std::align_val_t{kPackAlignment})));
  std::memcpy(pack.data_.get(), bytes.data() + data_offset, data_size);
  return pack;
}

bool ModelPack::has_tensor(std::string_view name, DType dtype) const {
  return std::any_of(tensors_.begin(), tensors_.end(),
                     [&](const PackedTensor& t) { return t.name == name && t.dtype == dtype; });
}

const PackedTensor& ModelPack::tensor(std::string_view name, DType dtype) const {
  const auto it = std::find_if(tensors_.begin(), tensors_.end(),
                               [&](const PackedTensor& t) { return t.name == name && t.dtype == dtype; });
  if (it == tensors_.end())
    throw std::runtime_error(
        fmt::format("model pack '{}': no tensor '{}' stored as {}", source_, name, to_string(dtype)));
  return *it;
}

std::span<const std::byte> ModelPack::data(std::string_view name, DType dtype) const {
  const PackedTensor& t = tensor(name, dtype);
  return data_block().subspan(t.offset, t.byte_size);
}

std::vector<float> ModelPack::floats(std::string_view name, DType dtype) const {
  const auto bytes = data(name, dtype);
  std::vector<float> values(bytes.size() / dtype_bytes(dtype));
  if (dtype == DType::fp32) {
    std::memcpy(values.data(), bytes.data(), bytes.size());
  } else {
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = rt::half_to_float(get_at<std::uint16_t>(bytes, 2 * i));
  }
  return values;
}

const HyperValue& ModelPack::hyper(std::string_view key) const {
  const auto it = hyper_.find(key);
  if (it == hyper_.end())
    throw std::runtime_error(fmt::format("model pack '{}': no hyper-parameter '{}'", source_, key));
  return it->second;
}

double ModelPack::number(std::string_view key) const {
  const auto* value = std::get_if<double>(&hyper(key));
  if (!value)
    throw std::runtime_error(fmt::format("model pack '{}': hyper-parameter '{}' is not a number", source_, key));
  return *value;
}

std::int64_t ModelPack::integer(std::string_view key) const {
  const double value = number(key);
  if (std::trunc(value) != value)
    throw std::runtime_error(
        fmt::format("model pack '{}': hyper-parameter '{}' = {} is not an integer", source_, key, value));
  return static_cast<std::int64_t>(value);
}

const std::string& ModelPack::string(std::string_view key) const {
  const auto* value = std::get_if<std::string>(&hyper(key));
  if (!value)
    throw std::runtime_error(fmt::format("model pack '{}': hyper-parameter '{}' is not a string", source_, key));
  return *value;
}

const std::vector<double>& ModelPack::numbers(std::string_view key) const {
  const auto* value = std::get_if<std::vector<double>>(&hyper(key));
  if (!value)
    throw std::runtime_error(fmt::format("model pack '{}': hyper-parameter '{}' is not a number list", source_, key));
  return *value;
}

// ---------------------------------------------------------------------------------------------------------------
// Writing

void ModelPackWriter::add_tensor(const std::string& name, std::vector<std::int64_t> shape, const std::string& layout,
                                 std::span<const float> values, std::initializer_list<DType> dtypes) {
  const std::size_t count = stored_element_count(layout, shape);
  if (values.size() != count)
    throw std::invalid_argument(
        fmt::format("model pack tensor '{}': {} values given, layout '{}' of this shape "
                    "stores {}",
                    name, values.size(), layout, count));
  for (const DType dtype : dtypes) {
    for (const auto& e : entries_)
      if (e.info.name == name && e.info.dtype == dtype)
        throw std::invalid_argument(fmt::format("model pack tensor '{}' ({}) added twice", name, to_string(dtype)));
    Entry entry;
    entry.info.name = name;
    entry.info.dtype = dtype;
    entry.info.layout = layout;
    entry.info.shape = shape;
    entry.info.byte_size = count * dtype_bytes(dtype);
    entry.bytes.resize(entry.info.byte_size);
    if (dtype == DType::fp32) {
      std::memcpy(entry.bytes.data(), values.data(), entry.bytes.size());
    } else {
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint16_t h = rt::float_to_half(values[i]);
        std::memcpy(entry.bytes.data() + 2 * i, &h, 2);
      }
    }
    entries_.push_back(std::move(entry));
  }
}

std::vector<std::byte> ModelPackWriter::serialize() const {
  // Place the tensors in the data block first: the table records their offsets.
  std::vector<std::uint64_t> offsets;
  std::uint64_t data_size = 0;
  for (const auto& e : entries_) {
    data_size = round_up(data_size, kPackAlignment);
    offsets.push_back(data_size);
    data_size += e.bytes.size();
  }

  std::vector<std::byte> meta;
  put<std::uint32_t>(meta, static_cast<std::uint32_t>(hyper_.size()));
  for (const auto& [key, value] : hyper_) {
    put_string(meta, key);
    if (const auto* number = std::get_if<double>(&value)) {
      put(meta, HyperTag::number);
      put(meta, *number);
    } else if (const auto* text = std::get_if<std::string>(&value)) {
      put(meta, HyperTag::string);
      put_string(meta, *text);
    } else {
      const auto& list = std::get<std::vector<double>>(value);
      put(meta, HyperTag::numbers);
      put<std::uint32_t>(meta, static_cast<std::uint32_t>(list.size()));
      for (const double v : list) put(meta, v);
    }
  }
  put<std::uint32_t>(meta, static_cast<std::uint32_t>(entries_.size()));
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const PackedTensor& t = entries_[i].info;
    put_string(meta, t.name);
    put(meta, t.dtype);
    put_string(meta, t.layout);
    put<std::uint32_t>(meta, static_cast<std::uint32_t>(t.shape.size()));
    for (const auto d : t.shape) put<std::int64_t>(meta, d);
    put<std::uint64_t>(meta, offsets[i]);
    put<std::uint64_t>(meta, t.byte_size);
  }

  const std::uint64_t data_offset = round_up(kPackHeaderBytes + meta.size(), kPackAlignment);
  std::vector<std::byte> file(data_offset + data_size, std::byte{0});
  std::memcpy(file.data(), kPackMagic, sizeof(kPackMagic));
  put_at<std::uint32_t>(file, kVersionAt, kPackFormatVersion);
  put_at<std::uint32_t>(file, kKindAt, static_cast<std::uint32_t>(kind_));
  put_at<std::uint64_t>(file, kFileSizeAt, file.size());
  put_at<std::uint64_t>(file, kMetaOffsetAt, kPackHeaderBytes);
  put_at<std::uint64_t>(file, kMetaSizeAt, meta.size());
  put_at<std::uint64_t>(file, kDataOffsetAt, data_offset);
  put_at<std::uint64_t>(file, kDataSizeAt, data_size);
  std::memcpy(file.data() + kPackHeaderBytes, meta.data(), meta.size());
  for (std::size_t i = 0; i < entries_.size(); ++i)
    std::memcpy(file.data() + data_offset + offsets[i], entries_[i].bytes.data(), entries_[i].bytes.size());
  put_at<std::uint64_t>(file, kChecksumAt, pack_checksum(file));
  return file;
}

void ModelPackWriter::write(const std::filesystem::path& path) const {
  const auto file = serialize();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(fmt::format("model pack '{}': cannot create the file", path.string()));
  out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  if (!out) throw std::runtime_error(fmt::format("model pack '{}': write error", path.string()));
}

}  // namespace vkvo::io
