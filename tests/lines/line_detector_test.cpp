// Line detection on synthetic images with known straight edges (rendered with OpenCV): the edges are found with
// FastLineDetector and LSD, a line split by occluders is merged back into one, short clutter is filtered; and the
// YAML loader.
#include <random>

#include <opencv2/imgproc.hpp>

#include "common/test_support.hpp"
#include "features/lines/line_detector.hpp"

namespace vkvo::features {
namespace {

constexpr int kWidth = 752, kHeight = 480;

// Tolerances: a detected segment represents a true edge when both its endpoints lie within kOnLine px of the
// edge's supporting line and it covers at least kCoverage of the edge's length. FLD fits Canny edge pixels of the
// half-size image, i.e. positions quantised to 2 full-resolution px, and a step edge sits on a pixel boundary;
// endpoints of long merged segments (extrapolated fits) can be off by up to ~2.7 px.
constexpr float kOnLine = 3.0f;
constexpr float kCoverage = 0.9f;

// Length of the part of `truth` covered by `s` (projection overlap), or 0 when s is not on truth's line.
float covered_length(const LineSegment& s, const LineSegment& truth) {
  if (truth.distance_to_line(s.p0) > kOnLine || truth.distance_to_line(s.p1) > kOnLine) return 0.0f;
  const Eigen::Vector2f d = truth.direction();
  const float t0 = (s.p0 - truth.p0).dot(d), t1 = (s.p1 - truth.p0).dot(d);
  return std::max(0.0f, std::min(std::max(t0, t1), truth.length()) - std::max(std::min(t0, t1), 0.0f));
}

bool found(const std::vector<LineSegment>& detected, const LineSegment& truth) {
  for (const LineSegment& s : detected)
    if (covered_length(s, truth) >= kCoverage * truth.length()) return true;
  return false;
}

// Every detected segment must lie on one of the true edges (nothing spurious survives).
void expect_all_on_truth(const std::vector<LineSegment>& detected, const std::vector<LineSegment>& truths) {
  for (const LineSegment& s : detected) {
    bool on_truth = false;
    for (const LineSegment& t : truths) on_truth = on_truth || covered_length(s, t) > 0.0f;
    EXPECT_TRUE(on_truth) << "spurious segment (" << s.p0.transpose() << ") - (" << s.p1.transpose() << ")";
  }
}

// A bright convex quadrilateral on a dark, lightly textured background. Pixel (i, j) covers [i-0.5, i+0.5], so
// the polygon drawn through vertex coordinates v has its edges on the lines through v.
cv::Mat render_quad(const std::vector<cv::Point2f>& quad, uint64_t seed) {
  cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(60));
  cv::Mat noise(kHeight, kWidth, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0, 2);
  image += noise;
  std::vector<cv::Point> fixed;
  for (const auto& v : quad) fixed.emplace_back(cvRound(v.x * 16), cvRound(v.y * 16));
  cv::fillConvexPoly(image, fixed, cv::Scalar(190), cv::LINE_AA, 4);
  return image;
}

std::vector<LineSegment> quad_edges(const std::vector<cv::Point2f>& quad) {
  std::vector<LineSegment> edges;
  for (size_t i = 0; i < quad.size(); ++i) {
    const cv::Point2f a = quad[i], b = quad[(i + 1) % quad.size()];
    edges.push_back({{a.x, a.y}, {b.x, b.y}});
  }
  return edges;
}

const std::vector<cv::Point2f> kQuad = {{120.3f, 90.7f}, {610.2f, 60.4f}, {650.8f, 400.1f}, {90.6f, 370.9f}};

TEST(LineDetector, FindsTheEdgesOfAQuadrilateralWithFld) {
  const LineDetector detector{LineDetectorParams{}};
  const auto detected = detector.detect(render_quad(kQuad, 1));
  const auto edges = quad_edges(kQuad);
  for (const auto& e : edges) EXPECT_TRUE(found(detected, e)) << "edge " << e.p0.transpose() << " missing";
  expect_all_on_truth(detected, edges);
  EXPECT_EQ(detected.size(), edges.size());
}

// The quadrilateral at 5 % of the light: its edges step by 6.5 grey levels, below the Canny thresholds (50 on the
// Sobel response, 4 x the step). Stretched to the minimum contrast it gives the same four edges; without the
// stretch, none. A well-exposed image (130 levels from 1st to 99th percentile) is left as it is.
TEST(LineDetector, ADimImageIsStretchedToKeepItsEdges) {
  const cv::Mat bright = render_quad(kQuad, 1);
  cv::Mat dim;
  bright.convertTo(dim, CV_8U, 0.05);
  const auto edges = quad_edges(kQuad);
  const LineDetector detector{LineDetectorParams{}};
  const auto detected = detector.detect(dim);
  for (const auto& e : edges) EXPECT_TRUE(found(detected, e)) << "edge " << e.p0.transpose() << " missing";
  expect_all_on_truth(detected, edges);
  EXPECT_EQ(detected.size(), edges.size());

  LineDetectorParams unstretched;
  unstretched.min_contrast = 0.0f;
  EXPECT_TRUE(LineDetector(unstretched).detect(dim).empty());
  const auto as_is = LineDetector(unstretched).detect(bright), stretched = detector.detect(bright);
  ASSERT_EQ(as_is.size(), stretched.size());
  for (std::size_t i = 0; i < as_is.size(); ++i) {
    EXPECT_EQ(as_is[i].p0, stretched[i].p0);
    EXPECT_EQ(as_is[i].p1, stretched[i].p1);
  }
}

TEST(LineDetector, FindsTheEdgesOfAQuadrilateralWithLsdAtFullResolution) {
  LineDetectorParams params;
  params.method = LineDetectorMethod::kLsd;
  params.scale = 1.0f;
  const auto detected = LineDetector(params).detect(render_quad(kQuad, 2));
  const auto edges = quad_edges(kQuad);
  for (const auto& e : edges) EXPECT_TRUE(found(detected, e)) << "edge " << e.p0.transpose() << " missing";
  expect_all_on_truth(detected, edges);
}

TEST(LineDetector, DownscaledCoordinatesMapBackToFullResolution) {
  // The same image at scale 1 and 0.5: the long edges agree within 1 px (pixel-centre mapping, not a plain x2).
  LineDetectorParams full;
  full.scale = 1.0f;
  const cv::Mat image = render_quad(kQuad, 3);
  const auto a = LineDetector(full).detect(image);
  const auto b = LineDetector(LineDetectorParams{}).detect(image);
  for (const auto& e : quad_edges(kQuad)) {
    for (const auto* set : {&a, &b}) {
      float best = 1e9f;
      for (const auto& s : *set)
        if (covered_length(s, e) > 0.5f * e.length())
          best = std::min(best, 0.5f * (e.distance_to_line(s.p0) + e.distance_to_line(s.p1)));
      EXPECT_LT(best, 1.0f) << "edge " << e.p0.transpose();
    }
  }
}

TEST(LineDetector, LineSplitByOccludersIsMergedBackIntoOne) {
  // A long oblique step edge across the whole image (the bright half-plane's other sides lie outside the image),
  // crossed by five blobs of intermediate grey that cut it into pieces.
  cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(50));
  const cv::Point2f a(60.2f, 400.6f), b(700.4f, 110.3f);
  const cv::Point2f d = (b - a) / cv::norm(b - a), n(-d.y, d.x);
  auto fixed = [](const cv::Point2f& p) { return cv::Point(cvRound(p.x * 16), cvRound(p.y * 16)); };
  const std::vector<cv::Point> half = {fixed(a - 2000 * d), fixed(b + 2000 * d), fixed(b + 2000 * d + 3000 * n),
                                       fixed(a - 2000 * d + 3000 * n)};
  cv::fillConvexPoly(image, half, cv::Scalar(200), cv::LINE_AA, 4);
  const float length = static_cast<float>(cv::norm(b - a));
  for (float t : {0.15f, 0.33f, 0.5f, 0.68f, 0.85f})
    cv::circle(image, a + t * length * d, 9, cv::Scalar(120), cv::FILLED, cv::LINE_AA);
  // The visible edge runs from x = 0 to x = 751 (it stays inside the rows there).
  auto y_at = [&](float x) { return a.y + (x - a.x) * d.y / d.x; };
  const LineSegment truth{{0.0f, y_at(0.0f)}, {751.0f, y_at(751.0f)}};

