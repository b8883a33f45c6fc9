// The order in which nearest searches and rays visit the children of a
// 4-wide node: by a lower bound of their squared distance, or of the ray's
// entry parameter, ties in slot order.
//
// Sorting up to four nearly equal keys with branches is a coin toss the
// branch predictor loses about half the time; near the surface of a mesh
// that fits in cache those mispredictions were a fifth of a closest-point
// query. So each child's rank (how many children come before it) is counted
// without branches, by comparing the four keys with their three rotations
// in SSE. The order is the one a stable insertion sort gives, so every
// instruction set, and the portable build, visit the same children in the
// same order and return the same primitive among equally near ones.
#ifndef GRIDFREE_GEOMETRY_BVH_CHILD_ORDER_H
#define GRIDFREE_GEOMETRY_BVH_CHILD_ORDER_H

#include <limits>

#if !defined(GRIDFREE_BVH_SCALAR) &&                                                          \
  (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define GRIDFREE_BVH_CHILD_ORDER_SSE 1
#endif

namespace gridfree
{
namespace detail
{
/// Index of the lowest set bit of a nonzero mask.
inline int LowestSetBit(int mask)
{
#if defined(__GNUC__) || defined(__clang__)
  return __builtin_ctz(static_cast<unsigned>(mask));
#else
  int c = 0;
  while (!(mask >> c & 1))
  {
    ++c;
  }
  return c;
#endif
}

/// Ranks of the children in `mask` (bits 0..3, at least one set) by key,
/// ties to the lower slot: rank[c] counts the children of the mask that come
/// before c, and is 0 outside the mask. Returns the child of rank 0. Keys
/// of the mask must not be NaN (the searches leave such children out).
inline int RankFourChildren(int mask, const float* keys, int* rank)
{
#ifdef GRIDFREE_BVH_CHILD_ORDER_SSE
  // Lanes outside the mask get NaN keys, which compare false: never before
  // another child.
  const __m128i bits = _mm_set_epi32(8, 4, 2, 1);
  const __m128 in =
    _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(mask), bits), bits));
  const __m128 k = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(keys)),
    _mm_andnot_ps(in, _mm_set1_ps(std::numeric_limits<float>::quiet_NaN())));
  // Rotation r puts the key of slot (c + r) mod 4 in lane c; that slot is
  // the lower one, which wins a tie, in the lanes set in its tie mask.
  auto before = [&](__m128 other, __m128i tie)
  {
    return _mm_castps_si128(_mm_or_ps(
      _mm_cmplt_ps(other, k), _mm_and_ps(_mm_castsi128_ps(tie), _mm_cmpeq_ps(other, k))));
  };
  const __m128i b1 =
    before(_mm_shuffle_ps(k, k, _MM_SHUFFLE(0, 3, 2, 1)), _mm_set_epi32(-1, 0, 0, 0));
  const __m128i b2 =
    before(_mm_shuffle_ps(k, k, _MM_SHUFFLE(1, 0, 3, 2)), _mm_set_epi32(-1, -1, 0, 0));
  const __m128i b3 =
    before(_mm_shuffle_ps(k, k, _MM_SHUFFLE(2, 1, 0, 3)), _mm_set_epi32(-1, -1, -1, 0));
  // Each true comparison is -1.
  const __m128i r = _mm_and_si128(_mm_castps_si128(in),
    _mm_sub_epi32(_mm_setzero_si128(), _mm_add_epi32(_mm_add_epi32(b1, b2), b3)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(rank), r);
  return LowestSetBit(
    _mm_movemask_ps(_mm_and_ps(in, _mm_castsi128_ps(_mm_cmpeq_epi32(r, _mm_setzero_si128())))));
#else
  int first = 0;
  for (int c = 3; c >= 0; --c)
  {
    rank[c] = 0;
    for (int d = 0; d < 4; ++d)
    {
      rank[c] += (mask >> d & 1) && (keys[d] < keys[c] || (keys[d] == keys[c] && d < c));
    }
    rank[c] &= -(mask >> c & 1);
    first = (mask >> c & 1) && rank[c] == 0 ? c : first;
  }
  return first;
#endif
}
} // namespace detail
} // namespace gridfree

#endif
