#include "system/trajectory_record.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/frame_status.hpp"
#include "io/trajectory.hpp"

namespace vkvo::system {
namespace {

namespace fs = std::filesystem;

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

bool is_tracked(PoseState state) { return state == PoseState::tracked || state == PoseState::relocalised; }

std::FILE* open_file(const fs::path& path, const char* mode) {
  std::FILE* file = std::fopen(path.c_str(), mode);
  if (!file)
    throw io::OutputWriteError(fmt::format("cannot open {} for writing: {}", path.string(), std::strerror(errno)));
  return file;
}

void write_or_throw(std::FILE* file, const std::string& text, const fs::path& path) {
  if (text.empty()) return;
  if (std::fputs(text.c_str(), file) < 0 || std::fflush(file) != 0)
    throw io::OutputWriteError(fmt::format("cannot write {}: {}", path.string(), std::strerror(errno)));
}

// Writes `text` into a new file beside `path` and renames it over `path`.
void replace_file(const fs::path& path, const std::string& text) {
  const fs::path partial = path.string() + ".partial";
  std::FILE* file = open_file(partial, "w");
  const bool written = text.empty() || (std::fputs(text.c_str(), file) >= 0 && std::fflush(file) == 0);
  if (std::fclose(file) != 0 || !written) {
    const std::string reason = std::strerror(errno);
    std::error_code ignored;
    fs::remove(partial, ignored);
    throw io::OutputWriteError(fmt::format("cannot write {}: {}; {} is kept", partial.string(), reason, path.string()));
  }
  std::error_code error;
  fs::rename(partial, path, error);
  if (error)
    throw io::OutputWriteError(
        fmt::format("cannot rename {} to {}: {}", partial.string(), path.string(), error.message()));
}

}  // namespace

const char* to_string(PoseState state) {
  switch (state) {
    case PoseState::tracked: return "tracked";
    case PoseState::relocalised: return "relocalised";
    case PoseState::bridged: return "bridged";
    case PoseState::lost: return "lost";
    case PoseState::uninitialised: return "uninitialised";
  }
  return "?";
}

bool is_untracked(PoseState state) { return !is_tracked(state); }

Eigen::Isometry3d interpolate_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction) {
  const Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = qa.slerp(fraction, qb).normalized().toRotationMatrix();
  pose.translation() = (1.0 - fraction) * a.translation() + fraction * b.translation();
  return pose;
}

Eigen::Isometry3d hermite_pose(const Eigen::Isometry3d& a, const Velocity& va, const Eigen::Isometry3d& b,
                               const Velocity& vb, double duration, double s) {
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() =
      h00 * a.translation() + h10 * duration * va.linear + h01 * b.translation() + h11 * duration * vb.linear;
  const Eigen::Vector3d phi_b = log_so3(b.linear() * a.linear().transpose());
  const Eigen::Vector3d phi = h10 * duration * va.angular + h01 * phi_b + h11 * duration * vb.angular;
  pose.linear() = exp_so3(phi) * a.linear();
  return pose;
}

TrajectoryRecord::TrajectoryRecord(Files files, int max_bridged)
    : max_bridged_(max_bridged),
      trajectory_{std::move(files.trajectory)},
      keyframes_{std::move(files.keyframes)},
      status_{std::move(files.status)} {
  for (Output* out : {&trajectory_, &keyframes_, &status_}) out->file = open_file(out->path, "w");
  write_or_throw(status_.file, std::string(io::kFrameStatusHeader) + "\n", status_.path);
}

TrajectoryRecord::~TrajectoryRecord() {
  for (Output* out : {&trajectory_, &keyframes_, &status_})
    if (out->file) std::fclose(out->file);
}

std::string TrajectoryRecord::trajectory_line(const FrameRecord& f) {
  return f.state == PoseState::uninitialised ? std::string() : io::tum_line_ns(f.timestamp_ns, f.T_world_camera);
}

std::string TrajectoryRecord::keyframe_line(const FrameRecord& f) {
  return f.keyframe ? io::tum_line_ns(f.timestamp_ns, f.T_world_camera) : std::string();
}

std::string TrajectoryRecord::status_line(const FrameRecord& f) {
  return io::format_frame_status({.index = f.index,
                                  .timestamp_ns = f.timestamp_ns,
                                  .state = to_string(f.state),
                                  .segment = f.segment,
                                  .keyframe = f.keyframe,
                                  .point_inliers = f.point_inliers,
                                  .line_inliers = f.line_inliers,
                                  .note = f.note});
}

int TrajectoryRecord::frames_bridged() const {
  return static_cast<int>(std::count_if(frames_.begin(), frames_.end(),
                                        [](const FrameRecord& f) { return f.state == PoseState::bridged; }));
}

void TrajectoryRecord::add(FrameRecord frame, const std::optional<SegmentMerge>& merge) {
  bool changed = false;
  if (merge) {
    for (FrameRecord& f : frames_) {
      if (f.segment != merge->from || f.state == PoseState::uninitialised) continue;
      f.T_world_camera = merge->T_into_from * f.T_world_camera;
      f.segment = merge->into;
      changed = true;
    }
  }
  const bool started =
      std::any_of(frames_.begin(), frames_.end(), [](const FrameRecord& f) { return is_tracked(f.state); });
  if (!started && !is_tracked(frame.state)) frame.state = PoseState::uninitialised;
  frames_.push_back(std::move(frame));
  changed = bridge_gaps() || changed;
  if (changed)
    rewrite();
  else
    append(frames_.back());
}

