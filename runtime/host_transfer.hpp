#pragma once
// A network call's host inputs and outputs as part of its recorded Sequence, so that the call costs one queue
// submission (Buffer::upload / download on a discrete GPU each submit a copy and wait). An input is written by the
// host into mapped staging memory before Sequence::submit() and copied into its device buffer by the sequence's
// first commands; an output is copied by its last commands into mapped staging memory that the host reads after
// submit(). Where the device buffer itself is mapped (unified memory: lavapipe, Jetson) nothing is copied: the host
// writes and reads it in place.
#include <cstddef>
#include <memory>
#include <vector>

#include "runtime/buffer.hpp"
#include "runtime/sequence.hpp"

namespace vkvo::rt {

class Context;

class StagedTransfer {
 public:
  // `device` must outlive this object and the sequences it is recorded into.
  StagedTransfer(const Context& context, Buffer& device);
  // Whether the host goes through a staging buffer (false: the device buffer is mapped).
  bool staged() const { return staging_ != nullptr; }

 protected:
  Buffer& device_;
  std::unique_ptr<Buffer> staging_;
  // The memory the host writes or reads.
  Buffer& host() const;
};

class HostInput : public StagedTransfer {
 public:
  using StagedTransfer::StagedTransfer;
  // Records the copy into the device buffer (where one is needed): before the commands that read it.
  void record(Sequence& seq) const;
  // Host data for the next submit of the sequence (a memcpy).
  void write(const void* data, std::size_t bytes, std::size_t offset = 0) const;
};

class HostOutput : public StagedTransfer {
 public:
  using StagedTransfer::StagedTransfer;
  // Records the copy out of the device buffer (where one is needed): after the commands that write it.
  void record(Sequence& seq) const;
  // What the last submit of the sequence left there (a memcpy).
  void read(void* data, std::size_t bytes, std::size_t offset = 0) const;
  template <class T>
  std::vector<T> read(std::size_t count, std::size_t offset = 0) const {
    std::vector<T> values(count);
    read(values.data(), count * sizeof(T), offset);
    return values;
  }
};

}  // namespace vkvo::rt
