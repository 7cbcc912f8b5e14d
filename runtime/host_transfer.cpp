#include "runtime/host_transfer.hpp"

namespace vkvo::rt {

StagedTransfer::StagedTransfer(const Context& context, Buffer& device) : device_(device) {
  if (!device.host_visible())
    staging_ = std::make_unique<Buffer>(context, device.size(), BufferKind::staging, device.name() + ".host");
}

Buffer& StagedTransfer::host() const {
  // A mapped device buffer is written and read in place; Buffer::upload / download on it are plain memcpy.
  return staging_ ? *staging_ : device_;
}

void HostInput::record(Sequence& seq) const {
  if (staging_) seq.copy(*staging_, device_, device_.size(), 0, 0, device_.name() + " in");
}

void HostInput::write(const void* data, std::size_t bytes, std::size_t offset) const {
  host().upload(data, bytes, offset);
}

void HostOutput::record(Sequence& seq) const {
  if (staging_) seq.copy(device_, *staging_, device_.size(), 0, 0, device_.name() + " out");
}

void HostOutput::read(void* data, std::size_t bytes, std::size_t offset) const { host().download(data, bytes, offset); }

}  // namespace vkvo::rt
