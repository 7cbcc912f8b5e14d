#pragma once
// The synthetic indoor scene: a room seen from inside plus axis-aligned boxes (furniture, door and window frames),
// every face carrying an albedo texture, lit by point lights and an ambient term. Everything is axis-aligned so
// that the ray caster is analytic (slab tests).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tools/synth/texture.hpp"

namespace vkvo::synth {

// Face f of an axis-aligned box: axis = f / 2, on the max side when f is odd. Surface (u, v) coordinates in metres
// run along the two other axes: on walls (normal x or y) u runs to the viewer's right and v down from the top, so
// text painted on them reads correctly from the side they are seen from (inside the room, outside a box); floor
// and ceiling (normal z) have u = x - min.x, v = y - min.y.
struct FaceFrame {
  int u_axis, v_axis;
  bool u_flip;  // u = max[u_axis] - p[u_axis] instead of p[u_axis] - min[u_axis]
  bool v_down;  // v = max[v_axis] - p[v_axis] instead of p[v_axis] - min[v_axis]
};

// `from_inside`: the face is seen from inside the box (the room's walls).
inline FaceFrame face_frame(int face, bool from_inside) {
  // Seen from outside, the viewer's right runs towards -u on faces x = min (0) and y = max (3); from inside it is
  // the other two walls.
  const bool flip = (face == 0 || face == 3) != from_inside;
  switch (face / 2) {
    case 0: return {1, 2, flip, true};
    case 1: return {0, 2, flip, true};
    default: return {0, 1, false, false};
  }
}

// (width along u, height along v), metres.
inline Eigen::Vector2f face_extent(const Eigen::AlignedBox3f& box, int face) {
  const FaceFrame f = face_frame(face, false);
  const Eigen::Vector3f size = box.sizes();
  return {size[f.u_axis], size[f.v_axis]};
}

inline Eigen::Vector2f face_uv(const Eigen::AlignedBox3f& box, int face, bool from_inside, const Eigen::Vector3f& p) {
  const FaceFrame f = face_frame(face, from_inside);
  const float u = f.u_flip ? box.max()[f.u_axis] - p[f.u_axis] : p[f.u_axis] - box.min()[f.u_axis];
  const float v = f.v_down ? box.max()[f.v_axis] - p[f.v_axis] : p[f.v_axis] - box.min()[f.v_axis];
  return {u, v};
}

struct Box {
  Eigen::AlignedBox3f bounds;
  std::array<int, 6> textures{};  // index into Scene::textures per face
};

struct PointLight {
  Eigen::Vector3f position;
  float intensity = 1.f;  // irradiance on a surface facing it at the falloff distance is intensity / 2
};

struct Scene {
  Eigen::AlignedBox3f room;            // seen from inside
  std::array<int, 6> room_textures{};  // per face (0: x = min wall, 1: x = max wall, ..., 4: floor, 5: ceiling)
  std::vector<Box> boxes;
  std::vector<Texture> textures;
  std::vector<PointLight> lights;
  float ambient = 0.35f;
  float light_falloff = 2.5f;  // metres: a light gives intensity * cos * r F / (r^2 + F^2) at distance r

  int add_texture(Texture texture);
  void add_box(const Eigen::AlignedBox3f& bounds, const std::array<int, 6>& face_textures);
  void add_box(const Eigen::AlignedBox3f& bounds, int texture) {
    add_box(bounds, {texture, texture, texture, texture, texture, texture});
  }
};

struct SceneParams {
  Eigen::Vector3f room_min{-3.75f, -3.0f, 0.0f};
  Eigen::Vector3f room_max{3.75f, 3.0f, 3.0f};
  int num_boxes = 8;            // furniture boxes placed along the walls
  float furniture_band = 0.9f;  // boxes stay within this distance of a wall (the camera flies inside it)
  int posters_per_wall = 3;
  double texels_per_meter = 300.0;  // texture resolution of walls, floor, ceiling and boxes
  // Low texture: walls, floor, ceiling and boxes in flat albedo with faint, smooth shading (no grain, planks,
  // tiles or labels). Few corners remain, but every edge does: the room's, the boxes', the skirting board, the
  // door and window frames.
  bool plain_surfaces = false;
};

// Distance from `p` to the nearest surface of the scene: every surface is a face of the room or of a box, so it is
// the least distance to one of their boundaries (from inside or outside). A map's landmarks should lie on them.
float distance_to_surfaces(const Scene& scene, const Eigen::Vector3f& p);

// A seeded procedural room: plaster walls with posters, a door with a frame, a window with a frame, plank floor,
// tiled ceiling, cardboard boxes, two ceiling lights (with plain_surfaces: flat walls, floor, ceiling and boxes). The
// same params and seed give the same scene.
Scene generate_indoor_scene(const SceneParams& params, uint64_t seed);

}  // namespace vkvo::synth
