#include "tools/synth/texture_painter.hpp"

#include <algorithm>
#include <string>

#include <opencv2/imgproc.hpp>

namespace vkvo::synth::paint {
namespace {

int texels(double metres, double tpm) { return std::max(1, cvRound(metres * tpm)); }

cv::Scalar gray(double albedo) { return cv::Scalar(std::clamp(albedo, 0.0, 1.0) * 255.0); }

// base + amplitude * noise, plus independent per-texel grain, quantised to 8 bits.
cv::Mat noisy_surface(cv::Size size, double base, double amplitude, double cell, double grain, cv::RNG& rng) {
  cv::Mat noise = value_noise(size, cell, 4, rng);
  cv::Mat fine(size, CV_32F);
  rng.fill(fine, cv::RNG::UNIFORM, -grain, grain);
  cv::Mat albedo = base + amplitude * noise + fine;
  cv::Mat out;
  albedo.convertTo(out, CV_8U, 255.0);
  return out;
}

std::string random_word(cv::RNG& rng) {
  static const char* const kWords[] = {"EXIT",  "LAB",   "VKVO",   "STEREO", "ROOM 12", "NO ENTRY", "MEETING", "PULL",
                                       "AIRVO", "LINES", "POINTS", "VULKAN", "FIRE",    "SAFETY",   "QUIET"};
  return kWords[rng.uniform(0, static_cast<int>(std::size(kWords)))];
}

void mondrian(cv::Mat& roi, cv::RNG& rng) {
  const int n = rng.uniform(6, 14);
  for (int i = 0; i < n; ++i) {
    const int w = rng.uniform(roi.cols / 8, roi.cols / 2 + 1), h = rng.uniform(roi.rows / 8, roi.rows / 2 + 1);
    const cv::Point p(rng.uniform(0, std::max(1, roi.cols - w)), rng.uniform(0, std::max(1, roi.rows - h)));
    cv::rectangle(roi, cv::Rect(p, cv::Size(w, h)), gray(rng.uniform(0.05, 0.95)), cv::FILLED, cv::LINE_AA);
    cv::rectangle(roi, cv::Rect(p, cv::Size(w, h)), gray(0.05), std::max(1, roi.cols / 120), cv::LINE_AA);
  }
}

void checkerboard(cv::Mat& roi, cv::RNG& rng) {
  const int cells = rng.uniform(4, 9);
  const int side = std::max(2, std::min(roi.cols, roi.rows) / cells);
  for (int y = 0; y * side < roi.rows; ++y)
    for (int x = 0; x * side < roi.cols; ++x)
      if ((x + y) % 2) cv::rectangle(roi, cv::Rect(x * side, y * side, side, side), gray(0.08), cv::FILLED);
}

void text_block(cv::Mat& roi, cv::RNG& rng) {
  const int lines = rng.uniform(3, 7);
  const double scale = roi.rows / (lines * 32.0);
  for (int i = 0; i < lines; ++i) {
    const cv::Point origin(roi.cols / 12, (i + 1) * roi.rows / (lines + 1) + cvRound(10 * scale));
    cv::putText(roi, random_word(rng), origin, cv::FONT_HERSHEY_SIMPLEX, scale, gray(rng.uniform(0.0, 0.3)),
                std::max(1, cvRound(2.5 * scale)), cv::LINE_AA);
  }
}

void shapes(cv::Mat& roi, cv::RNG& rng) {
  roi.setTo(gray(rng.uniform(0.3, 0.7)));
  const int n = rng.uniform(5, 12);
  const int r_max = std::max(3, std::min(roi.cols, roi.rows) / 5);
  for (int i = 0; i < n; ++i) {
    const cv::Point c(rng.uniform(0, roi.cols), rng.uniform(0, roi.rows));
    const int r = rng.uniform(2, r_max);
    if (i % 2) {
      cv::circle(roi, c, r, gray(rng.uniform(0.0, 1.0)), cv::FILLED, cv::LINE_AA);
    } else {
      const cv::Point tri[3] = {c + cv::Point(0, -r), c + cv::Point(r, r), c + cv::Point(-r, r)};
      cv::fillConvexPoly(roi, tri, 3, gray(rng.uniform(0.0, 1.0)), cv::LINE_AA);
    }
  }
}

}  // namespace

cv::Mat value_noise(cv::Size size, double largest_cell, int octaves, cv::RNG& rng) {
  cv::Mat sum = cv::Mat::zeros(size, CV_32F);
  double amplitude = 1.0, total = 0.0, cell = largest_cell;
  for (int o = 0; o < octaves && cell >= 2.0; ++o, cell /= 2.0, amplitude *= 0.5) {
    cv::Mat grid(std::max(2, cvCeil(size.height / cell) + 1), std::max(2, cvCeil(size.width / cell) + 1), CV_32F);
    rng.fill(grid, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::Mat up;
    cv::resize(grid, up, size, 0, 0, cv::INTER_CUBIC);
    sum += amplitude * up;
    total += amplitude;
  }
  return total > 0 ? cv::Mat(sum / total) : sum;
}

// A skirting board along the bottom: a long horizontal edge for the line detector.
void paint_skirting(cv::Mat& wall, double tpm) {
  const int skirting = texels(0.1, tpm);
  cv::rectangle(wall, cv::Rect(0, wall.rows - skirting, wall.cols, skirting), gray(0.25), cv::FILLED);
  cv::line(wall, {0, wall.rows - skirting}, {wall.cols, wall.rows - skirting}, gray(0.1), texels(0.01, tpm));
}

cv::Mat plaster(cv::Size size, double tpm, double base_albedo, cv::RNG& rng) {
  cv::Mat wall = noisy_surface(size, base_albedo, 0.12, 0.8 * tpm, 0.04, rng);
  paint_skirting(wall, tpm);
  return wall;
}

cv::Mat plain(cv::Size size, double tpm, double albedo, bool skirting, cv::RNG& rng) {
  cv::Mat surface = noisy_surface(size, albedo, 0.03, 2.0 * tpm, 0.0, rng);
  if (skirting) paint_skirting(surface, tpm);
  return surface;
}

cv::Mat planks(cv::Size size, double tpm, cv::RNG& rng) {
  cv::Mat floor = noisy_surface(size, 0.45, 0.05, 0.3 * tpm, 0.05, rng);
  const int width = texels(0.18, tpm), gap = std::max(1, texels(0.006, tpm));
  for (int y = 0; y < size.height; y += width) {
    int x = -rng.uniform(0, texels(1.2, tpm));
    while (x < size.width) {
      const int length = rng.uniform(texels(0.8, tpm), texels(2.0, tpm));
      const cv::Rect plank(x, y, length, width);
      cv::Mat roi = floor(plank & cv::Rect({}, size));
      x += length;
      if (roi.empty()) continue;
      roi += cv::Scalar(rng.uniform(-30.0, 30.0));  // per-plank tone (saturating)
      // Grain: noise stretched along the plank.
      cv::Mat grain = value_noise({roi.cols, roi.rows}, 0.05 * tpm, 2, rng);
      cv::resize(grain(cv::Rect(0, 0, std::max(1, roi.cols / 8), roi.rows)), grain, roi.size(), 0, 0, cv::INTER_LINEAR);
      cv::Mat grain8;
      grain.convertTo(grain8, CV_8U, 20.0, 20.0);
      roi += grain8;
      roi -= cv::Scalar(20.0);
      cv::rectangle(floor, plank, gray(0.12), gap);
    }
  }
  return floor;
}

cv::Mat ceiling_tiles(cv::Size size, double tpm, cv::RNG& rng) {
  cv::Mat ceiling = noisy_surface(size, 0.8, 0.05, 0.3 * tpm, 0.06, rng);
  const int tile = texels(0.6, tpm), rail = std::max(1, texels(0.025, tpm));
  for (int x = 0; x < size.width; x += tile) cv::line(ceiling, {x, 0}, {x, size.height}, gray(0.45), rail);
  for (int y = 0; y < size.height; y += tile) cv::line(ceiling, {0, y}, {size.width, y}, gray(0.45), rail);
  // Acoustic perforations: dark speckles.
  const int holes = size.area() / std::max(1, texels(0.05, tpm) * texels(0.05, tpm));
  for (int i = 0; i < holes; ++i)
    cv::circle(ceiling, {rng.uniform(0, size.width), rng.uniform(0, size.height)}, std::max(1, texels(0.004, tpm)),
               gray(0.55), cv::FILLED);
  return ceiling;
}

cv::Mat cardboard(cv::Size size, double tpm, cv::RNG& rng) {
  cv::Mat face = noisy_surface(size, rng.uniform(0.4, 0.65), 0.06, 0.2 * tpm, 0.05, rng);
  const int tape = texels(0.05, tpm);
  cv::rectangle(face, cv::Rect(0, size.height / 2 - tape / 2, size.width, tape), gray(0.8), cv::FILLED);
  if (rng.uniform(0, 3) > 0 && size.width > texels(0.3, tpm) && size.height > texels(0.3, tpm)) {
    const cv::Rect label(size.width / 8, size.height / 8, size.width / 3, size.height / 4);
    cv::rectangle(face, label, gray(0.95), cv::FILLED);
    cv::Mat roi = face(label);
    text_block(roi, rng);
  }
  cv::rectangle(face, cv::Rect({}, size), gray(0.2), std::max(1, texels(0.01, tpm)));  // darker worn edges
  return face;
}

void poster(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng) {
  const cv::Rect inside = area & cv::Rect({}, canvas.size());
  cv::rectangle(canvas, inside, gray(0.92), cv::FILLED);
  const int border = texels(0.04, tpm);
  cv::Rect content(inside.x + border, inside.y + border, inside.width - 2 * border, inside.height - 2 * border);
  if (content.width < 4 || content.height < 4) return;
  cv::Mat roi = canvas(content);
  switch (rng.uniform(0, 4)) {
    case 0: mondrian(roi, rng); break;
    case 1: checkerboard(roi, rng); break;
    case 2: text_block(roi, rng); break;
    default: shapes(roi, rng); break;
  }
  cv::rectangle(canvas, inside, gray(0.05), std::max(1, texels(0.008, tpm)), cv::LINE_AA);
}

void door(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng) {
  cv::Mat roi = canvas(area & cv::Rect({}, canvas.size()));
  roi.setTo(gray(rng.uniform(0.2, 0.35)));
  cv::Mat grain = value_noise(roi.size(), 0.1 * tpm, 3, rng);
  cv::Mat grain8;
  grain.convertTo(grain8, CV_8U, 12.0, 12.0);
  roi += grain8;
  // Two recessed panels and a handle.
  const int m = texels(0.12, tpm);
  const int panel_h = (roi.rows - 3 * m) / 2;
  for (int i = 0; i < 2; ++i)
    cv::rectangle(roi, cv::Rect(m, m + i * (panel_h + m), roi.cols - 2 * m, panel_h), gray(0.12), texels(0.015, tpm),
                  cv::LINE_AA);
  cv::circle(roi, {roi.cols - texels(0.08, tpm), roi.rows / 2 + texels(0.05, tpm)}, texels(0.03, tpm), gray(0.85),
             cv::FILLED, cv::LINE_AA);
}

void window(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng) {
  cv::Mat roi = canvas(area & cv::Rect({}, canvas.size()));
  // A bright, slightly clouded view outside; the glass is the brightest thing in the room.
  cv::Mat sky = value_noise(roi.size(), 0.4 * tpm, 3, rng);
  sky.convertTo(roi, CV_8U, 25.0, 225.0);
  const int bar = texels(0.035, tpm);
  cv::rectangle(roi, cv::Rect(roi.cols / 2 - bar / 2, 0, bar, roi.rows), gray(0.3), cv::FILLED);
  cv::rectangle(roi, cv::Rect(0, roi.rows / 2 - bar / 2, roi.cols, bar), gray(0.3), cv::FILLED);
}

}  // namespace vkvo::synth::paint
