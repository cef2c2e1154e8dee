// The directions of beams (vwg/geometry/directions.hpp): vwg's own sine and cosine. Moved here
// from the raycaster (vwg_sim) so that the robot, which turns the same beams into map cells, does
// not link the simulator; the code and its flags (-ffp-contract=off, CMakeLists.txt) are the same,
// so every direction keeps its bits.
#include "vwg/geometry/directions.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>

#include "geometry/directions_detail.hpp"
#include "vwg/error.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define VWG_DIRECTIONS_X86 1
#endif

namespace vwg::geometry {

namespace {

// A ray's direction is the cosine and sine of its angle in grid axes. libm's sincos took a fifth
// of a scan, so they come from a Cody-Waite reduction and Taylor polynomials instead, 8 angles at
// a time with AVX-512 (within 1 ulp of libm's; std::sin and std::cos beyond |angle| = 1e5).
// Every method takes its directions from grid_directions(), so all see the same bits: on a CPU
// with AVX-512 every ray, single or in a scan, uses the AVX-512 code (which rounds each operation
// on its own, never fused); without it, single rays use the one compiled copy of the scalar code
// and a scan's beams the same operations on 4 lanes of AVX2 (no FMA: never fused either).

constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
constexpr double kHalfPiHigh = 0x1.921fb544p+0;  // pi/2 in three parts; the first two have 33
constexpr double kHalfPiMid = 0x1.0b4611a6p-34;  // bits, so k * part is exact for |k| < 2^20
constexpr double kHalfPiLow = 0x1.3198a2e037073p-69;
constexpr double kRoundToInteger = 0x1.8p52;  // (x + it) - it rounds x to an integer, |x| < 2^51
constexpr double kReduceLimit = 1e5;

constexpr double inverse_factorial(int n) {
  double f = 1.0;
  for (int i = 2; i <= n; ++i) f *= i;  // exact up to 18!
  return 1.0 / f;
}
// Taylor coefficients; on |r| <= pi/4 the first terms left out are below 1e-19.
constexpr double kSin[] = {-inverse_factorial(3),  inverse_factorial(5),  -inverse_factorial(7),
                           inverse_factorial(9),   -inverse_factorial(11), inverse_factorial(13),
                           -inverse_factorial(15), inverse_factorial(17)};
constexpr double kCos[] = {inverse_factorial(4),   -inverse_factorial(6),  inverse_factorial(8),
                           -inverse_factorial(10), inverse_factorial(12),  -inverse_factorial(14),
                           inverse_factorial(16)};


#ifdef VWG_DIRECTIONS_X86

// GCC 12's AVX-512 headers pass _mm512_undefined_pd() around, which -Wmaybe-uninitialized flags.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

/// Rounded to nearest, each operation apart: the compiler cannot fuse these into an FMA, which
/// would round differently from the scalar code.
constexpr int kRoundNearest = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
#define VWG_AVX512 __attribute__((target("avx2,avx512f"), always_inline)) inline
VWG_AVX512 __m512d mul(__m512d a, __m512d b) { return _mm512_mul_round_pd(a, b, kRoundNearest); }
VWG_AVX512 __m512d add(__m512d a, __m512d b) { return _mm512_add_round_pd(a, b, kRoundNearest); }
VWG_AVX512 __m512d sub(__m512d a, __m512d b) { return _mm512_sub_round_pd(a, b, kRoundNearest); }
VWG_AVX512 __m128d mul(__m128d a, __m128d b) { return _mm_mul_round_sd(a, b, kRoundNearest); }  // lane 0 only
VWG_AVX512 __m128d add(__m128d a, __m128d b) { return _mm_add_round_sd(a, b, kRoundNearest); }
VWG_AVX512 __m128d sub(__m128d a, __m128d b) { return _mm_sub_round_sd(a, b, kRoundNearest); }
template <class V>
V splat(double x);
template <>
VWG_AVX512 __m512d splat<__m512d>(double x) { return _mm512_set1_pd(x); }
template <>
VWG_AVX512 __m128d splat<__m128d>(double x) { return _mm_set_sd(x); }

/// The steps of sincos_portable() up to the quadrant: the nearest quarter turn k to x, and the
/// sine and cosine of r = x - k pi/2. V: 8 lanes, or 1 (lane 0) for single rays.
template <class V>
VWG_AVX512 void reduced_sincos(V x, V& k, V& sin_r, V& cos_r) {
  const V round = splat<V>(kRoundToInteger);
  k = sub(add(mul(x, splat<V>(kTwoOverPi)), round), round);
  const V r = sub(sub(sub(x, mul(k, splat<V>(kHalfPiHigh))), mul(k, splat<V>(kHalfPiMid))),
                  mul(k, splat<V>(kHalfPiLow)));
  const V z = mul(r, r);
  V p = splat<V>(kSin[7]);
  for (int i = 6; i >= 0; --i) p = add(mul(p, z), splat<V>(kSin[i]));
  sin_r = add(r, mul(mul(r, z), p));
  V q = splat<V>(kCos[6]);
  for (int i = 5; i >= 0; --i) q = add(mul(q, z), splat<V>(kCos[i]));
  cos_r = add(sub(splat<V>(1.0), mul(splat<V>(0.5), z)), mul(mul(z, z), q));
}

/// sincos_portable() on 8 lanes (angles within kReduceLimit).
VWG_AVX512 void sincos_x8(__m512d x, __m512d& sin_x, __m512d& cos_x) {
  __m512d k, sin_r, cos_r;
  reduced_sincos(x, k, sin_r, cos_r);
  const __m512d fours = _mm512_roundscale_pd(mul(k, _mm512_set1_pd(0.25)), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d quarter = sub(k, mul(_mm512_set1_pd(4.0), fours));  // k mod 4, exactly
  const __mmask8 is1 = _mm512_cmp_pd_mask(quarter, _mm512_set1_pd(1.0), _CMP_EQ_OQ);
  const __mmask8 is2 = _mm512_cmp_pd_mask(quarter, _mm512_set1_pd(2.0), _CMP_EQ_OQ);
  const __mmask8 is3 = _mm512_cmp_pd_mask(quarter, _mm512_set1_pd(3.0), _CMP_EQ_OQ);
  const __mmask8 odd = static_cast<__mmask8>(is1 | is3);
  const __m512d s = _mm512_mask_blend_pd(odd, sin_r, cos_r), c = _mm512_mask_blend_pd(odd, cos_r, sin_r);
  const __m512d zero = _mm512_setzero_pd();
  sin_x = _mm512_mask_sub_pd(s, static_cast<__mmask8>(is2 | is3), zero, s);  // 0 - s: +0 where -s is -0,
  cos_x = _mm512_mask_sub_pd(c, static_cast<__mmask8>(is1 | is2), zero, c);  // made alike by grid_directions
}

/// sin and cos of n angles, 8 at a time.
__attribute__((target("avx2,avx512f"))) void sincos_avx512(const double* x, std::size_t n, double* sin_x,
                                                           double* cos_x) {
  for (std::size_t i = 0; i < n; i += 8) {
    const __mmask8 lanes = static_cast<__mmask8>(n - i >= 8 ? 0xFF : (1u << (n - i)) - 1);
    const __m512d angle = _mm512_maskz_loadu_pd(lanes, x + i);
    __m512d s, c;
    sincos_x8(angle, s, c);
    _mm512_mask_storeu_pd(sin_x + i, lanes, s);
    _mm512_mask_storeu_pd(cos_x + i, lanes, c);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::abs(x[i]) <= kReduceLimit)) sin_x[i] = std::sin(x[i]), cos_x[i] = std::cos(x[i]);
}

/// The same for one angle, on one lane: cheaper for single rays.
__attribute__((target("avx2,avx512f"))) void sincos_avx512(double x, double& sin_x, double& cos_x) {
  if (!(std::abs(x) <= kReduceLimit)) {
    sin_x = std::sin(x), cos_x = std::cos(x);
    return;
  }
  __m128d k, sin_r, cos_r;
  reduced_sincos(_mm_set_sd(x), k, sin_r, cos_r);
  const int quarter = static_cast<int>(_mm_cvtsd_f64(k)) & 3;
  const double s = _mm_cvtsd_f64(quarter & 1 ? cos_r : sin_r), c = _mm_cvtsd_f64(quarter & 1 ? sin_r : cos_r);
  sin_x = quarter >= 2 ? -s : s;
  cos_x = quarter == 1 || quarter == 2 ? -c : c;
}
#undef VWG_AVX512

#pragma GCC diagnostic pop

// ---- CPUs with AVX2 --------------------------------------------------------------------------
// No FMA is enabled here, so no expression is fused: every product and sum is rounded on its own,
// as in the scalar code.
#define VWG_AVX2 __attribute__((target("avx2"), always_inline)) inline

/// sincos_portable() on 4 lanes, by the same operations (angles within kReduceLimit).
VWG_AVX2 void sincos_x4(__m256d x, __m256d& sin_x, __m256d& cos_x) {
  const __m256d round = _mm256_set1_pd(kRoundToInteger);
  const __m256d k = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(x, _mm256_set1_pd(kTwoOverPi)), round), round);
  const __m256d r = _mm256_sub_pd(
      _mm256_sub_pd(_mm256_sub_pd(x, _mm256_mul_pd(k, _mm256_set1_pd(kHalfPiHigh))),
                    _mm256_mul_pd(k, _mm256_set1_pd(kHalfPiMid))),
      _mm256_mul_pd(k, _mm256_set1_pd(kHalfPiLow)));
  const __m256d z = _mm256_mul_pd(r, r);
  __m256d p = _mm256_set1_pd(kSin[7]);
  for (int i = 6; i >= 0; --i) p = _mm256_add_pd(_mm256_mul_pd(p, z), _mm256_set1_pd(kSin[i]));
  const __m256d sin_r = _mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, z), p));
  __m256d q = _mm256_set1_pd(kCos[6]);
  for (int i = 5; i >= 0; --i) q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(kCos[i]));
  const __m256d cos_r = _mm256_add_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(_mm256_set1_pd(0.5), z)),
                                      _mm256_mul_pd(_mm256_mul_pd(z, z), q));
  // k mod 4, exactly (k is an integer below 2^20 in magnitude).
  const __m256d fours = _mm256_floor_pd(_mm256_mul_pd(k, _mm256_set1_pd(0.25)));
  const __m256d quarter = _mm256_sub_pd(k, _mm256_mul_pd(_mm256_set1_pd(4.0), fours));
  const __m256d is1 = _mm256_cmp_pd(quarter, _mm256_set1_pd(1.0), _CMP_EQ_OQ);
  const __m256d is2 = _mm256_cmp_pd(quarter, _mm256_set1_pd(2.0), _CMP_EQ_OQ);
  const __m256d is3 = _mm256_cmp_pd(quarter, _mm256_set1_pd(3.0), _CMP_EQ_OQ);
  const __m256d odd = _mm256_or_pd(is1, is3);
  const __m256d s = _mm256_blendv_pd(sin_r, cos_r, odd), c = _mm256_blendv_pd(cos_r, sin_r, odd);
  const __m256d zero = _mm256_setzero_pd();
  // 0 - s: +0 where -s would be -0, made alike by grid_directions.
  sin_x = _mm256_blendv_pd(s, _mm256_sub_pd(zero, s), _mm256_or_pd(is2, is3));
  cos_x = _mm256_blendv_pd(c, _mm256_sub_pd(zero, c), _mm256_or_pd(is1, is2));
}

