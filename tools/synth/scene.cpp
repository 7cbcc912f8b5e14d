#include "tools/synth/scene.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "tools/synth/texture_painter.hpp"

namespace vkvo::synth {

int Scene::add_texture(Texture texture) {
  textures.push_back(std::move(texture));
  return static_cast<int>(textures.size()) - 1;
}

void Scene::add_box(const Eigen::AlignedBox3f& bounds, const std::array<int, 6>& face_textures) {
  boxes.push_back(Box{bounds, face_textures});
}

namespace {

// Builds the scene step by step; keeps the wall canvases open until doors, windows and posters are painted.
class RoomBuilder {
 public:
  RoomBuilder(const SceneParams& params, uint64_t seed)
      : params_(params), tpm_(params.texels_per_meter), rng_(seed ? seed : 0x5eed) {
    scene_.room = Eigen::AlignedBox3f(params.room_min, params.room_max);
  }

  Scene build() {
    const bool plain = params_.plain_surfaces;
    for (int face = 0; face < 4; ++face) {
      const double albedo = rng_.uniform(0.55, 0.75);
      walls_[face] = plain ? paint::plain(canvas_size(face), tpm_, albedo, true, rng_)
                           : paint::plaster(canvas_size(face), tpm_, albedo, rng_);
    }
    add_door(rng_.uniform(0, 4));
    add_window(rng_.uniform(0, 4));
    for (int face = 0; face < 4; ++face) add_posters(face);
    for (int face = 0; face < 4; ++face) scene_.room_textures[face] = scene_.add_texture(Texture(walls_[face], tpm_));
    scene_.room_textures[4] = scene_.add_texture(Texture(
        plain ? paint::plain(canvas_size(4), tpm_, 0.4, false, rng_) : paint::planks(canvas_size(4), tpm_, rng_),
        tpm_));
    scene_.room_textures[5] = scene_.add_texture(Texture(plain ? paint::plain(canvas_size(5), tpm_, 0.85, false, rng_)
                                                               : paint::ceiling_tiles(canvas_size(5), tpm_, rng_),
                                                         tpm_));
    add_furniture();
    const Eigen::Vector3f c = scene_.room.center();
    const float top = scene_.room.max().z() - 0.1f, half = 0.25f * scene_.room.sizes().x();
    scene_.lights = {{{c.x() - half, c.y(), top}, 1.0f}, {{c.x() + half, c.y(), top}, 1.0f}};
    return std::move(scene_);
  }

 private:
  cv::Size canvas_size(int face) const {
    const Eigen::Vector2f extent = face_extent(scene_.room, face);
    return {std::max(1, cvRound(extent.x() * tpm_)), std::max(1, cvRound(extent.y() * tpm_))};
  }

  cv::Rect to_texels(float u, float v, float w, float h) const {
    return {cvRound(u * tpm_), cvRound(v * tpm_), cvRound(w * tpm_), cvRound(h * tpm_)};
  }

  // A point on wall `face` at surface coordinates (u, v), pushed `out` metres into the room.
  Eigen::Vector3f wall_point(int face, float u, float v, float out) const {
    const FaceFrame f = face_frame(face, true);
    Eigen::Vector3f p;
    const int axis = face / 2;
    const bool max_side = face % 2;
    p[axis] = max_side ? scene_.room.max()[axis] - out : scene_.room.min()[axis] + out;
    p[f.u_axis] = f.u_flip ? scene_.room.max()[f.u_axis] - u : scene_.room.min()[f.u_axis] + u;
    p[f.v_axis] = scene_.room.max()[f.v_axis] - v;  // walls have v downward from the top
    return p;
  }

  // A frame molding: a thin box on wall `face` covering wall rectangle (u, v, w, h), protruding `depth`.
  void add_molding(int face, float u, float v, float w, float h, float depth, int texture) {
    Eigen::AlignedBox3f box(wall_point(face, u, v, 0.f));
    box.extend(wall_point(face, u + w, v + h, depth));
    scene_.add_box(box, texture);
  }

