#include "eval/association.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vkvo::eval {

namespace {
io::Trajectory sorted_by_time(io::Trajectory trajectory) {
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const io::StampedPose& a, const io::StampedPose& b) { return a.t < b.t; });
  return trajectory;
}
}  // namespace

AssociatedPoses associate(const io::Trajectory& estimate, const io::Trajectory& groundtruth, double max_dt_s) {
  const io::Trajectory est = sorted_by_time(estimate);
  const io::Trajectory gt = sorted_by_time(groundtruth);

  // Nearest ground truth per estimate pose (binary search), then keep the closest claimant of each GT pose.
  constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> match(est.size(), none);
  std::vector<double> match_dt(est.size(), 0);
  std::vector<std::size_t> owner(gt.size(), none);
  for (std::size_t i = 0; i < est.size(); ++i) {
    const auto it =
        std::lower_bound(gt.begin(), gt.end(), est[i].t, [](const io::StampedPose& p, double t) { return p.t < t; });
    std::size_t best = none;
    double best_dt = std::numeric_limits<double>::infinity();
    for (auto candidate : {it, it == gt.begin() ? gt.end() : std::prev(it)}) {
      if (candidate == gt.end()) continue;
      const double dt = std::abs(candidate->t - est[i].t);
      if (dt < best_dt) best = static_cast<std::size_t>(candidate - gt.begin()), best_dt = dt;
    }
    if (best == none || best_dt > max_dt_s) continue;
    if (owner[best] != none) {
      if (match_dt[owner[best]] <= best_dt) continue;
      match[owner[best]] = none;
    }
    owner[best] = i;
    match[i] = best;
    match_dt[i] = best_dt;
  }

  AssociatedPoses result;
  for (std::size_t i = 0; i < est.size(); ++i) {
    if (match[i] == none) continue;
    result.t.push_back(est[i].t);
    result.estimate.push_back(est[i].pose);
    result.groundtruth.push_back(gt[match[i]].pose);
  }
  return result;
}

}  // namespace vkvo::eval
