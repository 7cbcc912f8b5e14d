#include "runtime/precision.hpp"

namespace vkvo::rt {

std::string_view to_string(Precision p) {
  switch (p) {
    case Precision::fp32: return "fp32";
    case Precision::fp16s: return "fp16s";
    case Precision::fp16: return "fp16";
  }
  return "?";
}

std::optional<Precision> parse_precision(std::string_view text) {
  if (text == "fp32") return Precision::fp32;
  if (text == "fp16s" || text == "fp16-storage") return Precision::fp16s;
  if (text == "fp16") return Precision::fp16;
  return std::nullopt;
}

}  // namespace vkvo::rt
