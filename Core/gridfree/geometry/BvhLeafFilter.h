// Float filter of a hierarchy's leaf primitives for nearest-primitive
// searches: four primitives at a time, it proves in float which of them are
// farther from the query than the nearest one found so far, so that only the
// others get the exact double distance test.
//
// Why: a search visits leaves of several primitives, most of them no nearer
// than what it already holds; testing each one in double means reading its
// 72 bytes and running the full kernel. The float copy (36 bytes per
// triangle, four primitives interleaved per coordinate) is read and tested
// with one SIMD instruction sequence per four.
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
#ifndef GRIDFREE_GEOMETRY_BVH_LEAF_FILTER_H
#define GRIDFREE_GEOMETRY_BVH_LEAF_FILTER_H

#include <gridfree/geometry/FloatRounding.h>

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

/// The filter's bound (see above) for lanes with d[i] = x - V_i and any
/// direction n: a float Low with Low / |n| <= the distance from x to the
/// primitive, or -1 where no positive bound is proved (NaN included).
template <class L, int DIM>
inline typename L::F LeafFilterLow(
  const typename L::F (&d)[DIM][DIM], const typename L::F (&n)[DIM], typename L::F nn)
{
  using F = typename L::F;
  const F zero = L::Set(0.0f);
  // Below 2^-100 the squares may be subnormal and lose relative precision.
  F valid = L::Gt(nn, L::Set(0x1p-100f));
  F low = zero;
  for (int i = 0; i < DIM; ++i)
  {
    F sum = L::Mul(n[0], d[i][0]);
    F mag = L::Abs(sum);
    for (int k = 1; k < DIM; ++k)
    {
      const F p = L::Mul(n[k], d[i][k]);
      sum = L::Add(sum, p);
      mag = L::Add(mag, L::Abs(p));
    }
    const F li = L::Sub(L::Sub(sum, L::Mul(mag, L::Set(0x1p-20f))), L::Set(FLT_MIN));
    valid = L::And(valid, L::Gt(li, zero)); // false for NaN
    low = i == 0 ? li : L::Min(low, li);
  }
  return L::Select(valid, low, L::Set(-1.0f));
}

/// Direction n = x - c for c the float closest point of each lane's
/// primitive, given d[i] = x - V_i.
template <class L, int DIM>
inline void LeafFilterDirection(const typename L::F (&d)[DIM][DIM], typename L::F (&n)[DIM])
{
  using F = typename L::F;
  const F zero = L::Set(0.0f);
  const F one = L::Set(1.0f);
  auto dot = [](const F* a, const F* b)
  {
    F s = L::Mul(a[0], b[0]);
    for (int k = 1; k < DIM; ++k)
    {
      s = L::Add(s, L::Mul(a[k], b[k]));
    }
    return s;
  };
  F e1[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    e1[k] = L::Sub(d[0][k], d[1][k]); // V1 - V0
  }
  if constexpr (DIM == 2)
  {
    // Segment: the projection clamped to [0, 1]; a zero-length segment gives
    // NaN, which Max turns into 0.
    const F s = L::Min(L::Max(L::Div(dot(d[0], e1), dot(e1, e1)), zero), one);
    for (int k = 0; k < DIM; ++k)
    {
      n[k] = L::Sub(d[0][k], L::Mul(e1[k], s));
    }
  }
  else
  {
    F e2[DIM];
    for (int k = 0; k < DIM; ++k)
    {
      e2[k] = L::Sub(d[0][k], d[2][k]); // V2 - V0
    }
    // Ericson's regions (Real-Time Collision Detection, 5.1.5) without
    // branches: the closest point V0 + e1 s + e2 t of each region, selected
    // from the lowest priority to the highest.
    const F d1 = dot(e1, d[0]), d2 = dot(e2, d[0]);
    const F d3 = dot(e1, d[1]), d4 = dot(e2, d[1]);
    const F d5 = dot(e1, d[2]), d6 = dot(e2, d[2]);
    const F va = L::Sub(L::Mul(d3, d6), L::Mul(d5, d4));
    const F vb = L::Sub(L::Mul(d5, d2), L::Mul(d1, d6));
    const F vc = L::Sub(L::Mul(d1, d4), L::Mul(d3, d2));
    const F inv = L::Div(one, L::Add(L::Add(va, vb), vc));
    F s = L::Mul(vb, inv); // inside the face
    F t = L::Mul(vc, inv);
    const F d43 = L::Sub(d4, d3), d56 = L::Sub(d5, d6);
    const F onBC = L::And(L::Le(va, zero), L::And(L::Le(zero, d43), L::Le(zero, d56)));
    const F tBC = L::Div(d43, L::Add(d43, d56));
    s = L::Select(onBC, L::Sub(one, tBC), s);
    t = L::Select(onBC, tBC, t);
    const F onAC = L::And(L::Le(vb, zero), L::And(L::Le(zero, d2), L::Le(d6, zero)));
    s = L::Select(onAC, zero, s);
    t = L::Select(onAC, L::Div(d2, L::Sub(d2, d6)), t);
    const F atC = L::And(L::Le(zero, d6), L::Le(d5, d6));
    s = L::Select(atC, zero, s);
    t = L::Select(atC, one, t);
    const F onAB = L::And(L::Le(vc, zero), L::And(L::Le(zero, d1), L::Le(d3, zero)));
    s = L::Select(onAB, L::Div(d1, L::Sub(d1, d3)), s);
    t = L::Select(onAB, zero, t);
    const F atB = L::And(L::Le(zero, d3), L::Le(d4, d3));
    s = L::Select(atB, one, s);
    t = L::Select(atB, zero, t);
    const F atA = L::And(L::Le(d1, zero), L::Le(d2, zero));
    s = L::Select(atA, zero, s);
    t = L::Select(atA, zero, t);
    for (int k = 0; k < DIM; ++k)
    {
      n[k] = L::Sub(L::Sub(d[0][k], L::Mul(e1[k], s)), L::Mul(e2[k], t));
    }
  }
}

