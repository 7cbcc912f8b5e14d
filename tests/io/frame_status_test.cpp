// frames.csv: what format_frame_status writes, read_frame_status reads back; malformed files name file and line.
#include "io/frame_status.hpp"

#include <gtest/gtest.h>

#include "common/test_support.hpp"

namespace vkvo::io {
namespace {

TEST(FrameStatus, RoundTripWithQuotedNotes) {
  const auto dir = test::temp_dir("frame_status");
  const std::vector<FrameStatus> written = {{.index = 0,
                                             .timestamp_ns = 1403636584763555584,
                                             .state = "tracked",
                                             .segment = 0,
                                             .keyframe = true,
                                             .point_inliers = 210,
                                             .line_inliers = 7,
                                             .note = "new map segment 0"},
                                            {.index = 1,
                                             .timestamp_ns = -5,
                                             .state = "relocalised",
                                             .segment = 2,
                                             .keyframe = false,
                                             .point_inliers = 40,
                                             .line_inliers = 0,
                                             .note = "relocalised at keyframe 3 (appearance+recency), \"twice\""}};
  std::string text = std::string(kFrameStatusHeader) + "\n";
  for (const auto& s : written) text += format_frame_status(s);
  test::write_text(dir / "frames.csv", text);
  const auto read = read_frame_status(dir / "frames.csv");
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(read[i].index, written[i].index);
    EXPECT_EQ(read[i].timestamp_ns, written[i].timestamp_ns);
    EXPECT_EQ(read[i].state, written[i].state);
    EXPECT_EQ(read[i].segment, written[i].segment);
    EXPECT_EQ(read[i].keyframe, written[i].keyframe);
    EXPECT_EQ(read[i].point_inliers, written[i].point_inliers);
    EXPECT_EQ(read[i].line_inliers, written[i].line_inliers);
    EXPECT_EQ(read[i].note, written[i].note);
  }
}

TEST(FrameStatus, MalformedFilesNameTheFileAndLine) {
  const auto dir = test::temp_dir("frame_status_bad");
  test::write_text(dir / "header.csv", "index,timestamp\n0,1\n");
  EXPECT_NE(
      test::error_of([&] { read_frame_status(dir / "header.csv"); }).find("header.csv:1: not a frame status file"),
      std::string::npos);
  test::write_text(dir / "fields.csv", std::string(kFrameStatusHeader) + "\n0,1,tracked,0,1,5\n");
  EXPECT_NE(test::error_of([&] { read_frame_status(dir / "fields.csv"); }).find("fields.csv:2: expected 8"),
            std::string::npos);
  test::write_text(dir / "number.csv", std::string(kFrameStatusHeader) + "\n0,12x,tracked,0,1,5,0,\n");
  EXPECT_NE(test::error_of([&] { read_frame_status(dir / "number.csv"); }).find("timestamp_ns '12x' is not an integer"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] { read_frame_status(dir / "missing.csv"); }).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace vkvo::io