  LineDetectorParams params;
  const LineDetector detector(params);
  int raw_pieces = 0;
  for (const auto& s : detector.detect_raw(image)) raw_pieces += covered_length(s, truth) > 0.0f;
  EXPECT_GE(raw_pieces, 5) << "the occluders should split the raw detection";

  const auto detected = detector.detect(image);
  int on_truth = 0;
  for (const auto& s : detected) {
    if (covered_length(s, truth) <= 0.0f) continue;
    ++on_truth;
    EXPECT_GE(covered_length(s, truth), 0.95f * truth.length());
  }
  EXPECT_EQ(on_truth, 1);
  // The occluders' own round outlines are short curved clutter: nothing else survives.
  EXPECT_EQ(detected.size(), 1u);
}

TEST(LineDetector, ShortClutterIsFiltered) {
  // Two long edges plus 150 random short strokes (8..35 px) in between.
  cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(40));
  cv::rectangle(image, cv::Point(0, 300), cv::Point(kWidth - 1, kHeight - 1), cv::Scalar(180), cv::FILLED);
  cv::rectangle(image, cv::Point(500, 0), cv::Point(kWidth - 1, 299), cv::Scalar(120), cv::FILLED);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ux(20, 460), uy(20, 270), ua(0, 3.1416f), ul(8, 35);
  for (int k = 0; k < 150; ++k) {
    const cv::Point2f p(ux(rng), uy(rng));
    const float angle = ua(rng), len = ul(rng);
    cv::line(image, p, p + len * cv::Point2f(std::cos(angle), std::sin(angle)), cv::Scalar(90 + k % 100), 2,
             cv::LINE_AA);
  }
  // Edges on the pixel boundaries: y = 299.5 (x from 0 to 500) and x = 499.5 (y from 0 to 299.5) and the lower
  // boundary to its right.
  const std::vector<LineSegment> truths = {{{0, 299.5f}, {751, 299.5f}}, {{499.5f, 0}, {499.5f, 299.5f}}};
  const LineDetector detector{LineDetectorParams{}};
  size_t raw_short = 0;
  for (const auto& s : detector.detect_raw(image)) raw_short += s.length() < 40.0f;
  EXPECT_GT(raw_short, 50u) << "the clutter should produce many raw segments";

  const auto detected = detector.detect(image);
  for (const auto& s : detected) EXPECT_GE(s.length(), LineDetectorParams{}.min_length);
  expect_all_on_truth(detected, truths);
  EXPECT_TRUE(found(detected, truths[1]));
  float horizontal_cover = 0.0f;
  for (const auto& s : detected) horizontal_cover += covered_length(s, truths[0]);
  EXPECT_GE(horizontal_cover, 0.9f * truths[0].length());
}