/// What the filter computes once per group and query, for any radius after:
/// per lane the bound Low of LeafFilterLow and |n|^2, which is also the
/// squared distance computed in float (an estimate, to pick which primitive
/// to measure first).
struct alignas(16) BvhLeafBounds
{
  float Low[4];
  float Norm2[4];
};

/// The filter's bounds of the four primitives of a group from the float
/// query q (relative to the hierarchy's centre).
template <int DIM>
inline void LeafFilterBounds(
  const BvhLeafGroup<DIM>& g, const float (&q)[DIM], BvhLeafBounds& out)
{
#ifdef GRIDFREE_LEAF_FILTER_USE_SSE
  using L = LeafFilterSse;
  __m128 d[DIM][DIM];
  for (int i = 0; i < DIM; ++i)
  {
    for (int k = 0; k < DIM; ++k)
    {
      d[i][k] = _mm_sub_ps(_mm_set1_ps(q[k]), _mm_load_ps(g.V[i][k]));
    }
  }
  __m128 n[DIM];
  LeafFilterDirection<L, DIM>(d, n);
  __m128 nn = _mm_mul_ps(n[0], n[0]);
  for (int k = 1; k < DIM; ++k)
  {
    nn = _mm_add_ps(nn, _mm_mul_ps(n[k], n[k]));
  }
  _mm_store_ps(out.Norm2, nn);
  _mm_store_ps(out.Low, LeafFilterLow<L, DIM>(d, n, nn));
#else
  using L = LeafFilterScalar;
  for (int lane = 0; lane < 4; ++lane)
  {
    float d[DIM][DIM];
    for (int i = 0; i < DIM; ++i)
    {
      for (int k = 0; k < DIM; ++k)
      {
        d[i][k] = q[k] - g.V[i][k][lane];
      }
    }
    float n[DIM];
    LeafFilterDirection<L, DIM>(d, n);
    float nn = n[0] * n[0];
    for (int k = 1; k < DIM; ++k)
    {
      nn += n[k] * n[k];
    }
    out.Norm2[lane] = nn;
    out.Low[lane] = LeafFilterLow<L, DIM>(d, n, nn);
  }
#endif
}

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
