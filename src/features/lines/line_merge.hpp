#pragma once
// Fusing of segments that a detector split (paper Sec. "2D line processing / detection") and the length filter.
#include <vector>

#include "features/lines/line_params.hpp"
#include "features/lines/line_segment.hpp"

namespace vkvo::features {

// True when `a` and `b` belong to one line: their directions differ by less than max_angle, the midpoint of one
// lies within max_midpoint_distance of the other's supporting line, and, when their projections on the common
// direction do not overlap (for an axis-aligned pair: their x- resp. y-projections), the closest endpoints are
// less than max_endpoint_gap apart.
bool segments_mergeable(const LineSegment& a, const LineSegment& b, const MergeParams& params);

// The fused segment: direction = length-weighted mean of both directions, through the length-weighted centre of
// the two midpoints; endpoints = the extreme projections of the four endpoints onto that line.
LineSegment merge_two_segments(const LineSegment& a, const LineSegment& b);

// Merges mergeable pairs until no pair merges any more. Zero-length segments are dropped. Candidate pairs are
// found through an angle-sorted sweep, so the cost is about O(n log n + n k) for k segments per angle window.
std::vector<LineSegment> merge_segments(std::vector<LineSegment> segments, const MergeParams& params);

// Drops segments shorter than min_length (keeps the order of the rest).
void filter_short_segments(std::vector<LineSegment>& segments, float min_length);

}  // namespace vkvo::features
