// The exact squared Euclidean distance transform of a grid (Felzenszwalb & Huttenlocher 2012), which
// the clearance field (square-to-square distances) and the localization's likelihood field
// (centre-to-centre distances to the nearest obstacle) are made from.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <cstdint>
#include <vector>

namespace vwg::geometry {

/// One pass: d[q] = min over p of (q - p)² + f[p], through the lower envelope of the parabolas rooted at
/// the finite f[p] (∞ where every f is ∞). `v` and `z` are scratch of n and n + 1 entries.
void distance_transform_1d(const double* f, double* d, int n, std::vector<int>& v, std::vector<double>& z);

/// For each cell of a rows × cols grid (row-major), the squared distance in cells from its centre to the
/// centre of the nearest cell where `source` is non-zero; ∞ when there is none.
std::vector<double> squared_distance_transform(const std::vector<std::uint8_t>& source, int rows, int cols);

}  // namespace vwg::geometry
