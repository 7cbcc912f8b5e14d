// Build step of every shader variant (cmake/VkvoShaders.cmake): reads the SPIR-V glslc wrote and writes a C++
// source holding its words and the interface reflected from them (runtime/shader_interface.hpp): the descriptor
// bindings of set 0 with their kind and access (readonly / writeonly in the GLSL become NonWritable / NonReadable),
// the push-constant block's size and the number of specialization constants. With a push-constant struct named,
// the source also asserts that the C++ declaration (shaders/include/push/) has the size the SPIR-V declares.
//
//   vkvo_spirv_embed <input.spv> <output.cpp> <symbol> [<PushStruct>]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// SPIR-V encodings (SPIR-V specification, section 3).
constexpr std::uint32_t kMagic = 0x07230203u;
constexpr std::size_t kHeaderWords = 5;
enum Opcode : std::uint32_t {
  OpTypeInt = 21, OpTypeFloat = 22, OpTypeVector = 23, OpTypeImage = 25, OpTypeArray = 28, OpTypeRuntimeArray = 29,
  OpTypeStruct = 30, OpTypePointer = 32, OpConstant = 43, OpVariable = 59, OpDecorate = 71, OpMemberDecorate = 72,
};
enum Decoration : std::uint32_t {
  SpecId = 1, Block = 2, BufferBlock = 3, ArrayStride = 6, NonWritable = 24, NonReadable = 25, Binding = 33,
  DescriptorSet = 34, Offset = 35,
};
enum StorageClass : std::uint32_t { UniformConstant = 0, Uniform = 2, PushConstant = 9, StorageBuffer = 12 };
constexpr std::uint32_t kDimBuffer = 5;
constexpr std::uint32_t kMaxBindings = 16;  // runtime/shader_interface.hpp

struct Decorations {
  std::map<std::uint32_t, std::uint32_t> values;  // decoration -> first literal (0 when it has none)
  bool has(std::uint32_t d) const { return values.contains(d); }
};

struct Module {
  std::map<std::uint32_t, std::vector<std::uint32_t>> types;  // result id -> [opcode, operands after the id]
  std::map<std::uint32_t, std::uint32_t> constants;           // 32-bit OpConstant values
  std::map<std::uint32_t, Decorations> decorations;
  std::map<std::uint32_t, std::map<std::uint32_t, Decorations>> member_decorations;  // struct -> member -> ...
  std::vector<std::pair<std::uint32_t, std::uint32_t>> variables;  // (pointer type, id)
};

Module parse(const std::vector<std::uint32_t>& words) {
  if (words.size() < kHeaderWords || words[0] != kMagic) throw std::runtime_error("not a SPIR-V module");
  Module m;
  for (std::size_t at = kHeaderWords; at < words.size();) {
    const std::uint32_t count = words[at] >> 16, opcode = words[at] & 0xffffu;
    if (count == 0 || at + count > words.size()) throw std::runtime_error("malformed instruction stream");
    const std::uint32_t* op = &words[at + 1];
    switch (opcode) {
      case OpTypeInt: case OpTypeFloat: case OpTypeVector: case OpTypeImage: case OpTypeArray:
      case OpTypeRuntimeArray: case OpTypeStruct: case OpTypePointer: {
        std::vector<std::uint32_t> type{opcode};
        type.insert(type.end(), op + 1, op + count - 1);
        m.types[op[0]] = std::move(type);
        break;
      }
      case OpConstant:
        if (count == 4) m.constants[op[1]] = op[2];
        break;
      case OpVariable:
        m.variables.emplace_back(op[0], op[1]);
        break;
      case OpDecorate:
        m.decorations[op[0]].values[op[1]] = count > 3 ? op[2] : 0;
        break;
      case OpMemberDecorate:
        m.member_decorations[op[0]][op[1]].values[op[2]] = count > 4 ? op[3] : 0;
        break;
      default:
        break;
    }
    at += count;
  }
  return m;
}

