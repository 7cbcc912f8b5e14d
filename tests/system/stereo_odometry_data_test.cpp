// StereoOdometry with the real networks (label `data`): docs/usage.md's live-input example, SuperPoint converted from
// the shared ONNX and the NN matcher on the device, fed the raw (unrectified) EuRoC pairs one at a time as a
// camera driver would.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "eval/evaluate.hpp"
#include "io/dataset.hpp"
#include "io/model_pack.hpp"
#include "io/trajectory.hpp"
#include "system/network_frontend.hpp"
#include "system/stereo_odometry.hpp"
#include "tools/convert/convert.hpp"

namespace vkvo::system {
namespace {

TEST(StereoOdometryData, TracksRawEurocPairsPushedOneAtATime) {
  VKVO_REQUIRE_DATA(dataset_dir, "datasets/euroc_mh01_subset/MH_01_easy");
  VKVO_REQUIRE_DATA(onnx, "models/superpoint_v1.onnx");
  constexpr std::size_t kFrames = 15;
  const auto config = load_vo_config(test::source_dir() / "config" / "euroc.yaml");
  const auto dataset = io::open_dataset(dataset_dir, config.dataset);
  const auto pack_file = test::temp_dir("stereo_odometry_data") / "superpoint.vkvopack";
  convert::convert_file(onnx, pack_file, io::NetworkKind::superpoint);
  const auto superpoint = io::ModelPack::load(pack_file, io::NetworkKind::superpoint);
  auto features = make_network_frontend(test::gpu(), superpoint, nullptr, config);
  auto keyframes = make_network_frontend(test::gpu(), superpoint, nullptr, config);
  StereoOdometry odometry(config, dataset->calibration(), *features, *keyframes);

  io::Trajectory trajectory;
  for (std::size_t i = 0; i < kFrames; ++i) {
    const io::StereoImages raw = dataset->load(i);  // unrectified, as the cameras give them
    const OdometryPose pose = odometry.track(raw.left, raw.right, dataset->frame(i).timestamp_ns);
    EXPECT_TRUE(pose.tracked) << "frame " << i;
    EXPECT_EQ(pose.new_segment, i == 0) << "frame " << i;
    trajectory.push_back({dataset->frame(i).timestamp_s, pose.T_world_camera});
  }
  const auto groundtruth = io::read_dataset_groundtruth(*dataset);
  ASSERT_TRUE(groundtruth.has_value());
  const eval::EvaluationResult evaluation = eval::evaluate(trajectory, groundtruth->poses);
  spdlog::info("StereoOdometry on the first {} EuRoC pairs: ATE RMSE {:.4f} m, {} keyframes", kFrames,
               evaluation.ate.translation_m.rmse, odometry.keyframes());
  // Bound: issue 7's 3 cm (the measured ATE and time: docs/accuracy.md, docs/testing.md).
  EXPECT_EQ(evaluation.associated_poses, kFrames);
  EXPECT_LT(evaluation.ate.translation_m.rmse, 0.03);
  EXPECT_EQ(odometry.tracking_losses(), 0);
}

}  // namespace
}  // namespace vkvo::system