TEST(LineDetector, AcceptsBgrAndRejectsOtherTypes) {
  cv::Mat bgr;
  cv::cvtColor(render_quad(kQuad, 4), bgr, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(LineDetector(LineDetectorParams{}).detect(bgr).size(), 4u);
  EXPECT_THROW(LineDetector(LineDetectorParams{}).detect(cv::Mat(10, 10, CV_32FC1)), std::runtime_error);
  EXPECT_THROW(LineDetector(LineDetectorParams{}).detect(cv::Mat()), std::runtime_error);
}

TEST(LineParams, YamlKeysOverrideDefaultsAndWrongTypesThrow) {
  const YAML::Node config = YAML::Load(R"(
detector:
  method: lsd
  scale: 1.0
  min_length: 40
  min_contrast: 64
  fld: {length_threshold: 10, canny_aperture: 5}
  lsd: {refine: none}
  merge_stages:
    - {max_angle: 0.02, max_midpoint_distance: 2, max_endpoint_gap: 30, min_length_after: 12}
association: {max_distance: 2.5, require_both_extents: false}
matching: {score_threshold: 0.7, shared_threshold: 2}
stereo_matching: {by_appearance: false, min_rows: 20, min_row_overlap: 0.7, min_zncc: 0.9, min_margin: 0.2, half_width: 4}
keyframe_matching: {by_appearance: false, min_overlap: 0.3, min_zncc: 0.7, min_margin: 0.15, half_width: 2}
)");
  const LinePipelineParams p = load_line_pipeline_params(config);
  EXPECT_EQ(p.detector.method, LineDetectorMethod::kLsd);
  EXPECT_FLOAT_EQ(p.detector.scale, 1.0f);
  EXPECT_FLOAT_EQ(p.detector.min_length, 40.0f);
  EXPECT_FLOAT_EQ(p.detector.min_contrast, 64.0f);
  EXPECT_EQ(p.detector.fld.length_threshold, 10);
  EXPECT_EQ(p.detector.fld.canny_aperture, 5);
  EXPECT_FLOAT_EQ(p.detector.fld.distance_threshold, 1.414f);  // untouched default
  EXPECT_EQ(p.detector.lsd.refine, LsdParams::Refine::kNone);
  ASSERT_EQ(p.detector.merge_stages.size(), 1u);
  EXPECT_FLOAT_EQ(p.detector.merge_stages[0].merge.max_endpoint_gap, 30.0f);
  EXPECT_FLOAT_EQ(p.detector.merge_stages[0].min_length_after, 12.0f);
  EXPECT_FLOAT_EQ(p.association.max_distance, 2.5f);
  EXPECT_FLOAT_EQ(p.association.extent_margin, 3.0f);
  EXPECT_FALSE(p.association.require_both_extents);
  EXPECT_FLOAT_EQ(p.matching.score_threshold, 0.7f);
  EXPECT_EQ(p.matching.shared_threshold, 2);
  EXPECT_FALSE(p.stereo_matching.by_appearance);
  EXPECT_FLOAT_EQ(p.stereo_matching.min_rows, 20.0f);
  EXPECT_FLOAT_EQ(p.stereo_matching.min_row_overlap, 0.7f);
  EXPECT_FLOAT_EQ(p.stereo_matching.min_zncc, 0.9f);
  EXPECT_FLOAT_EQ(p.stereo_matching.min_margin, 0.2f);
  EXPECT_EQ(p.stereo_matching.half_width, 4);
  EXPECT_FALSE(p.keyframe_matching.by_appearance);
  EXPECT_FLOAT_EQ(p.keyframe_matching.min_overlap, 0.3f);
  EXPECT_FLOAT_EQ(p.keyframe_matching.min_zncc, 0.7f);
  EXPECT_FLOAT_EQ(p.keyframe_matching.min_margin, 0.15f);
  EXPECT_EQ(p.keyframe_matching.half_width, 2);

  const LinePipelineParams defaults = load_line_pipeline_params(YAML::Node());
  EXPECT_EQ(defaults.detector.merge_stages.size(), 2u);
  EXPECT_EQ(defaults.detector.method, LineDetectorMethod::kFastLineDetector);

  auto message_of = [](const char* text) {
    try {
      load_line_pipeline_params(YAML::Load(text));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message_of("detector: {scale: fast}").find("'scale'"), std::string::npos);
  EXPECT_NE(message_of("detector: {scale: 2.0}").find("detector.scale"), std::string::npos);
  EXPECT_NE(message_of("detector: {min_contrast: 300}").find("detector.min_contrast"), std::string::npos);
  EXPECT_NE(message_of("detector: {method: hough}").find("detector.method"), std::string::npos);
  EXPECT_NE(message_of("matching: {shared_threshold: [1]}").find("'shared_threshold'"), std::string::npos);
  EXPECT_NE(message_of("detector: {merge_stages: [{max_angle: x}]}").find("'max_angle'"), std::string::npos);
  EXPECT_NE(message_of("detector: {merge_stages: {max_angle: 1}}").find("merge_stages"), std::string::npos);
  EXPECT_NE(message_of("stereo_matching: {min_zncc: 1.5}").find("stereo_matching.min_zncc"), std::string::npos);
  EXPECT_NE(message_of("stereo_matching: {min_row_overlap: 0}").find("stereo_matching.min_row_overlap"),
            std::string::npos);
  EXPECT_NE(message_of("stereo_matching: {half_width: 0}").find("stereo_matching.half_width"), std::string::npos);
  EXPECT_NE(message_of("stereo_matching: [1]").find("stereo_matching"), std::string::npos);
  EXPECT_NE(message_of("keyframe_matching: {min_overlap: 1.5}").find("keyframe_matching.min_overlap"),
            std::string::npos);
  EXPECT_NE(message_of("keyframe_matching: {min_zncc: -2}").find("keyframe_matching.min_zncc"), std::string::npos);
  EXPECT_NE(message_of("keyframe_matching: {min_margin: -1}").find("keyframe_matching.min_margin"), std::string::npos);
  EXPECT_NE(message_of("keyframe_matching: 3").find("keyframe_matching"), std::string::npos);
}

TEST(LineParams, ExampleConfigFileStatesTheDefaults) {
  const auto file = test::source_dir() / "config" / "lines.yaml";
  ASSERT_TRUE(std::filesystem::exists(file)) << file;
  const LinePipelineParams loaded = load_line_pipeline_params(YAML::LoadFile(file.string())["lines"]);
  const LinePipelineParams defaults;
  EXPECT_EQ(loaded.detector.method, defaults.detector.method);
  EXPECT_FLOAT_EQ(loaded.detector.scale, defaults.detector.scale);
  EXPECT_EQ(loaded.detector.fld.length_threshold, defaults.detector.fld.length_threshold);
  EXPECT_FLOAT_EQ(loaded.detector.fld.distance_threshold, defaults.detector.fld.distance_threshold);
  EXPECT_DOUBLE_EQ(loaded.detector.fld.canny_threshold1, defaults.detector.fld.canny_threshold1);
  EXPECT_DOUBLE_EQ(loaded.detector.fld.canny_threshold2, defaults.detector.fld.canny_threshold2);
  EXPECT_EQ(loaded.detector.fld.canny_aperture, defaults.detector.fld.canny_aperture);
  EXPECT_EQ(loaded.detector.lsd.refine, defaults.detector.lsd.refine);
  ASSERT_EQ(loaded.detector.merge_stages.size(), defaults.detector.merge_stages.size());
  for (size_t i = 0; i < loaded.detector.merge_stages.size(); ++i) {
    const MergeStage& l = loaded.detector.merge_stages[i];
    const MergeStage& d = defaults.detector.merge_stages[i];
    EXPECT_FLOAT_EQ(l.merge.max_angle, d.merge.max_angle);
    EXPECT_FLOAT_EQ(l.merge.max_midpoint_distance, d.merge.max_midpoint_distance);
    EXPECT_FLOAT_EQ(l.merge.max_endpoint_gap, d.merge.max_endpoint_gap);
    EXPECT_FLOAT_EQ(l.min_length_after, d.min_length_after);
  }
  EXPECT_FLOAT_EQ(loaded.detector.min_length, defaults.detector.min_length);
  EXPECT_FLOAT_EQ(loaded.detector.min_contrast, defaults.detector.min_contrast);
  EXPECT_FLOAT_EQ(loaded.association.max_distance, defaults.association.max_distance);
  EXPECT_FLOAT_EQ(loaded.association.extent_margin, defaults.association.extent_margin);
  EXPECT_EQ(loaded.association.require_both_extents, defaults.association.require_both_extents);
  EXPECT_FLOAT_EQ(loaded.association.grid_cell_size, defaults.association.grid_cell_size);
  EXPECT_FLOAT_EQ(loaded.matching.score_threshold, defaults.matching.score_threshold);
  EXPECT_EQ(loaded.matching.shared_threshold, defaults.matching.shared_threshold);
  EXPECT_EQ(loaded.stereo_matching.by_appearance, defaults.stereo_matching.by_appearance);
  EXPECT_FLOAT_EQ(loaded.stereo_matching.min_rows, defaults.stereo_matching.min_rows);
  EXPECT_FLOAT_EQ(loaded.stereo_matching.min_row_overlap, defaults.stereo_matching.min_row_overlap);
  EXPECT_FLOAT_EQ(loaded.stereo_matching.min_zncc, defaults.stereo_matching.min_zncc);
  EXPECT_FLOAT_EQ(loaded.stereo_matching.min_margin, defaults.stereo_matching.min_margin);
  EXPECT_EQ(loaded.stereo_matching.half_width, defaults.stereo_matching.half_width);
  EXPECT_EQ(loaded.keyframe_matching.by_appearance, defaults.keyframe_matching.by_appearance);
  EXPECT_FLOAT_EQ(loaded.keyframe_matching.min_overlap, defaults.keyframe_matching.min_overlap);
  EXPECT_FLOAT_EQ(loaded.keyframe_matching.min_zncc, defaults.keyframe_matching.min_zncc);
  EXPECT_FLOAT_EQ(loaded.keyframe_matching.min_margin, defaults.keyframe_matching.min_margin);
  EXPECT_EQ(loaded.keyframe_matching.half_width, defaults.keyframe_matching.half_width);
}

}  // namespace
}  // namespace vkvo::features
