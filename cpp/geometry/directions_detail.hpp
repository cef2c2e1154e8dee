// The SIMD levels behind beam_directions (vwg/geometry/directions.hpp), for the raycaster, which
// chooses its level once and then asks for directions beam by beam or a scan at a time. Private to
// vwg's libraries: not installed.
#pragma once

#include <cstddef>
#include <string_view>

namespace vwg::geometry::detail {

/// Whether `name` names a SIMD code: "avx512", "avx2" or "none".
bool is_simd_name(std::string_view name);
/// The widest SIMD code this CPU runs, at most `cap` ("avx512", "avx2" or "none").
std::string_view simd_level(std::string_view cap);
/// Unit directions of n angles: du = cos, dv = sin, zero components +0. avx512: the AVX-512 code
/// (its own bits, used for every ray on such a CPU); avx2: the scalar code's operations on 4 lanes
/// (the scalar code's bits); neither: the scalar code. The level must be one this CPU runs
/// (simd_level); the arrays are not checked.
void grid_directions(const double* relative, std::size_t n, double* du, double* dv, bool avx512, bool avx2 = false);

}  // namespace vwg::geometry::detail
