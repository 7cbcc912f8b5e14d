#include "tools/synth/raycaster.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <opencv2/core/utility.hpp>

namespace vkvo::synth {
namespace {

constexpr int kTile = 16;
constexpr float kNear = 1e-3f;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Ray {
  Eigen::Vector3f origin, dir, inv_dir;  // dir has camera-z component 1, so the hit distance t is the depth
};

struct Hit {
  float t = kInf;
  int box = -1;  // -1: the room
  int face = 0;
  int surface_id() const { return (box + 1) * 6 + face; }
};

// Per-view state: camera, pose, and the boxes each image tile can see.
class View {
 public:
  View(const Scene& scene, const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera)
      : scene_(scene), camera_(camera) {
    R_ = T_world_camera.linear().cast<float>();
    origin_ = T_world_camera.translation().cast<float>();
    tiles_x_ = (camera.width + kTile - 1) / kTile;
    tiles_y_ = (camera.height + kTile - 1) / kTile;
    inv_fx_ = static_cast<float>(1.0 / camera.fx);
    du_ = R_.col(0) / static_cast<float>(camera.fx);
    dv_ = R_.col(1) / static_cast<float>(camera.fy);
    d00_ = R_.col(2) - static_cast<float>(camera.cx) * du_ - static_cast<float>(camera.cy) * dv_;
    bin_boxes();
  }

  // World direction through image point (px, py) is linear in px and py: dir = d00 + px * du + py * dv.
  Ray ray(float px, float py) const {
    Ray r{origin_, d00_ + px * du_ + py * dv_, {}};
    r.inv_dir = r.dir.cwiseInverse();
    return r;
  }

  Hit trace(const Ray& r, int tile) const {
    Hit hit = exit_room(r);
    for (int i = tile_start_[tile]; i < tile_start_[tile + 1]; ++i) {
      const int b = tile_boxes_[i];
      const Eigen::AlignedBox3f& box = scene_.boxes[b].bounds;
      const Eigen::Vector3f t0 = (box.min() - r.origin).cwiseProduct(r.inv_dir);
      const Eigen::Vector3f t1 = (box.max() - r.origin).cwiseProduct(r.inv_dir);
      const Eigen::Vector3f lo = t0.cwiseMin(t1), hi = t0.cwiseMax(t1);
      int axis = 0;
      const float t_near = lo.maxCoeff(&axis);
      if (t_near > kNear && t_near < hit.t && t_near <= hi.minCoeff()) {
        hit.t = t_near;
        hit.box = b;
        hit.face = 2 * axis + (r.dir[axis] < 0.f ? 1 : 0);  // entering through the side facing the camera
      }
    }
    return hit;
  }

  // The camera is inside the room: the ray leaves it through the nearest of the three faces it heads for.
  Hit exit_room(const Ray& r) const {
    Hit hit;
    for (int axis = 0; axis < 3; ++axis) {
      if (r.dir[axis] == 0.f) continue;
      const bool forward = r.dir[axis] > 0.f;
      const float wall = forward ? scene_.room.max()[axis] : scene_.room.min()[axis];
      const float t = (wall - r.origin[axis]) * r.inv_dir[axis];
      if (t < hit.t) {
        hit.t = t;
        hit.face = 2 * axis + (forward ? 1 : 0);
      }
    }
    return hit;
  }

  float shade(const Ray& r, const Hit& hit) const {
    const Eigen::Vector3f p = r.origin + hit.t * r.dir;
    const bool room = hit.box < 0;
    const Eigen::AlignedBox3f& bounds = room ? scene_.room : scene_.boxes[hit.box].bounds;
    const int texture = room ? scene_.room_textures[hit.face] : scene_.boxes[hit.box].textures[hit.face];
    const int axis = hit.face / 2;
    // Room faces look inwards, box faces outwards.
    const float normal_sign = (hit.face % 2 == 1) == room ? -1.f : 1.f;

    // Pixel footprint on the surface, sqrt of its area: depth / f, stretched by 1 / sqrt(cos incidence) (dir has
    // unit camera-z, so |dir[axis]| is cos(incidence) / cos(off-axis angle), which keeps fronto-parallel exact).
    const float footprint = hit.t * inv_fx_ * Texture::inv_sqrt(std::max(std::abs(r.dir[axis]), 0.02f));
    const Eigen::Vector2f uv = face_uv(bounds, hit.face, room, p);
    const float albedo = scene_.textures[texture].sample(uv.x(), uv.y(), footprint);

    // Soft point lights: I * (n . d) * F / (|d|^2 + F^2) with d to the light: cosine law, bounded near the lamp,
    // and about I * F / r when far; one division per light.
    float irradiance = scene_.ambient;
    const float falloff = scene_.light_falloff, falloff2 = falloff * falloff;
    for (const PointLight& light : scene_.lights) {
      const Eigen::Vector3f to_light = light.position - p;
      const float facing = normal_sign * to_light[axis];
      if (facing <= 0.f) continue;
      irradiance += light.intensity * facing * falloff / (to_light.squaredNorm() + falloff2);
    }
    return albedo * irradiance;
  }

  int tile_of(int x, int y) const { return (y / kTile) * tiles_x_ + x / kTile; }

