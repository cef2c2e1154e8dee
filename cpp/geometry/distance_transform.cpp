#include "geometry/distance_transform.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace vwg::geometry {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

void distance_transform_1d(const double* f, double* d, int n, std::vector<int>& v, std::vector<double>& z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;  // no parabola: keeps ∞ out of the intersection arithmetic
    const double fq = f[q] + static_cast<double>(q) * q;
    double s = -kInf;
    while (k >= 0) {
      const int p = v[k];
      s = (fq - (f[p] + static_cast<double>(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : s;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    std::fill(d, d + n, kInf);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    d[q] = dq * dq + f[v[j]];
  }
}

std::vector<double> squared_distance_transform(const std::vector<std::uint8_t>& source, int rows, int cols) {
  const auto at = [cols](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };
  std::vector<double> f(static_cast<std::size_t>(rows) * cols, kInf);
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (source[i]) f[i] = 0.0;
  }
  const int longest = std::max(rows, cols);
  std::vector<double> line(static_cast<std::size_t>(longest)), out(static_cast<std::size_t>(longest));
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  for (int c = 0; c < cols; ++c) {  // along columns first, then along rows
    for (int r = 0; r < rows; ++r) line[r] = f[at(r, c)];
    distance_transform_1d(line.data(), out.data(), rows, v, z);
    for (int r = 0; r < rows; ++r) f[at(r, c)] = out[r];
  }
  for (int r = 0; r < rows; ++r) {
    distance_transform_1d(&f[at(r, 0)], out.data(), cols, v, z);
    std::copy(out.begin(), out.begin() + cols, f.begin() + static_cast<std::ptrdiff_t>(at(r, 0)));
  }
  return f;
}

}  // namespace vwg::geometry
