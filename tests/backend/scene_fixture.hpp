#pragma once
// Synthetic stereo scenes for the back-end tests and benchmark: a rig moving along a gentle curve past random
// points and line segments; exact observations plus optional pixel noise, turned into a Map.
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.hpp"
#include "geometry/line3d.hpp"
#include "geometry/scene.hpp"  // tests/geometry: test_stereo_camera
#include "map/map.hpp"

namespace vkvo::test {

struct SceneSpec {
  int num_keyframes = 6;
  int num_points = 300;
  int num_lines = 60;
  double step = 0.25;            // m between keyframes
  double pixel_noise = 0.0;      // sigma of the Gaussian noise on every pixel coordinate
  double stereo_fraction = 0.7;  // share of observations that also have a right-image measurement
  unsigned seed = 1;
};

struct Scene {
  geometry::StereoCamera stereo;
  std::vector<Eigen::Isometry3d> T_world_camera;                      // true keyframe poses
  std::vector<Eigen::Vector3d> points;                                // true points
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;  // true 3D segments
  // Observations per keyframe (pixels with noise): point index, pixel, right x (or -1) / line index, segments.
  struct PointObs {
    int point;
    Eigen::Vector2d pixel;
    double right_x;
  };
  struct LineObs {
    int line;
    geometry::Segment2d left;
    std::optional<geometry::Segment2d> right;
  };
  std::vector<std::vector<PointObs>> point_obs;
  std::vector<std::vector<LineObs>> line_obs;
};

// The geometry tests' camera (fx != fy on purpose).
inline geometry::StereoCamera scene_camera() { return test_stereo_camera(); }

inline Eigen::Isometry3d scene_pose(int k, double step) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(step * k, 0.05 * std::sin(0.7 * k), 0.03 * k);
  T.linear() = (Eigen::AngleAxisd(0.04 * k, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.02 * std::cos(k), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

inline Scene make_scene(const SceneSpec& spec) {
  Scene s;
  s.stereo = scene_camera();
  std::mt19937 rng(spec.seed);
  std::normal_distribution<double> noise(0.0, spec.pixel_noise > 0 ? spec.pixel_noise : 1.0);
  auto jitter = [&]() { return spec.pixel_noise > 0 ? noise(rng) : 0.0; };
  std::uniform_real_distribution<double> ux(-3.0, 3.0 + spec.step * spec.num_keyframes), uy(-1.5, 1.5), uz(2.5, 8.0),
      u01(0.0, 1.0);
  for (int k = 0; k < spec.num_keyframes; ++k) s.T_world_camera.push_back(scene_pose(k, spec.step));
  for (int i = 0; i < spec.num_points; ++i) s.points.emplace_back(ux(rng), uy(rng), uz(rng));
  while (static_cast<int>(s.segments.size()) < spec.num_lines) {
    const Eigen::Vector3d a(ux(rng), uy(rng), uz(rng));
    Eigen::Vector3d d(u01(rng) - 0.5, u01(rng) - 0.5, 0.5 * (u01(rng) - 0.5));
    if (std::abs(d.normalized().x()) > 0.8) continue;  // keep away from lines parallel to the baseline
    s.segments.emplace_back(a, a + 1.5 * d.normalized());
  }
  const auto& cam = s.stereo.camera;
  s.point_obs.resize(spec.num_keyframes);
  s.line_obs.resize(spec.num_keyframes);
  for (int k = 0; k < spec.num_keyframes; ++k) {
    const Eigen::Isometry3d T_cw = s.T_world_camera[k].inverse();
    for (int i = 0; i < spec.num_points; ++i) {
      const Eigen::Vector3d p = T_cw * s.points[i];
      if (p.z() < 0.5) continue;
      const Eigen::Vector2d px = cam.project(p), pr = s.stereo.project_right(p);
      if (!cam.in_image(px, 5)) continue;
      const bool stereo = u01(rng) < spec.stereo_fraction && cam.in_image(pr, 5);
      s.point_obs[k].push_back({i, px + Eigen::Vector2d(jitter(), jitter()), stereo ? pr.x() + jitter() : -1.0});
    }
    for (int j = 0; j < spec.num_lines; ++j) {
      const Eigen::Vector3d a = T_cw * s.segments[j].first, b = T_cw * s.segments[j].second;
      if (a.z() < 0.5 || b.z() < 0.5) continue;
      // Each view sees a random part of the segment (endpoints differ between views, as detected segments do).
      const double s0 = 0.2 * u01(rng), s1 = 1.0 - 0.2 * u01(rng);
      const Eigen::Vector3d A = a + s0 * (b - a), B = a + s1 * (b - a);
      const Eigen::Vector2d la = cam.project(A), lb = cam.project(B);
      const Eigen::Vector2d ra = s.stereo.project_right(A), rb = s.stereo.project_right(B);
      if (!cam.in_image(la, 5) || !cam.in_image(lb, 5) || (la - lb).norm() < 20) continue;
      Scene::LineObs obs{
          j, geometry::Segment2d(la.x() + jitter(), la.y() + jitter(), lb.x() + jitter(), lb.y() + jitter()),
          std::nullopt};
      if (u01(rng) < spec.stereo_fraction && cam.in_image(ra, 5) && cam.in_image(rb, 5))
        obs.right = geometry::Segment2d(ra.x() + jitter(), ra.y() + jitter(), rb.x() + jitter(), rb.y() + jitter());
      s.line_obs[k].push_back(obs);
    }
  }
  return s;
}

// Map with one keyframe per scene keyframe and landmarks at the true values (perturb them afterwards). Landmarks
// seen by fewer than two keyframes are left out. Returns the map ids of the scene's points / lines (or invalid).
struct SceneMap {
  map::Map map;
  std::vector<map::Id> keyframe_ids, point_ids, line_ids;
};

inline SceneMap make_scene_map(const Scene& s) {
  SceneMap out;
  std::vector<int> point_views(s.points.size(), 0), line_views(s.segments.size(), 0);
  for (size_t k = 0; k < s.point_obs.size(); ++k) {
    for (const auto& o : s.point_obs[k]) ++point_views[o.point];
    for (const auto& o : s.line_obs[k]) ++line_views[o.line];
  }
  out.point_ids.assign(s.points.size(), map::kInvalidId);
  out.line_ids.assign(s.segments.size(), map::kInvalidId);
  for (size_t i = 0; i < s.points.size(); ++i)
    if (point_views[i] >= 2) out.point_ids[i] = out.map.add_point(s.points[i]);
  for (size_t j = 0; j < s.segments.size(); ++j)
    if (line_views[j] >= 2)
      out.line_ids[j] =
          out.map.add_line(geometry::PlueckerLine::from_points(s.segments[j].first, s.segments[j].second));
  for (size_t k = 0; k < s.point_obs.size(); ++k) {
    map::Frame f;
    f.frame_id = k;
    f.T_world_camera = s.T_world_camera[k];
    for (const auto& o : s.point_obs[k]) {
      f.keypoints.push_back(o.pixel);
      f.right_x.push_back(o.right_x);
    }
    for (const auto& o : s.line_obs[k]) f.lines.push_back({o.left, o.right});
    f.reset_associations();
    for (size_t i = 0; i < s.point_obs[k].size(); ++i) f.point_ids[i] = out.point_ids[s.point_obs[k][i].point];
    for (size_t j = 0; j < s.line_obs[k].size(); ++j) f.line_ids[j] = out.line_ids[s.line_obs[k][j].line];
    out.keyframe_ids.push_back(out.map.add_keyframe(f).id);
  }
  return out;
}

inline Eigen::Isometry3d perturb(const Eigen::Isometry3d& T, std::mt19937& rng, double translation, double rotation) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w(n(rng), n(rng), n(rng));
  D.linear() = Eigen::AngleAxisd(rotation, w.normalized()).toRotationMatrix();
  D.translation() = translation * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  return T * D;
}

inline double translation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}
inline double rotation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace vkvo::test