  // Rectangle frame of bars `bar` wide around wall rectangle (u, v, w, h); `sill` also adds the bottom bar.
  void add_frame(int face, float u, float v, float w, float h, bool sill) {
    const float bar = 0.08f, depth = 0.05f;
    const int wood = scene_.add_texture(Texture(paint::cardboard({64, 64}, 64.0 / 0.25, rng_), 64.0 / 0.25));
    add_molding(face, u - bar, v - bar, bar, h + bar, depth, wood);      // left jamb
    add_molding(face, u + w, v - bar, bar, h + bar, depth, wood);        // right jamb
    add_molding(face, u - bar, v - bar, w + 2 * bar, bar, depth, wood);  // lintel
    if (sill) add_molding(face, u - bar, v + h, w + 2 * bar, bar, depth, wood);
  }

  void add_door(int face) {
    const Eigen::Vector2f extent = face_extent(scene_.room, face);
    const float w = 0.9f, h = std::min(2.05f, extent.y() - 0.3f);
    const float u = static_cast<float>(rng_.uniform(0.5, std::max(0.6, double(extent.x() - w - 0.5))));
    const float v = extent.y() - h;
    paint::door(walls_[face], to_texels(u, v, w, h), tpm_, rng_);
    add_frame(face, u, v, w, h, false);
    occupied_[face].push_back({u - 0.2f, u + w + 0.2f});
    door_ = {face, u - 0.3f, u + w + 0.3f};
  }

  void add_window(int face) {
    const Eigen::Vector2f extent = face_extent(scene_.room, face);
    const float w = 1.4f, h = std::min(1.1f, extent.y() - 1.4f);
    float u = static_cast<float>(rng_.uniform(0.4, std::max(0.5, double(extent.x() - w - 0.4))));
    if (!free_span(face, u - 0.2f, u + w + 0.2f)) u = extent.x() - w - 0.4f - rng_.uniform(0.f, 0.3f);
    if (!free_span(face, u - 0.2f, u + w + 0.2f)) u = 0.4f;
    const float v = 0.9f;
    paint::window(walls_[face], to_texels(u, v, w, h), tpm_, rng_);
    add_frame(face, u, v, w, h, true);
    occupied_[face].push_back({u - 0.2f, u + w + 0.2f});
  }

  bool free_span(int face, float a, float b) const {
    return std::none_of(occupied_[face].begin(), occupied_[face].end(),
                        [&](const std::pair<float, float>& s) { return a < s.second && s.first < b; });
  }

  void add_posters(int face) {
    const Eigen::Vector2f extent = face_extent(scene_.room, face);
    for (int i = 0, tries = 0; i < params_.posters_per_wall && tries < 50; ++tries) {
      const float w = static_cast<float>(rng_.uniform(0.5, 1.1)), h = static_cast<float>(rng_.uniform(0.5, 1.0));
      const float u = static_cast<float>(rng_.uniform(0.2, std::max(0.3, double(extent.x() - w - 0.2))));
      if (!free_span(face, u - 0.1f, u + w + 0.1f)) continue;
      const float v = static_cast<float>(rng_.uniform(0.35, std::max(0.4, double(extent.y() - h - 1.0))));
      paint::poster(walls_[face], to_texels(u, v, w, h), tpm_, rng_);
      occupied_[face].push_back({u - 0.1f, u + w + 0.1f});
      ++i;
    }
  }

