#include "runtime/device_profile.hpp"

#include "runtime/context.hpp"

namespace vkvo::rt {

bool supports_coopmat_kernels(const DeviceCaps& caps) {
  return caps.has_cooperative_matrix_shape(kCoopmatKernelShape) && caps.supports(Precision::fp16) &&
         caps.subgroup_size > 0 && kCoopmatSubgroups * caps.subgroup_size <= caps.max_workgroup_invocations &&
         kCoopmatSharedBytes <= caps.max_shared_memory_bytes;
}

DeviceProfile make_device_profile(const DeviceCaps& caps) {
  DeviceProfile profile;
  profile.cooperative_matrix = supports_coopmat_kernels(caps);
  if (caps.type == "cpu") {
    profile.precision = Precision::fp32;
    profile.wide_gemm_tile = true;
    profile.winograd = true;
    profile.conv1x1_as_gemm = true;
    profile.shared_attention = false;
    profile.attention_rows = 8;  // the key and value fetches then serve twice the multiply-adds
    profile.sinkhorn_workgroup_per_line = false;
    // Each dispatch wakes the driver's worker threads, while the fused kernel runs on one of them: it pays up to
    // about N = M = 220.
    profile.fused_sinkhorn_max_cells = 48 * 1024;
  } else {
    profile.precision = caps.supports(Precision::fp16s) ? Precision::fp16s : Precision::fp32;
    profile.wide_gemm_tile = false;
    profile.winograd = false;
    profile.conv1x1_as_gemm = false;
    profile.shared_attention = true;
    profile.attention_rows = 4;  // where the register form is forced: 8 rows would double what an invocation holds
    profile.sinkhorn_workgroup_per_line = true;
    profile.fused_sinkhorn_max_cells = 0;
  }
  return profile;
}

}  // namespace vkvo::rt