const std::vector<std::uint32_t>& type_of(const Module& m, std::uint32_t id) {
  const auto it = m.types.find(id);
  if (it == m.types.end()) throw std::runtime_error("unknown type id " + std::to_string(id));
  return it->second;
}

// Bytes a value of type `id` occupies in an explicitly laid out block (scalars, vectors, sized arrays, structs).
std::uint32_t size_of(const Module& m, std::uint32_t id) {
  const auto& t = type_of(m, id);
  switch (t[0]) {
    case OpTypeInt: case OpTypeFloat: return t[1] / 8;
    case OpTypeVector: return t[2] * size_of(m, t[1]);
    case OpTypeArray: {
      const auto d = m.decorations.find(id);
      if (d == m.decorations.end() || !d->second.has(ArrayStride))
        throw std::runtime_error("array without ArrayStride in a block");
      return m.constants.at(t[2]) * d->second.values.at(ArrayStride);
    }
    case OpTypeStruct: {
      const auto members = m.member_decorations.find(id);
      std::uint32_t end = 0;
      for (std::uint32_t i = 1; i < t.size(); ++i) {
        if (members == m.member_decorations.end() || !members->second.contains(i - 1) ||
            !members->second.at(i - 1).has(Offset))
          throw std::runtime_error("block member without Offset");
        end = std::max(end, members->second.at(i - 1).values.at(Offset) + size_of(m, t[i]));
      }
      return end;
    }
    default:
      throw std::runtime_error("unsupported type in a push-constant block (opcode " + std::to_string(t[0]) + ")");
  }
}

struct BindingInfo {
  std::string kind;  // BindingKind enumerator
  bool read = false, write = false;
};

// Whether every member of struct `id` carries decoration `d` (glslang decorates the members of a readonly block).
bool all_members(const Module& m, std::uint32_t id, std::uint32_t d) {
  const auto& t = type_of(m, id);
  const auto it = m.member_decorations.find(id);
  if (it == m.member_decorations.end()) return false;
  for (std::uint32_t i = 0; i + 1 < t.size(); ++i) {
    const auto member = it->second.find(i);
    if (member == it->second.end() || !member->second.has(d)) return false;
  }
  return true;
}

struct Interface {
  std::map<std::uint32_t, BindingInfo> bindings;
  std::uint32_t push_constant_bytes = 0;
  std::uint32_t specialization_constants = 0;
};

Interface reflect(const Module& m) {
  Interface result;
  std::set<std::uint32_t> spec_ids;
  for (const auto& [id, d] : m.decorations)
    if (d.has(SpecId)) spec_ids.insert(d.values.at(SpecId));
  result.specialization_constants = spec_ids.empty() ? 0 : *spec_ids.rbegin() + 1;

  for (const auto& [pointer_id, id] : m.variables) {
    const auto& pointer = type_of(m, pointer_id);
    const std::uint32_t storage = pointer[1];
    std::uint32_t pointee = pointer[2];
    if (storage == PushConstant) {
      result.push_constant_bytes = size_of(m, pointee);
      continue;
    }
    const auto decorations = m.decorations.find(id);
    if (decorations == m.decorations.end() || !decorations->second.has(Binding)) continue;
    const Decorations& d = decorations->second;
    if (d.has(DescriptorSet) && d.values.at(DescriptorSet) != 0)
      throw std::runtime_error("descriptor set other than 0 (the runtime binds one set)");
    const auto& type = type_of(m, pointee);
    BindingInfo info;
    if (type[0] == OpTypeImage && type[2] == kDimBuffer && type[6] == 1) {  // sampled: a uniform texel buffer
      info = {"uniform_texel_buffer", true, false};
    } else if (type[0] == OpTypeStruct && (storage == StorageBuffer ||
                                           (storage == Uniform && m.decorations.count(pointee) &&
                                            m.decorations.at(pointee).has(BufferBlock)))) {
      info.kind = "storage_buffer";
      info.read = !d.has(NonReadable) && !all_members(m, pointee, NonReadable);
      info.write = !d.has(NonWritable) && !all_members(m, pointee, NonWritable);
    } else {
      throw std::runtime_error("binding " + std::to_string(d.values.at(Binding)) +
                               ": only storage buffers and uniform texel buffers are supported");
    }
    const std::uint32_t binding = d.values.at(Binding);
    auto [it, inserted] = result.bindings.try_emplace(binding, info);
    if (!inserted) {  // several blocks aliasing one binding (e.g. scalar and vec4 views of a buffer)
      if (it->second.kind != info.kind) throw std::runtime_error("binding " + std::to_string(binding) +
                                                                 " declared as two kinds of descriptor");
      it->second.read |= info.read;
      it->second.write |= info.write;
    }
  }
  std::uint32_t expected = 0;
  for (const auto& [binding, info] : result.bindings)
    if (binding != expected++)
      throw std::runtime_error("bindings must be 0..N-1 without gaps (binding " + std::to_string(expected - 1) +
                               " is missing or unused)");
  if (result.bindings.size() > kMaxBindings) throw std::runtime_error("more bindings than the runtime supports");
  return result;
}

