#pragma once
// Procedural albedo painters for the synthetic room (CV_8UC1 canvases, `tpm` texels per metre). Everything draws
// from the cv::RNG it is given, so a seeded RNG gives the same textures on every run.
#include <opencv2/core.hpp>

namespace vkvo::synth::paint {

// Band-limited noise in [-1, 1]: octaves of bicubically upsampled random grids from `largest_cell` texels down.
cv::Mat value_noise(cv::Size size, double largest_cell, int octaves, cv::RNG& rng);

cv::Mat plaster(cv::Size size, double tpm, double base_albedo, cv::RNG& rng);  // walls: smooth, stained, grainy
cv::Mat planks(cv::Size size, double tpm, cv::RNG& rng);                       // floor: wooden planks along u
cv::Mat ceiling_tiles(cv::Size size, double tpm, cv::RNG& rng);                // ceiling: 0.6 m acoustic tiles
cv::Mat cardboard(cv::Size size, double tpm, cv::RNG& rng);                    // box face: tape and label
// Low-texture surfaces: flat albedo with faint shading over metres; `skirting` adds the wall's skirting board.
cv::Mat plain(cv::Size size, double tpm, double albedo, bool skirting, cv::RNG& rng);

// Drawn onto an existing canvas inside `area`.
void poster(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng);
void door(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng);
void window(cv::Mat& canvas, const cv::Rect& area, double tpm, cv::RNG& rng);

}  // namespace vkvo::synth::paint
