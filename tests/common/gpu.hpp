#pragma once
// The Vulkan context shared by the tests of one process (device creation is the slow part).
#include "runtime/context.hpp"

namespace vkvo::test {

// Created on first use with validation as $VKVO_VALIDATION says (ctest sets it to 1).
rt::Context& gpu();

}  // namespace vkvo::test
