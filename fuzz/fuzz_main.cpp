// libFuzzer entry point of one target: VKVO_FUZZ_TARGET names the harness (fuzz/harnesses.cpp).
#include <cstdlib>

#include "fuzz/harnesses.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const vkvo::fuzz::Harness* harness = vkvo::fuzz::find_harness(VKVO_FUZZ_TARGET);
  if (!harness) std::abort();
  harness->run(data, size);
  return 0;
}
