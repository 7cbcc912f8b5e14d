#pragma once
// The parsers of outside input, each wrapped as a function of raw bytes: the libFuzzer targets (fuzz/fuzz_main.cpp)
// and the regression test (tests/io/fuzz_regression_test.cpp) call the same code. A harness returns normally when
// the parser accepts the input or rejects it with an exception; a crash, a sanitizer report or an exception of
// another kind is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace vkvo::fuzz {

using HarnessFn = void (*)(const std::uint8_t* data, std::size_t size);

struct Harness {
  std::string_view name;  // fuzz target vkvo_fuzz_<name>, corpus fuzz/corpus/<name>
  HarnessFn run;
};

const std::vector<Harness>& harnesses();
const Harness* find_harness(std::string_view name);

}  // namespace vkvo::fuzz