std::optional<Velocity> TrajectoryRecord::velocity_at(std::size_t frame, int direction) const {
  // A quadratic in time fitted by least squares to the position and to the rotation's tangent coordinates (about
  // the end's rotation) over up to kWindow tracked frames of one segment, differentiated at the end: second-order
  // accurate on a smooth motion where a one-frame difference lags half a frame.
  constexpr int kWindow = 5;
  const FrameRecord& end = frames_[frame];
  std::vector<const FrameRecord*> window{&end};
  for (auto k = static_cast<std::ptrdiff_t>(frame) + direction;
       k >= 0 && k < static_cast<std::ptrdiff_t>(frames_.size()) && static_cast<int>(window.size()) < kWindow;
       k += direction) {
    const FrameRecord& f = frames_[static_cast<std::size_t>(k)];
    if (!is_tracked(f.state) || f.segment != end.segment) break;
    window.push_back(&f);
  }
  if (window.size() < 2) return std::nullopt;
  const int order = window.size() >= 3 ? 2 : 1;
  Eigen::MatrixXd A(static_cast<Eigen::Index>(window.size()), order + 1);
  Eigen::MatrixXd b(static_cast<Eigen::Index>(window.size()), 6);
  for (std::size_t i = 0; i < window.size(); ++i) {
    const double t = static_cast<double>(window[i]->timestamp_ns - end.timestamp_ns) * 1e-9;
    for (int p = 0; p <= order; ++p) A(static_cast<Eigen::Index>(i), p) = std::pow(t, p);
    b.row(static_cast<Eigen::Index>(i)).head<3>() = window[i]->T_world_camera.translation();
    b.row(static_cast<Eigen::Index>(i)).tail<3>() =
        log_so3(window[i]->T_world_camera.linear() * end.T_world_camera.linear().transpose());
  }
  if (!(std::abs(A(static_cast<Eigen::Index>(window.size()) - 1, 1)) > 0)) return std::nullopt;
  const Eigen::MatrixXd coefficients = A.colPivHouseholderQr().solve(b);
  return Velocity{coefficients.row(1).head<3>().transpose(), coefficients.row(1).tail<3>().transpose()};
}

bool TrajectoryRecord::bridge_gaps() {
  // Only gaps whose closing frame is one of the last two can have changed since the previous call, unless a merge
  // moved frames; scanning every gap keeps this simple and is cheap next to a frame's work.
  bool changed = false;
  const std::size_t n = frames_.size();
  for (std::size_t i = 0; i < n;) {
    if (!is_untracked(frames_[i].state) || frames_[i].state == PoseState::uninitialised || i == 0) {
      ++i;
      continue;
    }
    std::size_t end = i;  // one past the gap
    while (end < n && is_untracked(frames_[end].state)) ++end;
    const std::size_t a = i - 1, b = end;
    const std::size_t length = end - i;
    i = end;
    if (b >= n || max_bridged_ <= 0 || static_cast<int>(length) > max_bridged_) continue;
    const FrameRecord& fa = frames_[a];
    const FrameRecord& fb = frames_[b];
    const double duration = static_cast<double>(fb.timestamp_ns - fa.timestamp_ns) * 1e-9;
    if (!(duration > 0)) continue;
    // An end without a measured velocity takes the gap's mean motion (the chord).
    const Velocity chord{(fb.T_world_camera.translation() - fa.T_world_camera.translation()) / duration,
                         log_so3(fb.T_world_camera.linear() * fa.T_world_camera.linear().transpose()) / duration};
    const Velocity va = velocity_at(a, -1).value_or(chord), vb = velocity_at(b, +1).value_or(chord);
    for (std::size_t k = a + 1; k < b; ++k) {
      FrameRecord& f = frames_[k];
      const double fraction = static_cast<double>(f.timestamp_ns - fa.timestamp_ns) * 1e-9 / duration;
      const Eigen::Isometry3d pose =
          hermite_pose(fa.T_world_camera, va, fb.T_world_camera, vb, duration, std::clamp(fraction, 0.0, 1.0));
      if (f.state != PoseState::bridged || !pose.isApprox(f.T_world_camera, 1e-12)) changed = true;
      f.T_world_camera = pose;
      f.state = PoseState::bridged;
      f.segment = fa.segment;
    }
  }
  return changed;
}

void TrajectoryRecord::append(const FrameRecord& frame) {
  write_or_throw(trajectory_.file, trajectory_line(frame), trajectory_.path);
  write_or_throw(keyframes_.file, keyframe_line(frame), keyframes_.path);
  write_or_throw(status_.file, status_line(frame), status_.path);
}

void TrajectoryRecord::rewrite() {
  std::string trajectory, keyframes, status = std::string(io::kFrameStatusHeader) + "\n";
  for (const FrameRecord& f : frames_) {
    trajectory += trajectory_line(f);
    keyframes += keyframe_line(f);
    status += status_line(f);
  }
  for (auto [out, text] :
       {std::pair{&trajectory_, &trajectory}, std::pair{&keyframes_, &keyframes}, std::pair{&status_, &status}}) {
    std::fclose(out->file);
    out->file = nullptr;
    replace_file(out->path, *text);
    out->file = open_file(out->path, "a");
  }
  ++rewrites_;
}

}  // namespace vkvo::system
