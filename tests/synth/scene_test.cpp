// The scene's surfaces as a reference for maps: closed-form distances to the room's walls and a box's faces.
#include <gtest/gtest.h>

#include "tools/synth/scene.hpp"

namespace vkvo::synth {
namespace {

constexpr float kTolerance = 1e-6f;  // float rounding of the coordinates

TEST(Scene, DistanceToSurfacesIsTheNearestFaceOfTheRoomOrABox) {
  Scene scene;
  scene.room = Eigen::AlignedBox3f(Eigen::Vector3f(-2, -1, 0), Eigen::Vector3f(2, 1, 3));
  scene.add_box(Eigen::AlignedBox3f(Eigen::Vector3f(1, -1, 0), Eigen::Vector3f(1.5f, -0.5f, 0.8f)), 0);
  // Inside the room, away from the box: the nearest wall (y = 1 is 0.3 away), the floor or the ceiling.
  EXPECT_NEAR(distance_to_surfaces(scene, {0, 0.7f, 1.5f}), 0.3f, kTolerance);
  EXPECT_NEAR(distance_to_surfaces(scene, {0, 0, 0.2f}), 0.2f, kTolerance);
  // On a wall and on the box's top face: 0.
  EXPECT_NEAR(distance_to_surfaces(scene, {-2, 0.5f, 1}), 0.0f, kTolerance);
  EXPECT_NEAR(distance_to_surfaces(scene, {1.2f, -0.8f, 0.8f}), 0.0f, kTolerance);
  // Beside the box's vertical edge (x = 1.5, y = -0.5): 0.15 and 0.2 off it is 0.25 from the box; 0.3 and 0.4 off
  // it, the wall x = 2 (0.2 away) is nearer than the box (0.5).
  EXPECT_NEAR(distance_to_surfaces(scene, {1.65f, -0.3f, 0.5f}), 0.25f, kTolerance);
  EXPECT_NEAR(distance_to_surfaces(scene, {1.8f, -0.1f, 0.5f}), 0.2f, kTolerance);
  // Inside the box: its nearest face; outside the room: the distance back to it.
  EXPECT_NEAR(distance_to_surfaces(scene, {1.1f, -0.7f, 0.4f}), 0.1f, kTolerance);
  EXPECT_NEAR(distance_to_surfaces(scene, {0, 4, 3}), 3.0f, kTolerance);
}

}  // namespace
}  // namespace vkvo::synth
