#include "tools/synth/perturb.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgcodecs.hpp>

#include "tools/synth/noise.hpp"

namespace vkvo::synth {
namespace fs = std::filesystem;
namespace {

std::string trim(std::string s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  return s;
}

std::vector<fs::path> sorted_images(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".pgm" || ext == ".tif"))
      files.push_back(entry.path().filename());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// cam<c>/data.csv rows in order -> "data/<filename>"; the sorted data/ folder when there is no CSV.
std::vector<fs::path> asl_images(const fs::path& cam_dir) {
  const fs::path csv_path = cam_dir / "data.csv";
  if (!fs::exists(csv_path)) {
    std::vector<fs::path> files = sorted_images(cam_dir / "data");
    for (auto& f : files) f = fs::path("data") / f;
    return files;
  }
  std::ifstream csv(csv_path);
  if (!csv) throw std::runtime_error(fmt::format("perturb: cannot read {}", csv_path.string()));
  std::vector<fs::path> files;
  std::string line;
  while (std::getline(csv, line)) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    if (comma == std::string::npos)
      throw std::runtime_error(
          fmt::format("perturb: {}: expected 'timestamp,filename', got '{}'", csv_path.string(), line));
    files.push_back(fs::path("data") / trim(line.substr(comma + 1)));
  }
  return files;
}

bool is_inside(const fs::path& child, const fs::path& parent) {
  const fs::path c = fs::weakly_canonical(child), p = fs::weakly_canonical(parent);
  auto [pi, ci] = std::mismatch(p.begin(), p.end(), c.begin(), c.end());
  return pi == p.end();
}

}  // namespace

StereoImageLists find_stereo_images(const fs::path& dir) {
  StereoImageLists lists;
  const fs::path mav0 = fs::is_directory(dir / "mav0") ? dir / "mav0" : dir;
  if (fs::is_directory(mav0 / "cam0") && fs::is_directory(mav0 / "cam1")) {
    lists.layout = SequenceLayout::asl;
    lists.left_dir = mav0 / "cam0";
    lists.right_dir = mav0 / "cam1";
    lists.left = asl_images(lists.left_dir);
    lists.right = asl_images(lists.right_dir);
    return lists;
  }
  for (const auto& [l, r] : {std::pair{"image_0", "image_1"}, std::pair{"image_l", "image_r"}}) {
    if (fs::is_directory(dir / l) && fs::is_directory(dir / r)) {
      lists.layout = SequenceLayout::kitti;
      lists.left_dir = dir / l;
      lists.right_dir = dir / r;
      lists.left = sorted_images(lists.left_dir);
      lists.right = sorted_images(lists.right_dir);
      return lists;
    }
  }
  throw std::runtime_error(
      fmt::format("perturb: {} is neither an ASL sequence (mav0/cam0, cam1) nor a KITTI "
                  "sequence (image_0/image_1 or image_l/image_r)",
                  dir.string()));
}

cv::Mat perturb_image(const cv::Mat& image, const FrameGain& gain, double noise_sigma, uint64_t stream) {
  std::vector<cv::Mat> channels;
  cv::split(image, channels);
  for (cv::Mat& channel : channels) {
    cv::Mat linear;
    channel.convertTo(linear, CV_32F);
    apply_gain(gain, linear, image.depth() == CV_16U ? 65535.0 : 255.0);
    if (noise_sigma > 0) {
      const auto sigma = static_cast<float>(noise_sigma);
      for (int y = 0; y < linear.rows; ++y) {
        float* row = linear.ptr<float>(y);
        const uint64_t row_stream = hash64(stream + static_cast<uint64_t>(y));
        for (int x = 0; x < linear.cols; ++x)
          row[x] += sigma * standard_normal(hash64(row_stream + static_cast<uint64_t>(x)));
      }
    }
    linear.convertTo(channel, image.depth());  // rounds and saturates to the source range
  }
  cv::Mat out;
  cv::merge(channels, out);
  return out;
}

void perturb_sequence(const fs::path& src, const fs::path& dst, const std::vector<IlluminationEvent>& events,
                      const PerturbOptions& options) {
  if (!fs::is_directory(src)) throw std::runtime_error(fmt::format("perturb: {} is not a folder", src.string()));
  if (is_inside(dst, src))
    throw std::runtime_error(
        fmt::format("perturb: output {} must not lie inside the source {}", dst.string(), src.string()));
  const StereoImageLists src_lists = find_stereo_images(src);
  fs::create_directories(dst);
  fs::copy(src, dst, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const StereoImageLists dst_lists = find_stereo_images(dst);

  const fs::path* dirs[2] = {&dst_lists.left_dir, &dst_lists.right_dir};
  const std::vector<fs::path>* files[2] = {&dst_lists.left, &dst_lists.right};
  for (int cam = 0; cam < 2; ++cam) {
    // Sequential: PNG coding dominates and errors must surface as exceptions here, not inside a thread pool.
    for (int k = 0; k < static_cast<int>(files[cam]->size()); ++k) {
      const fs::path path = *dirs[cam] / (*files[cam])[k];
      // The gain depends on the image size (spotlight), so read the header only when an event applies.
      if (frame_gain(events, k, cam, 1, 1).is_identity()) continue;
      const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
      if (image.empty()) throw std::runtime_error(fmt::format("perturb: cannot read {}", path.string()));
      const FrameGain gain = frame_gain(events, k, cam, image.cols, image.rows);
      const cv::Mat out = perturb_image(image, gain, options.noise_sigma, noise_stream(options.seed, k, cam));
      if (!cv::imwrite(path.string(), out))
        throw std::runtime_error(fmt::format("perturb: cannot write {}", path.string()));
    }
  }
  spdlog::info("perturb: {} -> {} ({} frames, {} events)", src.string(), dst.string(), src_lists.left.size(),
               events.size());
}

}  // namespace vkvo::synth
