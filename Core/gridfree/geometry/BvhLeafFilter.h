// Float filter of a hierarchy's leaf primitives for nearest-primitive
// searches and rays: four primitives at a time, it proves in float which of
// them are farther from the query than the nearest one found so far, or
// which a ray misses, so that only the others get the exact double test.
//
// Why: a search visits leaves of several primitives, most of them no nearer
// than what it already holds; testing each one in double means reading its
// 72 bytes and running the full kernel. The float copy (36 bytes per
// triangle, four primitives interleaved per coordinate) is read and tested
// with one SIMD instruction sequence per four, or per two groups of four
// with AVX2 (the lane templates of BvhLeafFilterLanes.h compiled again for
// AVX2, with the same bits per lane).
//
// The bound. For ANY vector n and a triangle (or segment) T with vertices
// V_i, every point p of T is a convex combination of the V_i, so
//   n . (x - p) >= min_i n . (x - V_i)   and   |x - p| >= that / |n|.
// The filter takes n = x - c for c the closest point of T computed in float
// (Ericson's region test); the bound is then nearly the true distance, but it
// stays a valid lower bound whatever c the rounding gives, even NaN (a NaN
// comparison never skips). Only the dot products need an error bound, and
// the differences between the exact data and its float copy:
// * min_i n . (x - V_i) is computed with at most 4 roundings per term, so it
//   is lowered by 2^-20 of the sum of the terms' magnitudes (and by FLT_MIN
//   for underflow);
// * the float query and vertices differ from the exact ones (relative to the
//   hierarchy's centre) by at most 2^-23 of their largest coordinate in
//   Euclidean norm, which the caller adds to the radius it asks about
//   (LeafFilterRadius2).
// A primitive is skipped only if low^2 > R2 * |n|^2 with a relative margin
// of 2^-19 folded into R2: its exact distance then exceeds R, so a search
// that keeps the first strictly nearer primitive gets the same answer, the
// same primitive and the same ties with or without the filter, on every
// instruction set.
//
// Rays use the same bound in the plane seen along the ray: projected and
// sheared as the watertight ray test projects them (RayKernels.h), a
// primitive the ray crosses contains the ray's point, and the exact test,
// whose signs are exact on its own double projection, rejects every
// primitive whose projection excludes that point. The filter bounds the
// distance from the point to the float projection from below and skips a
// primitive once that bound exceeds how far the float projection can lie
// from the exact test's (LeafRayFilterSetup): the exact tests that remain
// and their hits are those of an unfiltered traversal.
#ifndef GRIDFREE_GEOMETRY_BVH_LEAF_FILTER_H
#define GRIDFREE_GEOMETRY_BVH_LEAF_FILTER_H