std::vector<std::uint32_t> read_words(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read");
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.size() % 4 != 0) throw std::runtime_error("size is not a multiple of 4 bytes");
  std::vector<std::uint32_t> words(bytes.size() / 4);
  for (std::size_t i = 0; i < words.size(); ++i)  // SPIR-V words are little-endian here, as on every target
    words[i] = std::uint32_t(std::uint8_t(bytes[4 * i])) | std::uint32_t(std::uint8_t(bytes[4 * i + 1])) << 8 |
               std::uint32_t(std::uint8_t(bytes[4 * i + 2])) << 16 | std::uint32_t(std::uint8_t(bytes[4 * i + 3])) << 24;
  return words;
}

std::string source(const std::vector<std::uint32_t>& words, const Interface& interface, const std::string& symbol,
                   const std::string& push_struct, const std::string& input) {
  std::ostringstream out;
  out << "// Generated by vkvo_spirv_embed from " << input.substr(input.find_last_of('/') + 1) << ".\n"
      << "#include \"runtime/shader_interface.hpp\"\n";
  if (!push_struct.empty()) out << "#include \"runtime/push_constants.hpp\"\n";
  out << "\nnamespace vkvo::rt::detail {\n";
  if (!push_struct.empty())
    out << "static_assert(sizeof(vkvo::shader::" << push_struct << ") == " << interface.push_constant_bytes
        << ", \"" << symbol << ": the C++ struct " << push_struct
        << " and the shader's push-constant block differ in size\");\n";
  else if (interface.push_constant_bytes != 0)
    throw std::runtime_error("the shader has a push-constant block but the table names no PUSH struct for it");
  out << "extern const std::uint32_t " << symbol << "_words[] = {";
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i % 8 == 0) out << "\n   ";
    char hex[16];
    std::snprintf(hex, sizeof hex, " 0x%08xu,", words[i]);
    out << hex;
  }
  out << "\n};\nextern const std::size_t " << symbol << "_word_count = " << words.size() << ";\n";
  out << "extern const ShaderInterface " << symbol << "_interface{\n    .binding_count = "
      << interface.bindings.size() << ",\n    .bindings = {{";
  for (const auto& [binding, info] : interface.bindings)
    out << "\n        {BindingKind::" << info.kind << ", " << (info.read ? "true" : "false") << ", "
        << (info.write ? "true" : "false") << "},";
  out << "\n    }},\n    .push_constant_bytes = " << interface.push_constant_bytes
      << ",\n    .specialization_constants = " << interface.specialization_constants << "};\n";
  out << "}  // namespace vkvo::rt::detail\n";
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::cerr << "usage: vkvo_spirv_embed <input.spv> <output.cpp> <symbol> [<PushStruct>]\n";
    return 2;
  }
  const std::string input = argv[1], output = argv[2], symbol = argv[3], push_struct = argc == 5 ? argv[4] : "";
  try {
    const auto words = read_words(input);
    const std::string text = source(words, reflect(parse(words)), symbol, push_struct, input);
    std::ofstream out(output);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + output);
  } catch (const std::exception& e) {
    std::cerr << input << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