/// sin and cos of n angles, 4 at a time; bit for bit sincos_portable().
__attribute__((target("avx2"))) void sincos_avx2(const double* x, std::size_t n, double* sin_x, double* cos_x) {
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    __m256d s, c;
    sincos_x4(_mm256_loadu_pd(x + i), s, c);
    _mm256_storeu_pd(sin_x + i, s);
    _mm256_storeu_pd(cos_x + i, c);
  }
  if (i < n) {  // the last 1-3 angles, padded with zeros
    alignas(32) double tail[4] = {0.0, 0.0, 0.0, 0.0}, s_tail[4], c_tail[4];
    std::copy(x + i, x + n, tail);
    __m256d s, c;
    sincos_x4(_mm256_load_pd(tail), s, c);
    _mm256_store_pd(s_tail, s);
    _mm256_store_pd(c_tail, c);
    std::copy(s_tail, s_tail + (n - i), sin_x + i);
    std::copy(c_tail, c_tail + (n - i), cos_x + i);
  }
  for (std::size_t j = 0; j < n; ++j)
    if (!(std::abs(x[j]) <= kReduceLimit)) sin_x[j] = std::sin(x[j]), cos_x[j] = std::cos(x[j]);
}
#undef VWG_AVX2
#endif  // VWG_DIRECTIONS_X86

