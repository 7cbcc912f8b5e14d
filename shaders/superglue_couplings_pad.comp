#version 450
// Z (rows x cols, row-major) -> its rows and its columns as padded row-major copies for
// superglue_sinkhorn_tiled.comp: rows (rows x cols_padded) and columns (cols x rows_padded, i.e. Z^T), the
// padding (up to whole texels of 4) set to -1e30 so that it adds nothing to a logsumexp.
layout(local_size_x = 16, local_size_y = 4) in;

layout(std430, binding = 0) readonly buffer Couplings { float z[]; };
layout(std430, binding = 1) writeonly buffer Rows { float by_row[]; };
layout(std430, binding = 2) writeonly buffer Columns { float by_column[]; };

#include "push/couplings_pad.h"

void main() {
  const uint j = gl_GlobalInvocationID.x, i = gl_GlobalInvocationID.y;
  if (i >= p.rows_padded || j >= p.cols_padded) return;
  const bool inside = i < p.rows && j < p.cols;
  const float value = inside ? z[i * p.cols + j] : -1.0e30;
  if (i < p.rows) by_row[i * p.cols_padded + j] = value;
  if (j < p.cols) by_column[j * p.rows_padded + i] = value;
}