 private:
  // Projected bounds of each box (near-plane clipped, +-1 pixel) -> the tiles that list it.
  void bin_boxes() {
    const Eigen::Matrix3f R_cw = R_.transpose();
    std::vector<std::vector<int>> per_tile(static_cast<size_t>(tiles_x_ * tiles_y_));
    for (int b = 0; b < static_cast<int>(scene_.boxes.size()); ++b) {
      const Eigen::AlignedBox3f& box = scene_.boxes[b].bounds;
      Eigen::Vector3f corners[8];
      for (int i = 0; i < 8; ++i)
        corners[i] = R_cw * (box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i)) - origin_);
      float x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
      auto add = [&](const Eigen::Vector3f& pc) {
        const float z = std::max(pc.z(), kNear);
        const float u = static_cast<float>(camera_.fx * pc.x() / z + camera_.cx);
        const float v = static_cast<float>(camera_.fy * pc.y() / z + camera_.cy);
        x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v);
      };
      for (int i = 0; i < 8; ++i) {
        if (corners[i].z() >= kNear) add(corners[i]);
        for (int bit = 1; bit < 8;
             bit <<= 1) {  // edges to corners differing in one coordinate, crossing the near plane
          if (i & bit) continue;
          const Eigen::Vector3f& a = corners[i];
          const Eigen::Vector3f& c = corners[i | bit];
          if ((a.z() < kNear) != (c.z() < kNear)) add(a + (c - a) * ((kNear - a.z()) / (c.z() - a.z())));
        }
      }
      if (x0 > x1) continue;  // entirely behind the camera
      const int tx0 = std::clamp(static_cast<int>(std::floor((x0 - 1.f) / kTile)), 0, tiles_x_ - 1);
      const int tx1 = std::clamp(static_cast<int>(std::floor((x1 + 1.f) / kTile)), 0, tiles_x_ - 1);
      const int ty0 = std::clamp(static_cast<int>(std::floor((y0 - 1.f) / kTile)), 0, tiles_y_ - 1);
      const int ty1 = std::clamp(static_cast<int>(std::floor((y1 + 1.f) / kTile)), 0, tiles_y_ - 1);
      if (x1 < -1.f || y1 < -1.f || x0 > camera_.width + 1.f || y0 > camera_.height + 1.f) continue;
      for (int ty = ty0; ty <= ty1; ++ty)
        for (int tx = tx0; tx <= tx1; ++tx) per_tile[static_cast<size_t>(ty * tiles_x_ + tx)].push_back(b);
    }
    tile_start_.assign(1, 0);
    for (const auto& list : per_tile) {
      tile_boxes_.insert(tile_boxes_.end(), list.begin(), list.end());
      tile_start_.push_back(static_cast<int>(tile_boxes_.size()));
    }
  }

  const Scene& scene_;
  PinholeCamera camera_;
  Eigen::Matrix3f R_;
  Eigen::Vector3f origin_;
  Eigen::Vector3f d00_, du_, dv_;
  float inv_fx_ = 1.f;
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<int> tile_start_, tile_boxes_;
};

// Rotated-grid offsets of the 4 anti-aliasing rays inside a pixel.
constexpr float kSubsamples[4][2] = {{-0.125f, -0.375f}, {0.375f, -0.125f}, {0.125f, 0.375f}, {-0.375f, 0.125f}};

void for_rows(int rows, bool parallel, const std::function<void(int, int)>& body) {
  if (!parallel) {
    body(0, rows);
    return;
  }
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& r) { body(r.start, r.end); });
}

}  // namespace

void RayCaster::render(const PinholeCamera& camera, const Eigen::Isometry3d& T_world_camera, cv::Mat& radiance,
                       cv::Mat* depth, const RenderOptions& options) const {
  const View view(scene_, camera, T_world_camera);
  radiance.create(camera.height, camera.width, CV_32F);
  if (depth) depth->create(camera.height, camera.width, CV_32F);
  cv::Mat ids(camera.height, camera.width, CV_32S);

  // Tile by tile: neighbouring rays hit the same texels and the same box list, which keeps the caches warm.
  const int tile_rows = (camera.height + kTile - 1) / kTile;
  for_rows(tile_rows, options.parallel, [&](int ty0, int ty1) {
    for (int ty = ty0; ty < ty1; ++ty) {
      const int y_end = std::min(camera.height, (ty + 1) * kTile);
      for (int x0 = 0; x0 < camera.width; x0 += kTile) {
        const int x_end = std::min(camera.width, x0 + kTile);
        const int tile = view.tile_of(x0, ty * kTile);
        for (int y = ty * kTile; y < y_end; ++y) {
          float* out = radiance.ptr<float>(y);
          int* id = ids.ptr<int>(y);
          float* z = depth ? depth->ptr<float>(y) : nullptr;
          for (int x = x0; x < x_end; ++x) {
            const Ray r = view.ray(static_cast<float>(x), static_cast<float>(y));
            const Hit hit = view.trace(r, tile);
            out[x] = view.shade(r, hit);
            id[x] = hit.surface_id();
            if (z) z[x] = hit.t;
          }
        }
      }
    }
  });
  if (!options.anti_alias) return;

  // Pixels whose right or lower neighbour shows another surface straddle an edge: average 4 rays there.
  for_rows(camera.height, options.parallel, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const int* id = ids.ptr<int>(y);
      const int* above = y > 0 ? ids.ptr<int>(y - 1) : nullptr;
      const int* below = y + 1 < camera.height ? ids.ptr<int>(y + 1) : nullptr;
      float* out = radiance.ptr<float>(y);
      for (int x = 0; x < camera.width; ++x) {
        const bool edge = (x + 1 < camera.width && id[x + 1] != id[x]) || (x > 0 && id[x - 1] != id[x]) ||
                          (below && below[x] != id[x]) || (above && above[x] != id[x]);
        if (!edge) continue;
        float sum = 0.f;
        for (const auto& offset : kSubsamples) {
          const Ray r = view.ray(static_cast<float>(x) + offset[0], static_cast<float>(y) + offset[1]);
          sum += view.shade(r, view.trace(r, view.tile_of(x, y)));
        }
        out[x] = 0.25f * sum;
      }
    }
  });
}

}  // namespace vkvo::synth
