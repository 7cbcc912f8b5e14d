// perturb_sequence: geometry, calibration, ground truth and timestamps stay byte-identical; the pixels of the
// frames an event touches change as the event prescribes, all other images stay byte-identical.
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_support.hpp"
#include "synth/tiny_config.hpp"
#include "tools/synth/perturb.hpp"
#include "tools/synth/sequence_writer.hpp"

namespace vkvo::synth {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> tree(const fs::path& root) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root));
  std::sort(files.begin(), files.end());
  return files;
}

double mean_of(const fs::path& image) { return cv::mean(cv::imread(image.string(), cv::IMREAD_UNCHANGED))[0]; }

TEST(Perturb, AslSequenceKeepsGeometryAndChangesTheEventFrames) {
  const fs::path root = vkvo::test::temp_dir("synth_perturb_asl");
  const fs::path src = root / "src", dst = root / "dst";
  write_synthetic_sequence(testing::tiny_config(4), src);
  perturb_sequence(src, dst, parse_events({"lights_off:1-1", "stereo:0-,gain=0.5"}));

  const auto files = tree(src);
  ASSERT_EQ(files, tree(dst));  // same names: timestamps intact
  const StereoImageLists lists = find_stereo_images(src);
  ASSERT_EQ(lists.layout, SequenceLayout::asl);
  ASSERT_EQ(lists.left.size(), 4u);
  for (const auto& f : files) {
    if (f.extension() != ".png") {
      EXPECT_EQ(test::read_text(src / f), test::read_text(dst / f)) << f;  // CSVs, sensor.yaml, ground truth
    }
  }
  const fs::path l = "mav0/cam0", r = "mav0/cam1";
  for (size_t k = 0; k < 4; ++k) {
    const fs::path left = l / lists.left[k], right = r / lists.right[k];
    if (k == 1) {
      EXPECT_NEAR(mean_of(dst / left), 0.02 * mean_of(src / left), 1.0);
      EXPECT_NEAR(mean_of(dst / right), 0.01 * mean_of(src / right), 1.0);
    } else {
      EXPECT_EQ(test::read_text(src / left), test::read_text(dst / left)) << "untouched frame " << k;
      EXPECT_NEAR(mean_of(dst / right) / mean_of(src / right), 0.5, 0.01);
    }
  }
  EXPECT_THROW(perturb_sequence(src, src / "inside", {}), std::runtime_error);
}

TEST(Perturb, KittiSequenceWithSixteenBitImages) {
  const fs::path root = vkvo::test::temp_dir("synth_perturb_kitti");
  const fs::path src = root / "seq", dst = root / "out";
  fs::create_directories(src / "image_0");
  fs::create_directories(src / "image_1");
  std::ofstream(src / "calib.txt") << "P0: 700 0 600 0 0 700 180 0 0 0 1 0\nP1: 700 0 600 -380 0 700 180 0 0 0 1 0\n";
  std::ofstream(src / "times.txt") << "0.0\n0.1\n0.2\n";
  std::ofstream(src / "poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n1 0 0 0 0 1 0 0 0 0 1 2\n";
  cv::RNG rng(3);
  for (int k = 0; k < 3; ++k)
    for (const char* cam : {"image_0", "image_1"}) {
      cv::Mat image(40, 60, CV_16UC1);
      rng.fill(image, cv::RNG::UNIFORM, 10000, 50000);
      cv::imwrite((src / cam / cv::format("%06d.png", k)).string(), image);
    }
  perturb_sequence(src, dst, parse_events({"dim:0-2"}));
  ASSERT_EQ(tree(src), tree(dst));
  for (const char* f : {"calib.txt", "times.txt", "poses.txt"})
    EXPECT_EQ(test::read_text(src / f), test::read_text(dst / f));
  // Gain 1 at the start: the first image is unchanged.
  EXPECT_EQ(test::read_text(src / "image_0/000000.png"), test::read_text(dst / "image_0/000000.png"));
  const cv::Mat out = cv::imread((dst / "image_1/000002.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(out.type(), CV_16UC1);
  EXPECT_NEAR(mean_of(dst / "image_1/000002.png") / mean_of(src / "image_1/000002.png"), 0.1, 1e-3);
  EXPECT_NEAR(mean_of(dst / "image_0/000001.png") / mean_of(src / "image_0/000001.png"), 0.55, 1e-3);
}

TEST(Perturb, RejectsAFolderThatIsNoSequence) {
  const fs::path root = vkvo::test::temp_dir("synth_perturb_none");
  fs::create_directories(root / "src" / "images");
  EXPECT_THROW(perturb_sequence(root / "src", root / "dst", {}), std::runtime_error);
}

}  // namespace
}  // namespace vkvo::synth