#include <gridfree/geometry/FloatRounding.h>
#include <gridfree/geometry/SimdDispatch.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#if !defined(GRIDFREE_BVH_SCALAR) &&                                                          \
  (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define GRIDFREE_LEAF_FILTER_USE_SSE 1
#endif
#ifdef GRIDFREE_SIMD_DISPATCH
#include <immintrin.h>
#endif

namespace gridfree
{
namespace detail
{
/// Four consecutive primitives (in leaf order) in float, relative to the
/// hierarchy's centre: V[vertex][axis][lane]. 144 bytes for triangles.
template <int DIM>
struct alignas(16) BvhLeafGroup
{
  float V[DIM][DIM][4];
};

/// The float threshold R2 of the filter for a search whose nearest squared
/// distance so far is best2, with `margin` the bound of the float copies'
/// displacement (query plus vertices): (sqrt(best2) + margin)^2 rounded up
/// and raised by 2^-19 for the filter's own roundings. inf skips nothing.
inline float LeafFilterRadius2(double best2, double margin)
{
  const double r = std::sqrt(best2) * (1.0 + 0x1p-50) + margin;
  const double r2 = r * r * (1.0 + 0x1p-40) * (1.0 + 0x1p-19);
  return r2 < static_cast<double>(FLT_MAX) ? FloatUp(r2) : std::numeric_limits<float>::infinity();
}

/// Lane arithmetic of the filter: four lanes with SSE, or one float. Both
/// follow SSE's rules (max(a, b) = a > b ? a : b, so NaN gives b; a NaN
/// comparison is false).
#ifdef GRIDFREE_LEAF_FILTER_USE_SSE
struct LeafFilterSse
{
  using F = __m128;
  static F Set(float v) { return _mm_set1_ps(v); }
  static F Add(F a, F b) { return _mm_add_ps(a, b); }
  static F Sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F Mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F Div(F a, F b) { return _mm_div_ps(a, b); }
  static F Min(F a, F b) { return _mm_min_ps(a, b); }
  static F Max(F a, F b) { return _mm_max_ps(a, b); }
  static F Abs(F a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
  static F Le(F a, F b) { return _mm_cmple_ps(a, b); }
  static F Gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static F And(F a, F b) { return _mm_and_ps(a, b); }
  static F Select(F m, F a, F b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
};
#endif
struct LeafFilterScalar
{
  using F = float;
  static F Set(float v) { return v; }
  static F Add(F a, F b) { return a + b; }
  static F Sub(F a, F b) { return a - b; }
  static F Mul(F a, F b) { return a * b; }
  static F Div(F a, F b) { return a / b; }
  static F Min(F a, F b) { return a < b ? a : b; }
  static F Max(F a, F b) { return a > b ? a : b; }
  static F Abs(F a) { return std::fabs(a); }
  // Masks as floats: all bits set (a NaN) for true, +0 for false.
  static F Mask(bool b)
  {
    const std::uint32_t bits = b ? 0xffffffffu : 0u;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
  static bool Test(F m)
  {
    std::uint32_t bits;
    std::memcpy(&bits, &m, sizeof bits);
    return bits != 0u;
  }
  static F Le(F a, F b) { return Mask(a <= b); }
  static F Gt(F a, F b) { return Mask(a > b); }
  static F And(F a, F b) { return Mask(Test(a) && Test(b)); }
  static F Select(F m, F a, F b) { return Test(m) ? a : b; }
};

/// What the filter computes once per group and query, for any radius after:
/// per lane the bound Low of LeafFilterLow and |n|^2, which is also the
/// squared distance computed in float (an estimate, to pick which primitive
/// to measure first).
struct alignas(16) BvhLeafBounds
{
  float Low[4];
  float Norm2[4];
};

// The lane templates: LeafFilterLow, LeafFilterDirection,
// LeafFilterLaneBounds (instantiated again for AVX2 lanes below).
#include <gridfree/geometry/BvhLeafFilterLanes.h>

/// Runs the filter on the four lanes of a group: fill(L, load, d) writes
/// d[i] = x - V_i of the lanes, with load(lanes) giving a group row (4
/// floats) as lane values.
template <int NV, int ND, class Fill>
inline void LeafFilterBoundsOf(const Fill& fill, BvhLeafBounds& out)
{
#ifdef GRIDFREE_LEAF_FILTER_USE_SSE
  using L = LeafFilterSse;
  __m128 d[NV][ND];
  fill(L{}, [](const float* lanes) { return _mm_load_ps(lanes); }, d);
  __m128 low, nn;
  LeafFilterLaneBounds<L, NV, ND>(d, low, nn);
  _mm_store_ps(out.Norm2, nn);
  _mm_store_ps(out.Low, low);
#else
  using L = LeafFilterScalar;
  for (int lane = 0; lane < 4; ++lane)
  {
    float d[NV][ND];
    fill(L{}, [lane](const float* lanes) { return lanes[lane]; }, d);
    LeafFilterLaneBounds<L, NV, ND>(d, out.Low[lane], out.Norm2[lane]);
  }
#endif
}


/// The filter's bounds of the four primitives of a group from the float
/// query q (relative to the hierarchy's centre).
template <int DIM>
inline void LeafFilterBounds(
  const BvhLeafGroup<DIM>& g, const float (&q)[DIM], BvhLeafBounds& out)
{
  LeafFilterBoundsOf<DIM, DIM>(
    [&](auto lanes, const auto& load, auto& d)
    {
      using L = decltype(lanes);
      for (int i = 0; i < DIM; ++i)
      {
        for (int k = 0; k < DIM; ++k)
        {
          d[i][k] = L::Sub(L::Set(q[k]), load(g.V[i][k]));
        }
      }
    },
    out);
}

/// A ray seen along its direction: the primitives projected onto the DIM - 1
/// axes other than the dominant one, sheared so that the ray becomes the
/// origin, as the watertight ray tests do (RayKernels.h). The exact test
/// rejects every primitive whose projection (from its own double
/// arithmetic) does not contain the origin, so the filter's bound of the
/// distance from the origin to the float projection proves a miss once it
/// exceeds the bound of the two projections' difference (LeafFilterRayBounds).
template <int DIM>
struct LeafRayProjection
{
  float Origin[DIM]; // a point of the ray, relative to the centre, in float
  int Axis[DIM - 1]; // the projection's axes
  int Dominant;      // the axis along which the ray is followed
  float Shear[DIM - 1]; // direction[Axis[j]] / direction[Dominant], in float
};

/// Sets up the filter for a ray: y is a point of it relative to the
/// hierarchy's centre, within err[k] of an exact point of the ray per axis;
/// the exact test projects along axis `dominant` onto `axis`, with shear[j]
/// = direction[axis[j]] / direction[dominant] rounded to double (so
/// |shear| <= 1); the float vertices are within vertexMargin of the exact
/// ones per axis, and every vertex within 2^23 vertexMargin of the centre;
/// every coordinate of the ray origin the exact test uses is within
/// originOffset of the centre. Returns the threshold for LeafFilterSkipMask:
/// the square of a bound of how far, per projected point, the float
/// projection can lie from the exact test's, in the real numbers:
/// * float side: the displacements of the float origin (err, rounding to
///   float) and of the vertices, each counted twice (once through the
///   shear), and 2^-20 of the largest float coordinate for the rounding of
///   the subtraction, of the shear and of its two operations (7 roundings
///   of 2^-24 at most);
/// * double side: 2^-49 of the largest |vertex - origin| coordinate for the
///   exact test's own subtraction, shear and their roundings (6 of 2^-53);
/// times sqrt(2) for the two axes of a triangle's projection. The exact test
/// decides by exact signs on its projection, so it rejects every primitive
/// whose projection excludes the ray's point; the filter proves that when
/// its float projection is farther than this bound from the ray.
template <int DIM>
inline float LeafRayFilterSetup(const double (&y)[DIM], const double (&err)[DIM],
  const int (&axis)[DIM - 1], int dominant, const double (&shear)[DIM - 1], double vertexMargin,
  double originOffset, LeafRayProjection<DIM>& out)
{
  double yMax = 0.0, originError = 0.0;
  for (int k = 0; k < DIM; ++k)
  {
    out.Origin[k] = static_cast<float>(y[k]);
    yMax = std::max(yMax, std::abs(y[k]));
    originError = std::max(originError, err[k] + std::abs(y[k]) * 0x1p-24 + 0x1p-140);
  }
  out.Dominant = dominant;
  for (int j = 0; j < DIM - 1; ++j)
  {
    out.Axis[j] = axis[j];
    out.Shear[j] = static_cast<float>(shear[j]);
  }
  const double largest = vertexMargin * 0x1p23;
  const double floatSide = 2.0 * (originError + vertexMargin) + (yMax + largest) * 0x1p-20;
  const double doubleSide = (largest + originOffset) * 0x1p-49;
  const double margin = (DIM == 3 ? 1.5 : 1.0) * (floatSide + doubleSide) * (1.0 + 0x1p-40);
  // Far beyond float range the float origin is inf or NaN: skip nothing.
  return yMax < 0x1p100 ? LeafFilterRadius2(0.0, margin) : std::numeric_limits<float>::infinity();
}

/// The filter's bounds for a ray: Low / |n| bounds below the distance from
/// the ray to each lane's primitive in the float projection, whose vertices
/// are (Origin - V_i)[Axis[j]] - Shear[j] (Origin - V_i)[Dominant].
template <int DIM>
inline void LeafFilterRayBounds(
  const BvhLeafGroup<DIM>& g, const LeafRayProjection<DIM>& ray, BvhLeafBounds& out)
{
  LeafFilterBoundsOf<DIM, DIM - 1>(
    [&](auto lanes, const auto& load, auto& d)
    {
      using L = decltype(lanes);
      for (int i = 0; i < DIM; ++i)
      {
        const auto along = L::Sub(L::Set(ray.Origin[ray.Dominant]), load(g.V[i][ray.Dominant]));
        for (int j = 0; j < DIM - 1; ++j)
        {
          const int k = ray.Axis[j];
          d[i][j] = L::Sub(
            L::Sub(L::Set(ray.Origin[k]), load(g.V[i][k])), L::Mul(L::Set(ray.Shear[j]), along));
        }
      }
    },
    out);
}

#ifdef GRIDFREE_SIMD_DISPATCH
// The same lane templates again, compiled for AVX2 (as the searches of
// GRIDFREE_TARGET_AVX2 are, contraction off), so that eight-lane values never
// pass through code of another instruction set.
#pragma GCC push_options
#pragma GCC target("avx2,fma,bmi,bmi2,popcnt")
#pragma GCC optimize("fp-contract=off")
namespace avx2
{
#include <gridfree/geometry/BvhLeafFilterLanes.h>

/// Eight lanes (two groups) with AVX2, for the searches compiled for AVX2
/// and AVX-512. Each operation rounds as its SSE counterpart does, and
/// compares and selects the same way on NaN, so each lane's result is the
/// bits the SSE path computes for it.
struct LeafFilterAvx2
{
  using F = __m256;
  static F Set(float v) { return _mm256_set1_ps(v); }
  static F Add(F a, F b) { return _mm256_add_ps(a, b); }
  static F Sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F Mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F Div(F a, F b) { return _mm256_div_ps(a, b); }
  static F Min(F a, F b) { return _mm256_min_ps(a, b); }
  static F Max(F a, F b) { return _mm256_max_ps(a, b); }
  static F Abs(F a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
  static F Le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OS); }
  static F Gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OS); }
  static F And(F a, F b) { return _mm256_and_ps(a, b); }
  static F Select(F m, F a, F b)
  {
    return _mm256_or_ps(_mm256_and_ps(m, a), _mm256_andnot_ps(m, b));
  }
};

/// LeafFilterBounds of two consecutive groups at once, in eight AVX2 lanes:
/// the same bits as two calls.
template <int DIM>
inline void LeafFilterBoundsPair(
  const BvhLeafGroup<DIM>* g, const float (&q)[DIM], BvhLeafBounds (&out)[2])
{
  using L = LeafFilterAvx2;
  __m256 d[DIM][DIM];
  for (int i = 0; i < DIM; ++i)
  {
    for (int k = 0; k < DIM; ++k)
    {
      const __m256 v = _mm256_insertf128_ps(
        _mm256_castps128_ps256(_mm_load_ps(g[0].V[i][k])), _mm_load_ps(g[1].V[i][k]), 1);
      d[i][k] = L::Sub(L::Set(q[k]), v);
    }
  }
  __m256 low, nn;
  LeafFilterLaneBounds<L, DIM, DIM>(d, low, nn);
  _mm_store_ps(out[0].Norm2, _mm256_castps256_ps128(nn));
  _mm_store_ps(out[1].Norm2, _mm256_extractf128_ps(nn, 1));
  _mm_store_ps(out[0].Low, _mm256_castps256_ps128(low));
  _mm_store_ps(out[1].Low, _mm256_extractf128_ps(low, 1));
}

/// LeafFilterRayBounds of two consecutive groups at once, in eight AVX2
/// lanes: the same bits as two calls.
template <int DIM>
inline void LeafFilterRayBoundsPair(
  const BvhLeafGroup<DIM>* g, const LeafRayProjection<DIM>& ray, BvhLeafBounds (&out)[2])
{
  using L = LeafFilterAvx2;
  auto load = [&](int i, int k)
  {
    return _mm256_insertf128_ps(
      _mm256_castps128_ps256(_mm_load_ps(g[0].V[i][k])), _mm_load_ps(g[1].V[i][k]), 1);
  };
  __m256 d[DIM][DIM - 1];
  for (int i = 0; i < DIM; ++i)
  {
    const __m256 along = L::Sub(L::Set(ray.Origin[ray.Dominant]), load(i, ray.Dominant));
    for (int j = 0; j < DIM - 1; ++j)
    {
      const int k = ray.Axis[j];
      d[i][j] =
        L::Sub(L::Sub(L::Set(ray.Origin[k]), load(i, k)), L::Mul(L::Set(ray.Shear[j]), along));
    }
  }
  __m256 low, nn;
  LeafFilterLaneBounds<L, DIM, DIM - 1>(d, low, nn);
  _mm_store_ps(out[0].Norm2, _mm256_castps256_ps128(nn));
  _mm_store_ps(out[1].Norm2, _mm256_extractf128_ps(nn, 1));
  _mm_store_ps(out[0].Low, _mm256_castps256_ps128(low));
  _mm_store_ps(out[1].Low, _mm256_extractf128_ps(low, 1));
}
} // namespace avx2
#pragma GCC pop_options
#endif

/// The lanes (bits 0..3) whose primitive the bounds prove farther than
/// sqrt(r2), r2 from LeafFilterRadius2: Low > 0 and Low^2 > r2 |n|^2.
inline int LeafFilterSkipMask(const BvhLeafBounds& b, float r2)
{
#ifdef GRIDFREE_LEAF_FILTER_USE_SSE
  const __m128 low = _mm_load_ps(b.Low);
  const __m128 far = _mm_and_ps(_mm_cmpgt_ps(low, _mm_setzero_ps()),
    _mm_cmpgt_ps(_mm_mul_ps(low, low), _mm_mul_ps(_mm_set1_ps(r2), _mm_load_ps(b.Norm2))));
  return _mm_movemask_ps(far);
#else
  int mask = 0;
  for (int lane = 0; lane < 4; ++lane)
  {
    const float low = b.Low[lane];
    mask |= static_cast<int>(low > 0.0f && low * low > r2 * b.Norm2[lane]) << lane;
  }
  return mask;
#endif
}

} // namespace detail
} // namespace gridfree

#endif
