// `vkvo lines`: runs the line pipeline on one image (detect, optionally associate keypoints) or on a pair
// (detect both, associate, match lines through point matches) and writes a debug overlay.
//   vkvo lines --image A.png [--keypoints-a DIR] --out overlay.png
//   vkvo lines --image A.png --image-b B.png --keypoints-a DIR --keypoints-b DIR --matches matches0.npy --out o.png
// Keypoint folders hold keypoints.npy (N x 2 float32, as written by `vkvo features`); matches0.npy is int32 (N),
// the index in B of each keypoint of A or -1.
#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "app/command.hpp"
#include "features/lines/line_detector.hpp"
#include "features/lines/line_drawing.hpp"
#include "features/lines/line_matching.hpp"
#include "features/lines/point_line_association.hpp"
#include "io/image_io.hpp"
#include "io/npy.hpp"
#include "system/vo_config.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vkvo;

struct LinesOptions {
  std::string image_a, image_b, keypoints_a, keypoints_b, matches, out, config, lines_out;
};

// `location` is a folder holding keypoints.npy or the .npy file itself.
std::vector<Eigen::Vector2f> read_keypoints(const std::string& location) {
  const fs::path path = fs::is_directory(location) ? fs::path(location) / "keypoints.npy" : fs::path(location);
  const io::NpyArray array = io::read_npy(path);
  if (array.shape.size() != 2 || array.shape[1] != 2)
    throw std::runtime_error("keypoints file " + path.string() + ": expected shape (N, 2)");
  const std::vector<float> xy = array.to_floats();
  std::vector<Eigen::Vector2f> points(array.shape[0]);
  for (size_t i = 0; i < points.size(); ++i) points[i] = {xy[2 * i], xy[2 * i + 1]};
  return points;
}

std::vector<features::LineSegment> detect_timed(const features::LineDetector& detector, const cv::Mat& image,
                                                const std::string& name) {
  const auto start = std::chrono::steady_clock::now();
  auto lines = detector.detect(image);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("{}: {} lines ({:.1f} ms)", name, lines.size(), ms);
  return lines;
}

void write_lines_npy(const std::string& path, const std::vector<features::LineSegment>& lines) {
  std::vector<float> values;
  for (const auto& l : lines) values.insert(values.end(), {l.p0.x(), l.p0.y(), l.p1.x(), l.p1.y()});
  io::write_npy(path, {lines.size(), 4}, values.data());
}

void write_image(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write overlay " + path);
  spdlog::info("wrote {}", path);
}

int run_lines(const LinesOptions& o) {
  const features::LinePipelineParams params = system::load_vo_config_or_defaults(o.config).lines;
  const features::LineDetector detector(params.detector);

  features::LineOverlayView a;
  a.image = io::read_gray_image(o.image_a);
  a.lines = detect_timed(detector, a.image, o.image_a);
  if (!o.lines_out.empty()) write_lines_npy(o.lines_out, a.lines);
  features::PointLineAssociation assoc_a;
  if (!o.keypoints_a.empty()) {
    a.points = read_keypoints(o.keypoints_a);
    assoc_a = features::associate_points_to_lines(a.points, a.lines, params.association);
    a.association = &assoc_a;
    size_t on_lines = 0;
    for (const auto& l : assoc_a.lines_of_point) on_lines += !l.empty();
    spdlog::info("{} of {} keypoints lie on lines", on_lines, a.points.size());
  }
  if (o.image_b.empty()) {
    write_image(o.out, features::draw_line_overlay(a));
    return 0;
  }

  if (o.keypoints_a.empty() || o.keypoints_b.empty() || o.matches.empty())
    throw std::runtime_error("a pair needs --keypoints-a, --keypoints-b and --matches");
  features::LineOverlayView b;
  b.image = io::read_gray_image(o.image_b);
  b.lines = detect_timed(detector, b.image, o.image_b);
  b.points = read_keypoints(o.keypoints_b);
  const features::PointLineAssociation assoc_b =
      features::associate_points_to_lines(b.points, b.lines, params.association);
  b.association = &assoc_b;
  const std::vector<int32_t> matches = io::read_npy(o.matches).to_int32s();
  const std::vector<int> point_matches(matches.begin(), matches.end());
  const std::vector<int> line_matches = features::match_lines(assoc_a, assoc_b, point_matches, params.matching);
  size_t matched = 0;
  for (int m : line_matches) matched += m >= 0;
  spdlog::info("{} line matches ({} x {} lines)", matched, a.lines.size(), b.lines.size());
  write_image(o.out, features::draw_line_matches(a, b, line_matches));
  return 0;
}

app::CommandRegistration registration{
    {"lines", "detect, associate and match line segments; write a debug overlay", [](CLI::App& sub) {
       auto o = std::make_shared<LinesOptions>();
       sub.add_option("--image", o->image_a, "image A (8-bit)")->required()->check(CLI::ExistingFile);
       sub.add_option("--image-b", o->image_b, "image B: match lines A -> B")->check(CLI::ExistingFile);
       sub.add_option("--keypoints-a", o->keypoints_a, "folder with keypoints.npy of A (or the file)");
       sub.add_option("--keypoints-b", o->keypoints_b, "folder with keypoints.npy of B (or the file)");
       sub.add_option("--matches", o->matches, "matches0.npy: int32 index in B per keypoint of A, -1 = none");
       sub.add_option("--config", o->config, "YAML file with a `lines:` section")->check(CLI::ExistingFile);
       sub.add_option("--lines-out", o->lines_out, "also write A's lines as .npy (N x 4 float32: x0 y0 x1 y1)");
       sub.add_option("--out", o->out, "overlay PNG")->required();
       return std::function<int()>([o] { return run_lines(*o); });
     }}};

}  // namespace
