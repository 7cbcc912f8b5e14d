// Dataset readers on small synthetic EuRoC and KITTI folders written by the tests themselves.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_support.hpp"
#include "io/config.hpp"
#include "io/dataset.hpp"

namespace fs = std::filesystem;
using namespace vkvo;

using test::error_of;
using test::write_text;

namespace {

// A 16x12 image whose pixels encode `seed`, so a test can tell which file was loaded.
cv::Mat pattern_image(int seed, int width = 16, int height = 12) {
  cv::Mat image(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((seed * 7 + x + 3 * y) % 256);
  return image;
}

std::string euroc_sensor_yaml(const std::string& intrinsics, double tx, bool with_directive = true) {
  std::string text = with_directive ? "%YAML:1.0\n" : "";
  text += "sensor_type: camera\nT_BS:\n  cols: 4\n  rows: 4\n";
  text += "  data: [0.0, -1.0, 0.0, " + std::to_string(tx) + ",\n         1.0, 0.0, 0.0, 0.0,\n";
  text += "         0.0, 0.0, 1.0, 0.0,\n         0.0, 0.0, 0.0, 1.0]\n";
  text += "rate_hz: 20\nresolution: [16, 12]\ncamera_model: pinhole\n";
  if (!intrinsics.empty()) text += "intrinsics: " + intrinsics + " #fu, fv, cu, cv\n";
  text += "distortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 1.7e-05]\n";
  return text;
}

// mav0 with 5 left images (t = 1000..1004 ms) and right images for all but the third.
fs::path write_euroc(const fs::path& base, const std::string& left_intrinsics = "[100.0, 101.0, 8.0, 6.0]") {
  const fs::path mav0 = base / "SEQ_01" / "mav0";
  std::string left_csv = "#timestamp [ns],filename\r\n", right_csv = left_csv;
  for (int k = 0; k < 5; ++k) {
    const std::int64_t t = 1'000'000'000'000LL + k * 50'000'000LL;
    const std::string name = std::to_string(t) + ".png";
    fs::create_directories(mav0 / "cam0" / "data");
    fs::create_directories(mav0 / "cam1" / "data");
    cv::imwrite((mav0 / "cam0" / "data" / name).string(), pattern_image(k));
    left_csv += std::to_string(t) + "," + name + "\r\n";
    if (k == 2) continue;  // a dropped right frame
    cv::imwrite((mav0 / "cam1" / "data" / name).string(), pattern_image(100 + k));
    right_csv += std::to_string(t) + "," + name + "\r\n";
  }
  write_text(mav0 / "cam0" / "data.csv", left_csv);
  write_text(mav0 / "cam1" / "data.csv", right_csv);
  write_text(mav0 / "cam0" / "sensor.yaml", euroc_sensor_yaml(left_intrinsics, -0.02));
  write_text(mav0 / "cam1" / "sensor.yaml", euroc_sensor_yaml("[102.0, 103.0, 7.5, 6.5]", 0.09, false));
  return mav0;
}

const char* kLabelledCalib =
    "P0: 7.0e+02 0 3.0e+02 0 0 7.0e+02 1.5e+02 0 0 0 1 0\n"
    "P1: 7.0e+02 0 3.0e+02 -3.5e+02 0 7.0e+02 1.5e+02 0 0 0 1 0\n"
    "P2: 7.0e+02 0 3.0e+02 4.0e+01 0 7.0e+02 1.5e+02 0 0 0 1 0\n"
    "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";

fs::path write_kitti(const fs::path& base, int frames, const char* calib, bool with_times, bool lr_names = false) {
  const fs::path seq = base / "05";
  const fs::path left = seq / (lr_names ? "image_l" : "image_0");
  const fs::path right = seq / (lr_names ? "image_r" : "image_1");
  fs::create_directories(left);
  fs::create_directories(right);
  std::string times;
  for (int k = 0; k < frames; ++k) {
    const std::string name = fmt::format("{:06d}.png", k);
    cv::imwrite((left / name).string(), pattern_image(k, 20, 10));
    cv::imwrite((right / name).string(), pattern_image(50 + k, 20, 10));
    times += fmt::format("{:e}\n", 0.103 * k + 0.5);
  }
  if (calib) write_text(seq / "calib.txt", calib);
  if (with_times) write_text(seq / "times.txt", times);
  return seq;
}

}  // namespace

TEST(EurocDataset, PairsByTimestampAndParsesSensorYaml) {
  const fs::path mav0 = write_euroc(test::temp_dir("euroc"));
  io::EurocDataset dataset(mav0);
  EXPECT_EQ(dataset.kind(), io::DatasetKind::euroc);
  EXPECT_EQ(dataset.name(), "SEQ_01");
  ASSERT_EQ(dataset.size(), 4u);  // the left image without a partner is dropped
  const std::int64_t t0 = 1'000'000'000'000LL;
  EXPECT_EQ(dataset.frame(0).timestamp_ns, t0);
  EXPECT_EQ(dataset.frame(2).timestamp_ns, t0 + 3 * 50'000'000LL);
  EXPECT_DOUBLE_EQ(dataset.frame(2).timestamp_s, 1000.15);
  EXPECT_EQ(dataset.frame(2).left.filename(), dataset.frame(2).right.filename());

  const auto& left = dataset.calibration().left;
  EXPECT_EQ(left.width, 16);
  EXPECT_EQ(left.height, 12);
  EXPECT_DOUBLE_EQ(left.fx, 100.0);
  EXPECT_DOUBLE_EQ(left.fy, 101.0);
  EXPECT_DOUBLE_EQ(left.cx, 8.0);
  EXPECT_DOUBLE_EQ(left.cy, 6.0);
  EXPECT_EQ(left.distortion, io::DistortionModel::radtan);
  ASSERT_EQ(left.distortion_coeffs.size(), 4u);
  EXPECT_DOUBLE_EQ(left.distortion_coeffs[3], 1.7e-05);
  EXPECT_DOUBLE_EQ(left.T_body_camera(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(left.T_body_camera.translation().x(), -0.02);
  EXPECT_DOUBLE_EQ(dataset.calibration().right.fx, 102.0);
  EXPECT_FALSE(dataset.calibration().rectified);
  EXPECT_NEAR(dataset.calibration().baseline(), 0.11, 1e-12);

  const auto images = dataset.load(2);  // sequence frame 3
  ASSERT_EQ(images.left.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(images.left, pattern_image(3), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(images.right, pattern_image(103), cv::NORM_INF), 0.0);
  EXPECT_FALSE(dataset.groundtruth_path().has_value());
}

TEST(EurocDataset, AcceptsSequenceAndParentFoldersAndFrameRange) {
  const fs::path base = test::temp_dir("euroc_paths");
  const fs::path mav0 = write_euroc(base);
  for (const fs::path& path : {mav0, mav0.parent_path(), base}) {
    const auto dataset = io::open_dataset(path);
    EXPECT_EQ(dataset->kind(), io::DatasetKind::euroc) << path;
    EXPECT_EQ(dataset->root(), mav0) << path;
    EXPECT_EQ(dataset->size(), 4u) << path;
  }
  io::DatasetOptions options;
  options.range = {1, 3, 2};
  io::EurocDataset ranged(mav0, options);
  ASSERT_EQ(ranged.size(), 2u);
  EXPECT_EQ(ranged.frame(0).sequence_index, 1u);
  EXPECT_EQ(ranged.frame(1).sequence_index, 3u);
  options.range = {7, std::nullopt, 1};
  EXPECT_NE(error_of([&] { io::EurocDataset(mav0, options); }).find("selects no frames"), std::string::npos);
}

TEST(EurocDataset, MissingCalibrationFieldNamesFileAndField) {
  const fs::path mav0 = write_euroc(test::temp_dir("euroc_missing"), /*left_intrinsics=*/"");
  const std::string message = error_of([&] { io::EurocDataset dataset(mav0); });
  EXPECT_NE(message.find((mav0 / "cam0" / "sensor.yaml").string()), std::string::npos) << message;
  EXPECT_NE(message.find("'intrinsics'"), std::string::npos) << message;
}

// AirVO's layout, as bag extraction leaves OIVIO and UMA-VI: cam0/data and cam1/data with images named by their
// nanosecond timestamps, no data.csv, no sensor.yaml; the calibration comes from the config's camera section.
TEST(EurocDataset, ImagesNamedByTimestampWithCamerasFromTheConfig) {
  const fs::path root = write_euroc(test::temp_dir("euroc_bare"));
  for (const char* cam : {"cam0", "cam1"}) {
    fs::remove(root / cam / "data.csv");
    fs::remove(root / cam / "sensor.yaml");
  }
  write_text(root / "cam0" / "data" / "notes.txt", "not an image, ignored");

  // Without a camera section the missing calibration is named, with the way out.
  std::string message = error_of([&] { io::EurocDataset dataset(root); });
  EXPECT_NE(message.find((root / "cam0" / "sensor.yaml").string()), std::string::npos) << message;
  EXPECT_NE(message.find("camera section"), std::string::npos) << message;

  io::DatasetOptions options;
  options.camera_overrides = YAML::Load(
      "{fx: 100, fy: 101, cx: 8, cy: 6,"
      " left: {distortion_model: radtan, distortion_coeffs: [-0.1, 0.01, 0, 0]},"
      " right: {T_body_camera: [1, 0, 0, 0.11,  0, 1, 0, 0,  0, 0, 1, 0]}}");
  io::EurocDataset dataset(root.parent_path(), options);  // the sequence folder finds it too
  ASSERT_EQ(dataset.size(), 4u);  // paired by the timestamps in the names; the unpaired left image is dropped
  EXPECT_EQ(dataset.frame(2).timestamp_ns, 1'000'000'000'000LL + 3 * 50'000'000LL);
  EXPECT_EQ(dataset.frame(2).left.filename(), dataset.frame(2).right.filename());
  EXPECT_EQ(cv::norm(dataset.load_left(2), pattern_image(3), cv::NORM_INF), 0.0);
  const auto& calibration = dataset.calibration();
  EXPECT_EQ(calibration.left.width, 16);  // from the first image
  EXPECT_EQ(calibration.right.height, 12);
  EXPECT_DOUBLE_EQ(calibration.right.fy, 101.0);
  EXPECT_EQ(calibration.left.distortion, io::DistortionModel::radtan);
  EXPECT_NEAR(calibration.baseline(), 0.11, 1e-12);

  // An image whose name is not a timestamp is named, with what the reader expected.
  const fs::path stray = root / "cam1" / "data" / "frame_0001.png";
  cv::imwrite(stray.string(), pattern_image(9));
  message = error_of([&] { io::EurocDataset dataset(root, options); });
  EXPECT_NE(message.find(stray.string()), std::string::npos) << message;
  EXPECT_NE(message.find("timestamp in nanoseconds"), std::string::npos) << message;
  fs::remove(stray);

  // A camera section that leaves a field out still fails validation, naming the field.
  options.camera_overrides = YAML::Load("{fx: 100, fy: 101, cx: 8}");
  message = error_of([&] { io::EurocDataset dataset(root, options); });
  EXPECT_NE(message.find("'cy'"), std::string::npos) << message;
  EXPECT_NE(message.find("cam0 missing"), std::string::npos) << message;
}

TEST(EurocDataset, EmptyCameraFolderIsNamed) {
  const fs::path root = test::temp_dir("euroc_empty");
  fs::create_directories(root / "cam0" / "data");
  fs::create_directories(root / "cam1" / "data");
  const std::string message = error_of([&] { io::open_dataset(root); });
  EXPECT_NE(message.find("no images"), std::string::npos) << message;
  EXPECT_NE(message.find((root / "cam0").string()), std::string::npos) << message;
}

// A sensor.yaml without intrinsics (or resolution) is enough where the config gives them: its T_BS is kept.
TEST(EurocDataset, PartialSensorYamlCompletedByTheConfig) {
  const fs::path mav0 = write_euroc(test::temp_dir("euroc_partial"), /*left_intrinsics=*/"");
  io::DatasetOptions options;
  options.camera_overrides = YAML::Load("left: {fx: 99, fy: 98, cx: 8.5, cy: 6.5}");
  io::EurocDataset dataset(mav0, options);
  const auto& left = dataset.calibration().left;
  EXPECT_DOUBLE_EQ(left.fx, 99.0);
  EXPECT_DOUBLE_EQ(left.cy, 6.5);
  EXPECT_EQ(left.width, 16);                                      // from the file
  EXPECT_EQ(left.distortion, io::DistortionModel::radtan);        // from the file
  EXPECT_DOUBLE_EQ(left.T_body_camera.translation().x(), -0.02);  // from the file
  EXPECT_NEAR(dataset.calibration().baseline(), 0.11, 1e-12);

  // What neither gives is still named.
  options.camera_overrides = YAML::Load("left: {fx: 99, fy: 98, cx: 8.5}");
  const std::string message = error_of([&] { io::EurocDataset dataset(mav0, options); });
  EXPECT_NE(message.find("'cy'"), std::string::npos) << message;
  EXPECT_NE(message.find("sensor.yaml"), std::string::npos) << message;
}

TEST(EurocDataset, CorruptAndMissingImagesNameTheFile) {
  const fs::path mav0 = write_euroc(test::temp_dir("euroc_corrupt"));
  io::EurocDataset dataset(mav0);
  write_text(dataset.frame(1).left, "this is not a png");
  std::string message = error_of([&] { dataset.load_left(1); });
  EXPECT_NE(message.find(dataset.frame(1).left.string()), std::string::npos) << message;
  EXPECT_NE(message.find("cannot decode"), std::string::npos) << message;

  fs::remove(dataset.frame(0).right);
  message = error_of([&] { dataset.load(0); });
  EXPECT_NE(message.find(dataset.frame(0).right.string()), std::string::npos) << message;
  EXPECT_NE(message.find("missing"), std::string::npos) << message;

  cv::imwrite(dataset.frame(3).left.string(), pattern_image(0, 10, 12));  // wrong size
  message = error_of([&] { dataset.load_left(3); });
  EXPECT_NE(message.find("10x12 but the calibration says 16x12"), std::string::npos) << message;
}

TEST(EurocDataset, ColourAnd16BitImagesBecome8BitGray) {
  const fs::path mav0 = write_euroc(test::temp_dir("euroc_depth"));
  io::EurocDataset dataset(mav0);
  cv::Mat wide;
  pattern_image(0).convertTo(wide, CV_16U, 256.0);
  cv::imwrite(dataset.frame(0).left.string(), wide);
  cv::Mat colour;
  cv::Mat channels[] = {pattern_image(1), pattern_image(1), pattern_image(1)};
  cv::merge(channels, 3, colour);
  cv::imwrite(dataset.frame(1).left.string(), colour);
  const cv::Mat a = dataset.load_left(0), b = dataset.load_left(1);
  ASSERT_EQ(a.type(), CV_8UC1);
  ASSERT_EQ(b.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(a, pattern_image(0), cv::NORM_INF), 0.0);
  EXPECT_LE(cv::norm(b, pattern_image(1), cv::NORM_INF), 1.0);  // BGR->gray weights sum to 1, rounding only
}

TEST(KittiDataset, LabelledCalibTimesAndBaseline) {
  const fs::path seq = write_kitti(test::temp_dir("kitti"), 4, kLabelledCalib, /*with_times=*/true);
  const auto dataset = io::open_dataset(seq.parent_path());
  ASSERT_EQ(dataset->kind(), io::DatasetKind::kitti);
  EXPECT_EQ(dataset->name(), "05");
  ASSERT_EQ(dataset->size(), 4u);
  EXPECT_DOUBLE_EQ(dataset->frame(3).timestamp_s, 0.103 * 3 + 0.5);
  EXPECT_EQ(dataset->frame(3).timestamp_ns, 809'000'000);
  ASSERT_TRUE(dataset->times_path().has_value());
  const auto& calibration = dataset->calibration();
  EXPECT_TRUE(calibration.rectified);
  EXPECT_DOUBLE_EQ(calibration.left.fx, 700.0);
  EXPECT_DOUBLE_EQ(calibration.left.cx, 300.0);
  EXPECT_DOUBLE_EQ(calibration.left.cy, 150.0);
  EXPECT_EQ(calibration.left.width, 20);
  EXPECT_EQ(calibration.left.height, 10);
  EXPECT_DOUBLE_EQ(calibration.baseline(), 0.5);  // 350 / 700
  EXPECT_DOUBLE_EQ(calibration.T_left_right().translation().x(), 0.5);
  EXPECT_EQ(cv::norm(dataset->load_right(2), pattern_image(52, 20, 10), cv::NORM_INF), 0.0);
}

TEST(KittiDataset, UnlabelledCalibAndNominalRate) {
  const std::string calib =
      "7.0e+02 0 3.0e+02 0 0 7.0e+02 1.5e+02 0 0 0 1 0\n"
      "7.0e+02 0 3.0e+02 -2.1e+02 0 7.0e+02 1.5e+02 0 0 0 1 0\n";
  const fs::path seq = write_kitti(test::temp_dir("kitti_bare"), 3, calib.c_str(), false, /*lr_names=*/true);
  io::KittiDataset dataset(seq);
  ASSERT_EQ(dataset.size(), 3u);
  EXPECT_DOUBLE_EQ(dataset.frame(2).timestamp_s, 0.2);
  EXPECT_EQ(dataset.frame(2).timestamp_ns, 200'000'000);
  EXPECT_DOUBLE_EQ(dataset.calibration().baseline(), 0.3);
  EXPECT_FALSE(dataset.times_path().has_value());
}

TEST(KittiDataset, MissingCalibrationNeedsCameraSection) {
  const fs::path seq = write_kitti(test::temp_dir("kitti_nocalib"), 2, nullptr, false);
  const std::string message = error_of([&] { io::KittiDataset dataset(seq); });
  EXPECT_NE(message.find("calib.txt"), std::string::npos) << message;
  EXPECT_NE(message.find("'fx'"), std::string::npos) << message;

  io::DatasetOptions options;
  options.camera_overrides = YAML::Load("{fx: 500, fy: 501, cx: 10, cy: 5, baseline: 0.25}");
  io::KittiDataset dataset(seq, options);
  EXPECT_DOUBLE_EQ(dataset.calibration().right.fy, 501.0);
  EXPECT_DOUBLE_EQ(dataset.calibration().baseline(), 0.25);
  EXPECT_EQ(dataset.calibration().right.width, 20);  // from the images
}

TEST(KittiDataset, MissingProjectionMatrixIsNamed) {
  const fs::path seq = write_kitti(test::temp_dir("kitti_p1"), 2, "P0: 7 0 3 0 0 7 1 0 0 0 1 0\n", false);
  const std::string message = error_of([&] { io::KittiDataset dataset(seq); });
  EXPECT_NE(message.find("missing field 'P1'"), std::string::npos) << message;
  EXPECT_NE(message.find("calib.txt"), std::string::npos) << message;
}

TEST(OpenDataset, RejectsUnknownFolders) {
  const fs::path dir = test::temp_dir("nothing");
  write_text(dir / "readme.txt", "hello");
  EXPECT_NE(error_of([&] { io::open_dataset(dir); }).find("not a recognised dataset"), std::string::npos);
  EXPECT_NE(error_of([&] { io::open_dataset(dir / "absent"); }).find("does not exist"), std::string::npos);
}

// Issue 36: data.csv timestamps must increase and its file names stay inside the dataset folder.
TEST(EurocDataset, DuplicateNegativeAndBackwardTimestampsNameFileAndLine) {
  const auto check = [](const std::string& tag, const std::string& csv, const std::vector<std::string>& fragments) {
    const fs::path mav0 = write_euroc(test::temp_dir(tag));
    write_text(mav0 / "cam0" / "data.csv", csv);
    const std::string message = error_of([&] { io::EurocDataset dataset(mav0); });
    EXPECT_NE(message.find((mav0 / "cam0" / "data.csv").string()), std::string::npos) << message;
    for (const auto& fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
  };
  check("euroc_dup", "#t,f\n100,a.png\n100,b.png\n", {":3:", "duplicate", "line 2"});
  check("euroc_back", "#t,f\n200,a.png\n100,b.png\n", {":3:", "earlier", "line 2"});
  check("euroc_negative", "#t,f\n-5,a.png\n", {":2:", "negative"});
}

TEST(EurocDataset, IndexPathsLeavingTheDatasetAreRejected) {
  for (const std::string& name :
       {std::string("../../etc/passwd"), std::string("/etc/passwd"), std::string("sub/../../x.png")}) {
    const fs::path mav0 = write_euroc(test::temp_dir("euroc_escape"));
    write_text(mav0 / "cam0" / "data.csv", "#t,f\n100," + name + "\n");
    const std::string message = error_of([&] { io::EurocDataset dataset(mav0); });
    EXPECT_NE(message.find("leaves the dataset folder"), std::string::npos) << message;
    EXPECT_NE(message.find(":2:"), std::string::npos) << message;
  }
}

TEST(KittiDataset, NonIncreasingTimesAreRejected) {
  const fs::path seq = write_kitti(test::temp_dir("kitti_times"), 3, kLabelledCalib, true);
  write_text(seq / "times.txt", "0.0\n0.1\n0.1\n");
  const std::string message = error_of([&] { io::open_dataset(seq); });
  EXPECT_NE(message.find("times.txt:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("duplicate"), std::string::npos) << message;
}
