// The written dataset layout (EuRoC/ASL + TUM) and the default preset's motion and viewing depths.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/test_support.hpp"
#include "io/config.hpp"
#include "synth/tiny_config.hpp"
#include "tools/synth/renderer.hpp"
#include "tools/synth/sequence_writer.hpp"

namespace vkvo::synth {
namespace {

namespace fs = std::filesystem;
using testing::tiny_config;

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(SequenceWriter, WritesTheAslLayout) {
  SynthConfig config = tiny_config(4);
  config.rig.baseline = 0.2;
  config.events = parse_events({"lights_off:2-2"});
  const fs::path dir = vkvo::test::temp_dir("synth_layout");
  write_synthetic_sequence(config, dir);

  for (const char* cam : {"cam0", "cam1"}) {
    const fs::path cam_dir = dir / "mav0" / cam;
    const auto csv = lines_of(cam_dir / "data.csv");
    ASSERT_EQ(csv.size(), 5u);
    EXPECT_EQ(csv[0], "#timestamp [ns],filename");
    for (size_t i = 1; i < csv.size(); ++i) {
      const std::string stamp = csv[i].substr(0, csv[i].find(','));
      EXPECT_EQ(csv[i], stamp + "," + stamp + ".png");
      const cv::Mat image = cv::imread((cam_dir / "data" / (stamp + ".png")).string(), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(image.empty());
      EXPECT_EQ(image.type(), CV_8UC1);
      EXPECT_EQ(image.cols, 160);
    }
    const YAML::Node sensor = YAML::LoadFile((cam_dir / "sensor.yaml").string());
    EXPECT_EQ(sensor["sensor_type"].as<std::string>(), "camera");
    EXPECT_EQ(sensor["T_BS"]["rows"].as<int>(), 4);
    EXPECT_EQ(sensor["T_BS"]["cols"].as<int>(), 4);
    const auto T = sensor["T_BS"]["data"].as<std::vector<double>>();
    ASSERT_EQ(T.size(), 16u);
    EXPECT_DOUBLE_EQ(T[3], std::string(cam) == "cam1" ? 0.2 : 0.0);  // cam1 = cam0 shifted by the baseline along x
    EXPECT_DOUBLE_EQ(T[0] + T[5] + T[10] + T[15], 4.0);
    EXPECT_EQ(sensor["rate_hz"].as<double>(), 20.0);
    EXPECT_EQ(sensor["resolution"].as<std::vector<int>>(), (std::vector<int>{160, 120}));
    EXPECT_EQ(sensor["camera_model"].as<std::string>(), "pinhole");
    EXPECT_EQ(sensor["intrinsics"].as<std::vector<double>>(), (std::vector<double>{100.0, 100.0, 79.5, 59.5}));
    EXPECT_EQ(sensor["distortion_model"].as<std::string>(), "radial-tangential");
    EXPECT_EQ(sensor["distortion_coefficients"].as<std::vector<double>>(), (std::vector<double>(4, 0.0)));
  }
  const auto gt = lines_of(dir / "mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_EQ(gt.size(), 5u);
  EXPECT_EQ(gt[0].rfind("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
                        "q_RS_z [], v_RS_R_x [m s^-1]",
                        0),
            0u);
  EXPECT_EQ(std::count(gt[1].begin(), gt[1].end(), ','), 16);
  EXPECT_EQ(lines_of(dir / "groundtruth_tum.txt").size(), 5u);  // comment + 4 poses

  // synth.yaml reproduces the configuration, and every key it holds is one the loader reads (`vkvo synth --config`
  // refuses keys it does not know).
  const YAML::Node written = YAML::LoadFile((dir / "synth.yaml").string());
  const io::KeyReadLog key_log;
  const SynthConfig again = load_synth_params(written);
  EXPECT_EQ(key_log.unread(written), std::vector<std::string>{});
  EXPECT_EQ(again.num_frames, 4);
  EXPECT_EQ(again.rig.width, 160);
  EXPECT_DOUBLE_EQ(again.rig.baseline, 0.2);
  ASSERT_EQ(again.events.size(), 1u);
  EXPECT_EQ(again.events[0].first_frame, 2);

  // scene_boxes.csv: the room, then every box of the scene the sequence was rendered from, each bound read back
  // to the same float.
  const Scene scene = generate_indoor_scene(config.scene, config.seed);
  const auto rows = lines_of(dir / "scene_boxes.csv");
  ASSERT_EQ(rows.size(), 2 + scene.boxes.size());  // header, room, boxes
  EXPECT_EQ(rows[0].rfind("# kind,min_x,min_y,min_z,max_x,max_y,max_z", 0), 0u);
  const auto expect_row = [](const std::string& row, const std::string& kind, const Eigen::AlignedBox3f& box) {
    std::istringstream fields(row);
    std::string field;
    std::getline(fields, field, ',');
    EXPECT_EQ(field, kind);
    for (int i = 0; i < 6; ++i) {
      ASSERT_TRUE(std::getline(fields, field, ',')) << row;
      EXPECT_EQ(std::stof(field), i < 3 ? box.min()[i] : box.max()[i - 3]) << row;
    }
  };
  expect_row(rows[1], "room", scene.room);
  for (std::size_t b = 0; b < scene.boxes.size(); ++b) expect_row(rows[2 + b], "box", scene.boxes[b].bounds);
}

TEST(SynthConfig, YamlOverridesAndTypeErrors) {
  const SynthConfig c = load_synth_params(YAML::Load("preset: small\nframes: 7\nspeed: 0.3\nevents: [\"dim:1-5\"]"));
  EXPECT_EQ(c.num_frames, 7);
  EXPECT_EQ(c.rig.width, 320);
  EXPECT_DOUBLE_EQ(c.trajectory.speed, 0.3);
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].kind, EventKind::dimming);
  const SynthConfig plain = load_synth_params(YAML::Load("preset: small\nplain_surfaces: true\nposters_per_wall: 0"));
  EXPECT_TRUE(plain.scene.plain_surfaces);
  EXPECT_EQ(plain.scene.posters_per_wall, 0);
  try {
    load_synth_params(YAML::Load("frames: many"));
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frames"), std::string::npos) << e.what();
  }
}

// Issue 36: a zero resolution used to crash the renderer; every unusable value is refused by name before rendering.
TEST(SynthConfig, UnusableValuesAreRefusedByName) {
  auto expect_refused = [](SynthConfig c, const std::string& fragment) {
    try {
      write_synthetic_sequence(c, test::temp_dir("synth_refused") / "out", nullptr);
      ADD_FAILURE() << "no exception for " << fragment;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  SynthConfig c = synth_preset("small");
  c.rig.width = 0;
  expect_refused(c, "resolution 0x240");
  c = synth_preset("small");
  c.rig.height = 100000;
  expect_refused(c, "resolution 320x100000");
  c = synth_preset("small");
  c.rate_hz = std::nan("");
  expect_refused(c, "rate_hz");
  c = synth_preset("small");
  c.num_frames = 0;
  expect_refused(c, "frames");
  c = synth_preset("small");
  c.scene.posters_per_wall = -1;
  expect_refused(c, "posters_per_wall");
  EXPECT_NO_THROW(validate_synth_config(synth_preset("small")));
  EXPECT_NO_THROW(validate_synth_config(synth_preset("low_texture")));
}

// The demo's camera: about 0.5 m/s, inside the free part of the room, looking at surfaces 1-6 m away.
TEST(SynthPreset, DefaultTrajectoryStaysInsideLookingAtNearbySurfaces) {
  SynthConfig config = synth_preset("default");
  const Scene scene = generate_indoor_scene(config.scene, config.seed);
  const SmoothTrajectory trajectory(config.trajectory, config.seed);
  double path = 0;
  for (int k = 1; k < config.num_frames; ++k)
    path +=
        (trajectory.pose(k / config.rate_hz).translation() - trajectory.pose((k - 1) / config.rate_hz).translation())
            .norm();
  const double duration = (config.num_frames - 1) / config.rate_hz;
  EXPECT_NEAR(path / duration, 0.5, 0.05);

  // Depth through a coarse grid of pixels (a 94x60 version of the camera) every 10th frame.
  const RayCaster caster(scene);
  const PinholeCamera small{94, 60, config.rig.fx / 8, config.rig.fy / 8, 46.5, 29.5};
  std::vector<float> medians;
  for (int k = 0; k < config.num_frames; k += 10) {
    const Eigen::Isometry3d T = trajectory.pose(k / config.rate_hz);
    const Eigen::Vector3f p = T.translation().cast<float>();
    EXPECT_TRUE(scene.room.contains(p)) << "frame " << k;
    for (const Box& box : scene.boxes) EXPECT_GT(box.bounds.exteriorDistance(p), 0.5f) << "frame " << k;
    cv::Mat radiance, depth;
    caster.render(small, T, radiance, &depth);
    std::vector<float> d(depth.begin<float>(), depth.end<float>());
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    medians.push_back(d[d.size() / 2]);
    EXPECT_GT(medians.back(), 1.0f) << "frame " << k;
    EXPECT_LT(medians.back(), 6.0f) << "frame " << k;
    std::nth_element(d.begin(), d.begin() + d.size() / 20, d.end());
    EXPECT_GT(d[d.size() / 20], 0.5f) << "frame " << k << ": 5% of the view closer than 0.5 m";
  }
}

// Left and right images agree through the rendered depth: sampling the right image at x - f b / z reproduces the
// left one (away from occlusions), and a wrong baseline sign does not.
TEST(StereoRenderer, RightImageIsTheLeftShiftedByTheDisparity) {
  SynthConfig config = tiny_config(1);
  config.sensor.read_noise = 0;
  config.sensor.shot_noise = 0;
  const StereoRenderer renderer(config, std::make_shared<Scene>(generate_indoor_scene(config.scene, 3)));
  cv::Mat depth;
  const cv::Mat left = renderer.render_clean(0, 0, &depth), right = renderer.render_clean(0, 1);
  auto warp_error = [&](double sign) {
    cv::Mat map_x(depth.size(), CV_32F), map_y(depth.size(), CV_32F);
    for (int y = 0; y < depth.rows; ++y)
      for (int x = 0; x < depth.cols; ++x) {
        map_x.at<float>(y, x) =
            static_cast<float>(x - sign * config.rig.fx * config.rig.baseline / depth.at<float>(y, x));
        map_y.at<float>(y, x) = static_cast<float>(y);
      }
    cv::Mat warped;
    cv::remap(right, warped, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(-1));
    cv::Mat valid = warped >= 0, diff;
    cv::absdiff(warped, left, diff);
    return cv::mean(diff, valid)[0];  // median-robust enough: occlusions are a few percent of the pixels
  };
  const double right_sign = warp_error(1.0), wrong_sign = warp_error(-1.0);
  EXPECT_LT(right_sign, 3.0);  // DN, linear interpolation of a texture rendered at a shifted centre
  EXPECT_GT(wrong_sign, 2.0 * right_sign);
}

}  // namespace
}  // namespace vkvo::synth