/// sin and cos of x, by the same operations as sincos_x8. Not inlined: one compiled copy.
[[gnu::noinline]] void sincos_portable(double x, double& sin_x, double& cos_x) {
  if (!(std::abs(x) <= kReduceLimit)) {
    sin_x = std::sin(x), cos_x = std::cos(x);
    return;
  }
  const double k = (x * kTwoOverPi + kRoundToInteger) - kRoundToInteger;  // nearest quarter turn
  const double r = ((x - k * kHalfPiHigh) - k * kHalfPiMid) - k * kHalfPiLow;
  const double z = r * r;
  double p = kSin[7];
  for (int i = 6; i >= 0; --i) p = p * z + kSin[i];
  const double sin_r = r + (r * z) * p;
  double q = kCos[6];
  for (int i = 5; i >= 0; --i) q = q * z + kCos[i];
  const double cos_r = (1.0 - 0.5 * z) + (z * z) * q;
  const int quarter = static_cast<int>(k) & 3;
  const double s = quarter & 1 ? cos_r : sin_r, c = quarter & 1 ? sin_r : cos_r;
  sin_x = quarter >= 2 ? -s : s;
  cos_x = quarter == 1 || quarter == 2 ? -c : c;
}

}  // namespace

namespace detail {

/// Unit directions in grid axes of n angles relative to the grid's yaw: du = cos, dv = sin.
/// Zero components are +0 (+ 0.0 turns -0 into +0), so they step +1 and cross at +infinity.
/// avx512: the AVX-512 code (its own bits, used for every ray on such a CPU); avx2: the scalar
/// code's operations on 4 lanes (the same bits as the scalar code, for a scan's many angles).
void grid_directions(const double* relative, std::size_t n, double* du, double* dv, [[maybe_unused]] bool avx512,
                     [[maybe_unused]] bool avx2) {
#ifdef VWG_DIRECTIONS_X86
  if (avx512 && n == 1) {
    sincos_avx512(*relative, *dv, *du);
  } else if (avx512) {
    sincos_avx512(relative, n, dv, du);
  } else if (avx2) {
    sincos_avx2(relative, n, dv, du);
  } else
#endif
  {
    for (std::size_t i = 0; i < n; ++i) sincos_portable(relative[i], dv[i], du[i]);
  }
  for (std::size_t i = 0; i < n; ++i) du[i] += 0.0, dv[i] += 0.0;
}

/// Whether `name` names a scan code: "avx512", "avx2" or "none".
bool is_simd_name(std::string_view name) { return name == "avx512" || name == "avx2" || name == "none"; }

/// The widest SIMD code this CPU runs, at most `cap` ("avx512", "avx2" or "none").
std::string_view simd_level(std::string_view cap) {
#ifdef VWG_DIRECTIONS_X86
  __builtin_cpu_init();  // in case a raycaster is made before libgcc's own initialisation
  if (cap != "none" && __builtin_cpu_supports("avx2"))
    return cap == "avx512" && __builtin_cpu_supports("avx512f") ? "avx512" : "avx2";
#endif
  return "none";
}

}  // namespace detail

std::string_view beam_directions(std::span<const double> relative, std::string_view simd, std::span<double> du,
                                 std::span<double> dv) {
  if (du.size() != relative.size() || dv.size() != relative.size())
    throw Error("beam_directions: " + std::to_string(relative.size()) + " angles for " + std::to_string(du.size()) +
                " and " + std::to_string(dv.size()) + " outputs");
  if (!detail::is_simd_name(simd))
    throw Error("beam_directions: simd must be avx512, avx2 or none, not '" + std::string(simd) + "'");
  const std::string_view level = detail::simd_level(simd);
  detail::grid_directions(relative.data(), relative.size(), du.data(), dv.data(), level == "avx512", level == "avx2");
  return level;
}

}  // namespace vwg::geometry
