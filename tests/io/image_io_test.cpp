// io::read_gray_image and io::check_image_size: clear errors with the size and the limit (issue 36).
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_support.hpp"
#include "io/image_io.hpp"

using namespace vkvo;
using test::error_of;

TEST(ImageIo, TinyImageNamesSizeAndMinimum) {
  const auto dir = test::temp_dir("image_tiny");
  cv::imwrite((dir / "tiny.png").string(), cv::Mat(4, 5, CV_8UC1, cv::Scalar(7)));
  const std::string message = error_of([&] { io::read_gray_image(dir / "tiny.png"); });
  EXPECT_NE(message.find("tiny.png"), std::string::npos) << message;
  EXPECT_NE(message.find("5x4"), std::string::npos) << message;
  EXPECT_NE(message.find("16x16 minimum"), std::string::npos) << message;
}

TEST(ImageIo, HugeSizeNamesTheLimit) {
  const std::string message = error_of([&] { io::check_image_size(cv::Size(20000, 100), "big.png"); });
  EXPECT_NE(message.find("20000x100"), std::string::npos) << message;
  EXPECT_NE(message.find("8192"), std::string::npos) << message;
  EXPECT_NE(error_of([&] { io::check_image_size(cv::Size(8000, 8000), "big.png"); }).find("Mpx"), std::string::npos);
  EXPECT_NO_THROW(io::check_image_size(cv::Size(1241, 376), "kitti.png"));
}

TEST(ImageIo, DirectoryMissingAndCorruptFilesAreNamed) {
  const auto dir = test::temp_dir("image_errors");
  EXPECT_NE(error_of([&] { io::read_gray_image(dir); }).find("is a directory"), std::string::npos);
  EXPECT_NE(error_of([&] { io::read_gray_image(dir / "absent.png"); }).find("missing"), std::string::npos);
  test::write_text(dir / "corrupt.png", "\x89PNG\r\n\x1a\nnot really");
  EXPECT_NE(error_of([&] { io::read_gray_image(dir / "corrupt.png"); }).find("cannot decode"), std::string::npos);
}

TEST(ImageIo, ColourAnd16BitBecome8BitGray) {
  cv::Mat colour(20, 30, CV_16UC3, cv::Scalar(256 * 10, 256 * 10, 256 * 10));
  std::vector<unsigned char> png;
  cv::imencode(".png", colour, png);
  const cv::Mat gray = io::decode_gray_image(png, "memory");
  EXPECT_EQ(gray.type(), CV_8UC1);
  EXPECT_EQ(gray.size(), cv::Size(30, 20));
  EXPECT_EQ(gray.at<unsigned char>(5, 5), 10);
}
