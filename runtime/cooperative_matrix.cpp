#include "runtime/cooperative_matrix.hpp"

#include <iterator>

#include <fmt/format.h>

namespace vkvo::rt {

std::string_view to_string(MatrixComponent component) {
  constexpr std::string_view names[] = {"f16", "f32", "f64", "s8", "s16", "s32", "s64", "u8", "u16", "u32", "u64"};
  const auto i = static_cast<std::size_t>(component);
  return i < std::size(names) ? names[i] : "other";
}

std::string_view to_string(MatrixScope scope) {
  constexpr std::string_view names[] = {"device", "workgroup", "subgroup", "queue family"};
  const auto i = static_cast<std::size_t>(scope);
  return i < std::size(names) ? names[i] : "other";
}

std::string to_string(const CooperativeMatrixShape& s) {
  return fmt::format("{}x{}x{} {}*{}+{}->{} {}", s.m, s.n, s.k, to_string(s.a), to_string(s.b), to_string(s.c),
                     to_string(s.result), to_string(s.scope));
}

}  // namespace vkvo::rt
