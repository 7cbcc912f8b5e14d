#include "map/map.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "io/config.hpp"

namespace vkvo::map {

MapParams load_map_params(const YAML::Node& section) {
  MapParams p;
  io::read_param(section, "min_point_observations", p.min_point_observations);
  io::read_param(section, "min_line_observations", p.min_line_observations);
  io::read_param(section, "culling_grace_keyframes", p.culling_grace_keyframes);
  io::read_param(section, "mono_points", p.mono_points);
  io::read_param(section, "mono_point_min_parallax_deg", p.mono_point_min_parallax_deg);
  return p;
}

void Frame::reset_associations() {
  point_ids.assign(keypoints.size(), kInvalidId);
  line_ids.assign(lines.size(), kInvalidId);
  if (right_x.empty()) right_x.assign(keypoints.size(), -1.0);
}

namespace {

// Points and lines share the observation bookkeeping; `ids` selects the keyframe's association vector.
template <typename Landmark>
Landmark& must_find(std::map<Id, Landmark>& table, Id id, const char* what) {
  const auto it = table.find(id);
  if (it == table.end()) throw std::out_of_range(std::string("map: no ") + what + " with id " + std::to_string(id));
  return it->second;
}

template <typename Landmark>
void link(std::map<Id, Landmark>& table, std::vector<Id> Frame::*ids, KeyFrame& kf, Id landmark_id, int index,
          const char* what) {
  Landmark& landmark = must_find(table, landmark_id, what);
  std::vector<Id>& kf_ids = kf.*ids;
  if (index < 0 || index >= static_cast<int>(kf_ids.size()))
    throw std::out_of_range(std::string("map: ") + what + " feature index out of range");
  // The feature may have belonged to another landmark, and the landmark may have used another feature here.
  if (const Id old = kf_ids[index]; old != kInvalidId && old != landmark_id) {
    if (auto it = table.find(old); it != table.end()) it->second.observations.erase(kf.id);
  }
  if (auto it = landmark.observations.find(kf.id); it != landmark.observations.end() && it->second != index)
    kf_ids[it->second] = kInvalidId;
  kf_ids[index] = landmark_id;
  landmark.observations[kf.id] = index;
}

template <typename Landmark>
void unlink(std::map<Id, Landmark>& table, std::vector<Id> Frame::*ids, std::map<Id, KeyFrame>& keyframes,
            Id landmark_id, Id kf_id) {
  const auto it = table.find(landmark_id);
  if (it == table.end()) return;
  const auto obs = it->second.observations.find(kf_id);
  if (obs == it->second.observations.end()) return;
  if (auto kf = keyframes.find(kf_id); kf != keyframes.end()) (kf->second.*ids)[obs->second] = kInvalidId;
  it->second.observations.erase(obs);
}

template <typename Landmark>
void erase_landmark(std::map<Id, Landmark>& table, std::vector<Id> Frame::*ids, std::map<Id, KeyFrame>& keyframes,
                    Id landmark_id) {
  const auto it = table.find(landmark_id);
  if (it == table.end()) return;
  for (const auto& [kf_id, index] : it->second.observations)
    if (auto kf = keyframes.find(kf_id); kf != keyframes.end()) (kf->second.*ids)[index] = kInvalidId;
  table.erase(it);
}

template <typename Landmark>
int cull_table(std::map<Id, Landmark>& table, std::vector<Id> Frame::*ids, std::map<Id, KeyFrame>& keyframes,
               int min_observations, int grace, Id last_kf) {
  std::vector<Id> doomed;
  for (const auto& [id, landmark] : table) {
    const int n = static_cast<int>(landmark.observations.size());
    // Age counts from the oldest observing keyframe (or creation, whichever is earlier).
    Id oldest = landmark.first_keyframe;
    if (n > 0) oldest = std::min(oldest, landmark.observations.begin()->first);
    const bool past_grace = last_kf != kInvalidId && oldest != kInvalidId && last_kf >= oldest + static_cast<Id>(grace);
    if (landmark.bad || n == 0 || (past_grace && n < min_observations)) doomed.push_back(id);
  }
  for (Id id : doomed) erase_landmark(table, ids, keyframes, id);
  return static_cast<int>(doomed.size());
}

template <typename Landmark>
void fuse_landmark(std::map<Id, Landmark>& table, std::vector<Id> Frame::*ids, std::map<Id, KeyFrame>& keyframes,
                   Id from, Id into, const char* what) {
  if (from == into) return;
  Landmark& source = must_find(table, from, what);
  Landmark& target = must_find(table, into, what);
  for (const auto& [kf_id, index] : source.observations) {
    KeyFrame& kf = keyframes.at(kf_id);
    (kf.*ids)[index] = kInvalidId;
    if (target.observations.count(kf_id)) continue;
    (kf.*ids)[index] = into;
    target.observations[kf_id] = index;
  }
  target.first_keyframe = std::min(target.first_keyframe, source.first_keyframe);
  table.erase(from);
}

}  // namespace

KeyFrame& Map::add_keyframe(const Frame& frame) {
  KeyFrame kf;
  static_cast<Frame&>(kf) = frame;
  kf.id = next_keyframe_id_++;
  if (kf.point_ids.size() != kf.keypoints.size() || kf.line_ids.size() != kf.lines.size() ||
      kf.right_x.size() != kf.keypoints.size())
    throw std::invalid_argument("map: keyframe association vectors must match the feature counts");
  KeyFrame& stored = keyframes_.emplace(kf.id, std::move(kf)).first->second;
  for (int i = 0; i < static_cast<int>(stored.point_ids.size()); ++i) {
    const Id p = std::exchange(stored.point_ids[i], kInvalidId);
    if (p != kInvalidId && points_.count(p)) add_point_observation(p, stored.id, i);
  }
  for (int i = 0; i < static_cast<int>(stored.line_ids.size()); ++i) {
    const Id l = std::exchange(stored.line_ids[i], kInvalidId);
    if (l != kInvalidId && lines_.count(l)) add_line_observation(l, stored.id, i);
  }
  return stored;
}

Id Map::add_point(const Eigen::Vector3d& position_world) {
  const Id id = next_point_id_++;
  points_[id] = MapPoint{id, position_world, {}, last_keyframe_id(), false};
  return id;
}

Id Map::add_line(const geometry::PlueckerLine& line_world) {
  const Id id = next_line_id_++;
  lines_[id] = MapLine{id, line_world.normalized(), {}, last_keyframe_id(), false, std::nullopt};
  return id;
}

void Map::add_point_observation(Id point, Id kf, int index) {
  link(points_, &Frame::point_ids, must_find(keyframes_, kf, "keyframe"), point, index, "point");
}
void Map::add_line_observation(Id line, Id kf, int index) {
  link(lines_, &Frame::line_ids, must_find(keyframes_, kf, "keyframe"), line, index, "line");
}
void Map::erase_point_observation(Id point, Id kf) { unlink(points_, &Frame::point_ids, keyframes_, point, kf); }
void Map::erase_line_observation(Id line, Id kf) { unlink(lines_, &Frame::line_ids, keyframes_, line, kf); }
void Map::erase_point(Id point) { erase_landmark(points_, &Frame::point_ids, keyframes_, point); }

void Map::erase_keyframe(Id kf) {
  const auto it = keyframes_.find(kf);
  if (it == keyframes_.end()) return;
  for (Id p : it->second.point_ids)
    if (auto pt = points_.find(p); pt != points_.end()) pt->second.observations.erase(kf);
  for (Id l : it->second.line_ids)
    if (auto ln = lines_.find(l); ln != lines_.end()) ln->second.observations.erase(kf);
  keyframes_.erase(it);
}

void Map::merge_segment(int from, int into, const Eigen::Isometry3d& T_into_from) {
  std::set<Id> points, lines;
  for (auto& [id, kf] : keyframes_) {
    if (kf.segment != from) continue;
    kf.segment = into;
    kf.T_world_camera = T_into_from * kf.T_world_camera;
    for (Id p : kf.point_ids)
      if (p != kInvalidId) points.insert(p);
    for (Id l : kf.line_ids)
      if (l != kInvalidId) lines.insert(l);
  }
  for (Id p : points)
    if (MapPoint* point = this->point(p)) point->position = T_into_from * point->position;
  for (Id l : lines) {
    MapLine* line = this->line(l);
    if (!line) continue;
    line->line = geometry::transform_line(T_into_from, line->line).normalized();
    if (line->endpoints)
      line->endpoints = std::make_pair(T_into_from * line->endpoints->first, T_into_from * line->endpoints->second);
  }
}

void Map::fuse_point(Id from, Id into) { fuse_landmark(points_, &Frame::point_ids, keyframes_, from, into, "point"); }
void Map::fuse_line(Id from, Id into) { fuse_landmark(lines_, &Frame::line_ids, keyframes_, from, into, "line"); }

std::vector<int> Map::segments() const {
  std::set<int> found;
  for (const auto& [id, kf] : keyframes_) found.insert(kf.segment);
  return {found.begin(), found.end()};
}

std::pair<int, int> Map::cull(const MapParams& params) {
  const Id last = last_keyframe_id();
  return {cull_table(points_, &Frame::point_ids, keyframes_, params.min_point_observations,
                     params.culling_grace_keyframes, last),
          cull_table(lines_, &Frame::line_ids, keyframes_, params.min_line_observations, params.culling_grace_keyframes,
                     last)};
}

std::vector<std::pair<Id, int>> Map::covisible_keyframes(Id kf_id, int min_shared) const {
  const KeyFrame& kf = keyframes_.at(kf_id);
  std::map<Id, int> shared;
  auto count = [&](const auto& table, const std::vector<Id>& ids) {
    for (Id id : ids) {
      if (id == kInvalidId) continue;
      const auto it = table.find(id);
      if (it == table.end()) continue;
      for (const auto& obs : it->second.observations)
        if (obs.first != kf_id) ++shared[obs.first];
    }
  };
  count(points_, kf.point_ids);
  count(lines_, kf.line_ids);
  std::vector<std::pair<Id, int>> out;
  for (const auto& [id, n] : shared)
    if (n >= min_shared) out.emplace_back(id, n);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  return out;
}

std::vector<Id> Map::local_window(Id kf, int size, int min_shared) const {
  std::vector<Id> others;
  for (const auto& [id, n] : covisible_keyframes(kf, min_shared)) others.push_back(id);
  std::sort(others.begin(), others.end(), std::greater<>());  // ids grow with time: most recent first
  std::vector<Id> window{kf};
  for (Id id : others) {
    if (static_cast<int>(window.size()) >= size) break;
    window.push_back(id);
  }
  return window;
}

void Map::trim_line(Id line_id, const geometry::PinholeCamera& camera) {
  MapLine& ml = must_find(lines_, line_id, "line");
  std::vector<geometry::LineObservation> observations;
  for (const auto& [kf_id, index] : ml.observations) {
    const KeyFrame& kf = keyframes_.at(kf_id);
    observations.push_back({kf.T_world_camera, kf.lines[index].left});
  }
  if (!observations.empty()) ml.endpoints = geometry::trim_line(ml.line, camera, observations);
}

KeyFrame* Map::keyframe(Id id) {
  auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : &it->second;
}
const KeyFrame* Map::keyframe(Id id) const {
  auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : &it->second;
}
MapPoint* Map::point(Id id) {
  auto it = points_.find(id);
  return it == points_.end() ? nullptr : &it->second;
}
const MapPoint* Map::point(Id id) const {
  auto it = points_.find(id);
  return it == points_.end() ? nullptr : &it->second;
}
MapLine* Map::line(Id id) {
  auto it = lines_.find(id);
  return it == lines_.end() ? nullptr : &it->second;
}
const MapLine* Map::line(Id id) const {
  auto it = lines_.find(id);
  return it == lines_.end() ? nullptr : &it->second;
}

}  // namespace vkvo::map
