#include "fuzz/harnesses.hpp"

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "io/config.hpp"
#include "io/dataset.hpp"
#include "io/image_io.hpp"
#include "io/kalibr_camchain.hpp"
#include "io/model_pack.hpp"
#include "io/npy.hpp"
#include "io/trajectory.hpp"
#include "io/validation.hpp"
#include "tools/convert/convert.hpp"
#include "tools/convert/onnx_graph.hpp"

namespace vkvo::fuzz {
namespace {

namespace fs = std::filesystem;

std::string text_of(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// The file-based parsers read from disk: each process writes its inputs under one scratch folder of its own.
const fs::path& scratch() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("vkvo_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

fs::path write_input(const fs::path& relative, const std::string& content) {
  const fs::path path = scratch() / relative;
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
  return path;
}

// Rejection by exception is the parsers' contract; anything derived from std::exception counts as a clean reject.
template <typename Fn>
void rejecting_is_fine(Fn&& fn) {
  try {
    fn();
  } catch (const std::exception&) {
  }
}

void npy(const std::uint8_t* data, std::size_t size) {
  rejecting_is_fine([&] {
    std::istringstream in(text_of(data, size));
    const io::NpyArray array = io::read_npy(in, "fuzz.npy");
    rejecting_is_fine([&] { array.to_floats(); });
    rejecting_is_fine([&] { array.to_int32s(); });
  });
}

void model_pack(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  for (const auto kind : {io::NetworkKind::superpoint, io::NetworkKind::superglue})
    rejecting_is_fine([&] { io::ModelPack::parse(bytes, kind, "fuzz.vkvopack"); });
}

void onnx_import(const std::uint8_t* data, std::size_t size) {
  onnx::ModelProto model;
  if (!model.ParseFromArray(data, static_cast<int>(size))) return;
  rejecting_is_fine([&] {
    const convert::OnnxGraph graph(std::move(model), "fuzz.onnx");
    convert::convert_graph(graph);
  });
}

void yaml_config(const std::uint8_t* data, std::size_t size) {
  rejecting_is_fine([&] {
    const io::Config config = io::Config::from_string(text_of(data, size), "fuzz.yaml");
    rejecting_is_fine([&] { io::validate_config_values(config); });
    YAML::Node camera = config.section("camera");
    // A Kalibr file named by the input would be read from anywhere on the machine: not what this target tests.
    if (camera.IsMap() && camera["kalibr"]) return;
    rejecting_is_fine([&] {
      const io::StereoCalibration calibration = io::apply_camera_overrides(camera, {});
      io::validate_calibration(calibration, "fuzz.yaml");
    });
    rejecting_is_fine([&] { io::load_dataset_options(config.section("dataset"), camera); });
  });
}

void kalibr_camchain(const std::uint8_t* data, std::size_t size) {
  const fs::path file = write_input("camchain.yaml", text_of(data, size));
  rejecting_is_fine([&] { io::read_kalibr_camchain(file); });
}

void euroc_sensor_yaml(const std::uint8_t* data, std::size_t size) {
  const fs::path file = write_input("sensor.yaml", text_of(data, size));
  rejecting_is_fine([&] { io::read_euroc_camera_yaml(file); });
  rejecting_is_fine([&] { io::read_euroc_camera_yaml(file, io::SensorYamlFields::present_only); });
}

// An EuRoC folder whose cam0 and cam1 data.csv are the input (the images need not exist to index the frames).
void euroc_index(const std::uint8_t* data, std::size_t size) {
  static const char* kSensor =
      "sensor_type: camera\ncamera_model: pinhole\nresolution: [32, 24]\nintrinsics: [30.0, 30.0, 16.0, 12.0]\n"
      "distortion_model: radial-tangential\ndistortion_coefficients: [0.0, 0.0, 0.0, 0.0]\n"
      "T_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, %X, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, "
      "1.0]\n";
  const std::string sensor = kSensor;
  const std::string csv = text_of(data, size);
  write_input("euroc/mav0/cam0/data.csv", csv);
  write_input("euroc/mav0/cam1/data.csv", csv);
  write_input("euroc/mav0/cam0/sensor.yaml", std::string(sensor).replace(sensor.find("%X"), 2, "0.0"));
  write_input("euroc/mav0/cam1/sensor.yaml", std::string(sensor).replace(sensor.find("%X"), 2, "0.1"));
  rejecting_is_fine([&] { io::EurocDataset dataset(scratch() / "euroc" / "mav0"); });
}

void kitti_calib(const std::uint8_t* data, std::size_t size) {
  const fs::path file = write_input("calib.txt", text_of(data, size));
  rejecting_is_fine([&] { io::read_kitti_calib(file); });
}

void kitti_times(const std::uint8_t* data, std::size_t size) {
  const fs::path file = write_input("times.txt", text_of(data, size));
  rejecting_is_fine([&] { io::read_kitti_times(file); });
}

// One input read as each ground-truth format: TUM, EuRoC CSV, KITTI poses, and the automatic detection.
void groundtruth(const std::uint8_t* data, std::size_t size) {
  const fs::path file = write_input("gt/poses.txt", text_of(data, size));
  rejecting_is_fine([&] { io::read_tum(file); });
  rejecting_is_fine([&] { io::read_euroc_csv(file); });
  rejecting_is_fine([&] { io::read_kitti_poses(file); });
  rejecting_is_fine([&] { io::read_groundtruth(file); });
}

void image(const std::uint8_t* data, std::size_t size) {
  const std::vector<unsigned char> bytes(data, data + size);
  rejecting_is_fine([&] { io::decode_gray_image(bytes, "fuzz.png"); });
}

}  // namespace

const std::vector<Harness>& harnesses() {
  static const std::vector<Harness> all = {
      {"npy", npy},
      {"model_pack", model_pack},
      {"onnx", onnx_import},
      {"yaml_config", yaml_config},
      {"kalibr_camchain", kalibr_camchain},
      {"euroc_sensor_yaml", euroc_sensor_yaml},
      {"euroc_index", euroc_index},
      {"kitti_calib", kitti_calib},
      {"kitti_times", kitti_times},
      {"groundtruth", groundtruth},
      {"image", image},
  };
  return all;
}

const Harness* find_harness(std::string_view name) {
  for (const Harness& h : harnesses())
    if (h.name == name) return &h;
  return nullptr;
}

}  // namespace vkvo::fuzz
