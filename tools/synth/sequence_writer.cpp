#include "tools/synth/sequence_writer.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

namespace vkvo::synth {
namespace fs = std::filesystem;
namespace {

std::ofstream open_for_writing(const fs::path& path) {
  std::ofstream file(path);
  if (!file) throw std::runtime_error(fmt::format("synth: cannot write {}", path.string()));
  return file;
}

// Seconds with exactly nine decimals, without going through a double (1e9 s and ns do not fit in 53 bits).
std::string seconds_string(int64_t ns) { return fmt::format("{}.{:09d}", ns / 1'000'000'000, ns % 1'000'000'000); }

// Shortest round-trip text, always with a decimal point as the EuRoC files write numbers ("1.0", "0.11").
std::string num(double v) {
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

Eigen::Quaterniond canonical(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return q;
}

void write_info(const SynthConfig& c, const fs::path& path) {
  std::ofstream f = open_for_writing(path);
  f << "# vkvo synth: the parameters this sequence was rendered with (vkvo synth --config reads this format)\n";
  f << fmt::format("seed: {}\nframes: {}\nrate_hz: {}\n", c.seed, c.num_frames, c.rate_hz);
  f << fmt::format("width: {}\nheight: {}\nfx: {}\nfy: {}\ncx: {}\ncy: {}\nbaseline: {}\n", c.rig.width, c.rig.height,
                   c.rig.fx, c.rig.fy, c.rig.cx, c.rig.cy, c.rig.baseline);
  const TrajectoryParams& t = c.trajectory;
  f << fmt::format(
      "speed: {}\nyaw_rate_deg: {}\nyaw_sway_deg: {}\npitch_deg: {}\npitch_sway_deg: {}\n"
      "roll_sway_deg: {}\nstart_yaw_deg: {}\n",
      t.speed, t.yaw_rate_deg, t.yaw_sway_deg, t.pitch_deg, t.pitch_sway_deg, t.roll_sway_deg, t.start_yaw_deg);
  f << fmt::format("num_boxes: {}\ntexels_per_meter: {}\nposters_per_wall: {}\nplain_surfaces: {}\n", c.scene.num_boxes,
                   c.scene.texels_per_meter, c.scene.posters_per_wall, c.scene.plain_surfaces);
  const SensorParams& s = c.sensor;
  f << fmt::format(
      "exposure: {}\nread_noise: {}\nshot_noise: {}\nmotion_blur: {}\nexposure_time: {}\n"
      "blur_samples: {}\n",
      s.exposure, s.read_noise, s.shot_noise, s.motion_blur, s.exposure_time, s.blur_samples);
  f << "events:\n";
  for (const auto& e : c.events) f << "  - \"" << to_string(e) << "\"\n";
  if (c.events.empty()) f << "  []\n";
}

// The scene's geometry (every surface is a face of one of these axis-aligned boxes), so a map can be checked
// against it: a landmark's distance to the nearest face is its error.
void write_scene_boxes(const Scene& scene, const fs::path& path) {
  std::ofstream f = open_for_writing(path);
  f << "# kind,min_x,min_y,min_z,max_x,max_y,max_z (metres, world frame; the room is seen from inside)\n";
  const auto row = [&f](const char* kind, const Eigen::AlignedBox3f& b) {
    f << fmt::format("{},{},{},{},{},{},{}\n", kind, b.min().x(), b.min().y(), b.min().z(), b.max().x(), b.max().y(),
                     b.max().z());
  };
  row("room", scene.room);
  for (const Box& box : scene.boxes) row("box", box.bounds);
  if (!f.flush()) throw std::runtime_error(fmt::format("synth: cannot write {}", path.string()));
}

}  // namespace

std::string euroc_sensor_yaml(const io::CameraCalibration& cam, double rate_hz, const std::string& comment) {
  const Eigen::Matrix4d T = cam.T_body_camera.matrix();
  std::string rows;
  for (int r = 0; r < 4; ++r) {
    rows += r == 0 ? "  data: [" : "         ";
    rows += fmt::format("{}, {}, {}, {}", num(T(r, 0)), num(T(r, 1)), num(T(r, 2)), num(T(r, 3)));
    rows += r == 3 ? "]\n" : ",\n";
  }
  std::string coeffs = "[0.0, 0.0, 0.0, 0.0]";
  if (!cam.distortion_coeffs.empty()) {
    coeffs = "[";
    for (size_t i = 0; i < cam.distortion_coeffs.size(); ++i)
      coeffs += fmt::format("{}{}", i ? ", " : "", num(cam.distortion_coeffs[i]));
    coeffs += "]";
  }
  const std::string rate =
      rate_hz == std::floor(rate_hz) ? fmt::format("{}", static_cast<int64_t>(rate_hz)) : fmt::format("{}", rate_hz);
  return fmt::format(
      "# General sensor definitions.\n"
      "sensor_type: camera\n"
      "comment: {}\n"
      "\n"
      "# Sensor extrinsics wrt. the body-frame.\n"
      "T_BS:\n"
      "  cols: 4\n"
      "  rows: 4\n"
      "{}"
      "\n"
      "# Camera specific definitions.\n"
      "rate_hz: {}\n"
      "resolution: [{}, {}]\n"
      "camera_model: pinhole\n"
      "intrinsics: [{}, {}, {}, {}] #fu, fv, cu, cv\n"
      "distortion_model: radial-tangential\n"
      "distortion_coefficients: {}\n",
      comment, rows, rate, cam.width, cam.height, num(cam.fx), num(cam.fy), num(cam.cx), num(cam.cy), coeffs);
}

void write_asl_sequence(const StereoRenderer& renderer, const fs::path& out_dir, const ProgressCallback& progress) {
  const SynthConfig& config = renderer.config();
  const fs::path mav0 = out_dir / "mav0";
  const io::StereoCalibration calib = renderer.calibration();
  const io::CameraCalibration* cams[2] = {&calib.left, &calib.right};
  std::ofstream csv[2];
  for (int c = 0; c < 2; ++c) {
    const fs::path dir = mav0 / fmt::format("cam{}", c);
    fs::create_directories(dir / "data");
    open_for_writing(dir / "sensor.yaml")
        << euroc_sensor_yaml(*cams[c], config.rate_hz, fmt::format("vkvo synthetic cam{} (rectified pinhole)", c));
    csv[c] = open_for_writing(dir / "data.csv");
    csv[c] << "#timestamp [ns],filename\n";
  }
  const fs::path gt_dir = mav0 / "state_groundtruth_estimate0";
  fs::create_directories(gt_dir);
  std::ofstream gt = open_for_writing(gt_dir / "data.csv");
  gt << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
        "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
        "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  std::ofstream tum = open_for_writing(out_dir / "groundtruth_tum.txt");
  tum << "# timestamp tx ty tz qx qy qz qw (cam0 in world; vkvo synth)\n";
  write_info(config, out_dir / "synth.yaml");
  write_scene_boxes(renderer.scene(), out_dir / "scene_boxes.csv");

  for (int k = 0; k < renderer.frame_count(); ++k) {
    const StereoFrame frame = renderer.render(k);
    const std::string name = fmt::format("{}.png", frame.timestamp_ns);
    const cv::Mat* images[2] = {&frame.left, &frame.right};
    for (int c = 0; c < 2; ++c) {
      const fs::path file = mav0 / fmt::format("cam{}", c) / "data" / name;
      if (!cv::imwrite(file.string(), *images[c]))
        throw std::runtime_error(fmt::format("synth: cannot write {}", file.string()));
      csv[c] << frame.timestamp_ns << ',' << name << '\n';
    }
    const Eigen::Vector3d p = frame.T_world_cam0.translation();
    const Eigen::Quaterniond q = canonical(frame.T_world_cam0.linear());
    const Eigen::Vector3d v = renderer.velocity(k);
    gt << fmt::format("{},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},0,0,0,0,0,0\n",
                      frame.timestamp_ns, p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z());
    tum << fmt::format("{} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", seconds_string(frame.timestamp_ns),
                       p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
    if (progress) progress(k + 1, renderer.frame_count());
  }
  for (auto& f : csv)
    if (!f.flush()) throw std::runtime_error("synth: writing data.csv failed");
  if (!gt.flush() || !tum.flush()) throw std::runtime_error("synth: writing the ground truth failed");
}

void write_synthetic_sequence(const SynthConfig& config, const fs::path& out_dir, const ProgressCallback& progress) {
  validate_synth_config(config);
  write_asl_sequence(StereoRenderer(config), out_dir, progress);
}

}  // namespace vkvo::synth
