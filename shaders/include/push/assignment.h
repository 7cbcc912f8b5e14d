// Push constants: log-assignment from the Sinkhorn potentials (superglue_assignment.comp).
// Common subset of GLSL and C++ (common.h).
#ifndef VKVO_PUSH_ASSIGNMENT_H
#define VKVO_PUSH_ASSIGNMENT_H
#include "common.h"
VKVO_SHADER_NAMESPACE_BEGIN

VKVO_PUSH_CONSTANTS(AssignmentPush) {
  uint rows, cols;
  float norm;
} VKVO_PUSH_INSTANCE;

VKVO_SHADER_NAMESPACE_END
#endif
