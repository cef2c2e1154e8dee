// The unit directions of beams, from vwg's own sine and cosine (a Cody-Waite reduction and Taylor
// polynomials, within 1 ulp of libm's): the same bits on every machine, where libm's may differ
// between its FMA and plain code. The simulator's raycaster, its laser's test against other
// robots and the robot's map updates all take a beam's direction from here, so they agree on it.
#pragma once

#include <span>
#include <string_view>

namespace vwg::geometry {

/// The unit directions du = cos, dv = sin of each angle (radians) with the code for `simd`:
/// "avx512", "avx2" or "none", lowered to what this CPU has. Returns the level used. The AVX2
/// code gives the scalar code's bits (so a run of beams and a single one agree); the AVX-512 code
/// has its own. Zero components are +0. Throws vwg::Error if the spans' sizes differ or `simd` is
/// none of those.
std::string_view beam_directions(std::span<const double> relative, std::string_view simd, std::span<double> du,
                                 std::span<double> dv);

}  // namespace vwg::geometry