  // Boxes along the walls, inside the furniture band, not overlapping each other or the door.
  void add_furniture() {
    const Eigen::AlignedBox3f& room = scene_.room;
    std::vector<Eigen::AlignedBox3f> placed;
    for (int i = 0, tries = 0; i < params_.num_boxes && tries < 500; ++tries) {
      const Eigen::Vector3f size(static_cast<float>(rng_.uniform(0.3, 0.85)),
                                 static_cast<float>(rng_.uniform(0.3, 0.85)),
                                 static_cast<float>(rng_.uniform(0.25, 1.1)));
      if (size.x() > params_.furniture_band && size.y() > params_.furniture_band) continue;
      const int face = rng_.uniform(0, 4);
      const int axis = face / 2, along = 1 - axis;
      Eigen::Vector3f lo;
      lo[axis] = face % 2 ? room.max()[axis] - size[axis] - static_cast<float>(rng_.uniform(0.0, 0.1))
                          : room.min()[axis] + static_cast<float>(rng_.uniform(0.0, 0.1));
      lo[along] = static_cast<float>(rng_.uniform(room.min()[along] + 0.05, room.max()[along] - size[along] - 0.05));
      lo.z() = room.min().z();
      Eigen::AlignedBox3f box(lo, lo + size);
      const bool too_deep = face % 2 ? box.min()[axis] < room.max()[axis] - params_.furniture_band
                                     : box.max()[axis] > room.min()[axis] + params_.furniture_band;
      if (too_deep || blocks_door(box)) continue;
      Eigen::AlignedBox3f padded = box;
      padded.extend(box.min() - Eigen::Vector3f::Constant(0.05f)).extend(box.max() + Eigen::Vector3f::Constant(0.05f));
      if (std::any_of(placed.begin(), placed.end(), [&](const auto& b) { return b.intersects(padded); })) continue;
      scene_.add_box(box, box_faces(box));
      placed.push_back(box);
      // Sometimes a smaller box on top: more corners, more depth edges.
      if (rng_.uniform(0, 3) == 0 && size.z() < 0.8f) {
        const Eigen::Vector3f top_size(size.x() * 0.6f, size.y() * 0.6f, static_cast<float>(rng_.uniform(0.2, 0.4)));
        const Eigen::Vector3f top_lo(lo.x() + 0.1f * size.x(), lo.y() + 0.2f * size.y(), lo.z() + size.z());
        const Eigen::AlignedBox3f top(top_lo, top_lo + top_size);
        scene_.add_box(top, box_faces(top));
      }
      ++i;
    }
  }

  // A texture per face: cardboard, or one flat albedo per face (so that the box's edges show) for plain surfaces.
  std::array<int, 6> box_faces(const Eigen::AlignedBox3f& box) {
    std::array<int, 6> faces{};
    for (int f = 0; f < 6; ++f) {
      const Eigen::Vector2f e = face_extent(box, f);
      const cv::Size size(cvRound(e.x() * tpm_), cvRound(e.y() * tpm_));
      faces[f] = scene_.add_texture(Texture(params_.plain_surfaces
                                                ? paint::plain(size, tpm_, rng_.uniform(0.2, 0.9), false, rng_)
                                                : paint::cardboard(size, tpm_, rng_),
                                            tpm_));
    }
    return faces;
  }

  bool blocks_door(const Eigen::AlignedBox3f& box) const {
    const Eigen::Vector3f a = wall_point(door_.face, door_.u0, 0.f, 0.f),
                          b = wall_point(door_.face, door_.u1, 0.f, 1.0f);
    Eigen::AlignedBox3f zone(a.cwiseMin(b), a.cwiseMax(b));
    zone.min().z() = scene_.room.min().z();
    zone.max().z() = scene_.room.max().z();
    return zone.intersects(box);
  }

  struct DoorZone {
    int face = 0;
    float u0 = 0, u1 = 0;
  };

  const SceneParams& params_;
  double tpm_;
  cv::RNG rng_;
  Scene scene_;
  std::array<cv::Mat, 4> walls_;
  std::array<std::vector<std::pair<float, float>>, 4> occupied_;
  DoorZone door_;
};

}  // namespace

Scene generate_indoor_scene(const SceneParams& params, uint64_t seed) { return RoomBuilder(params, seed).build(); }

namespace {

float distance_to_boundary(const Eigen::AlignedBox3f& box, const Eigen::Vector3f& p) {
  if (box.contains(p)) return std::min((p - box.min()).minCoeff(), (box.max() - p).minCoeff());
  return std::sqrt(box.squaredExteriorDistance(p));
}

}  // namespace

float distance_to_surfaces(const Scene& scene, const Eigen::Vector3f& p) {
  float nearest = distance_to_boundary(scene.room, p);
  for (const Box& box : scene.boxes) nearest = std::min(nearest, distance_to_boundary(box.bounds, p));
  return nearest;
}

}  // namespace vkvo::synth
