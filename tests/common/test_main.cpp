// main() of every test executable: runs GoogleTest and fails the process when the Vulkan validation layer
// reported anything (ctest runs each test in its own process, so the failure lands on the test that caused it).
#include <cstdio>

#include <gtest/gtest.h>

#include "runtime/context.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  const auto messages = vkvo::rt::validation_message_count();
  if (messages != 0) {
    std::fprintf(stderr, "FAILED: %llu Vulkan validation message(s), see the log above\n",
                 static_cast<unsigned long long>(messages));
    return 1;
  }
  return result;
}
