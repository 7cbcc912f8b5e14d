#pragma once
// The per-frame status file a run writes beside its trajectory (frames.csv), one line per processed frame:
//   index,timestamp_ns,state,segment,keyframe,point_inliers,line_inliers,note
// state: tracked | relocalised | bridged (untracked, interpolated across a closed gap) | lost (untracked,
// predicted) | uninitialised (before the map first started: no pose in the trajectory). The note is quoted when it
// holds a comma or a quote (RFC 4180).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vkvo::io {

struct FrameStatus {
  std::size_t index = 0;
  std::int64_t timestamp_ns = 0;
  std::string state;
  int segment = 0;
  bool keyframe = false;
  int point_inliers = 0, line_inliers = 0;
  std::string note;
};

inline constexpr const char* kFrameStatusHeader =
    "index,timestamp_ns,state,segment,keyframe,point_inliers,line_inliers,note";

// One line, with its newline.
std::string format_frame_status(const FrameStatus& status);
// Throws std::runtime_error naming the file and line of a malformed line or a wrong header.
std::vector<FrameStatus> read_frame_status(const std::filesystem::path& file);

}  // namespace vkvo::io
