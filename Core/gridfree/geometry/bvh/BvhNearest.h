// Nearest-primitive searches: the traversal behind Distance, ClosestPoint and
// the relaxed bound, and ClosestPoint itself.
// Part of the hierarchy of Bvh.h, which includes it after the class: include
// <gridfree/geometry/Bvh.h>, not this file.
#ifndef GRIDFREE_GEOMETRY_BVH_BVH_NEAREST_H
#define GRIDFREE_GEOMETRY_BVH_BVH_NEAREST_H

#include <gridfree/geometry/Bvh.h>

namespace gridfree
{
//------------------------------------------------------------------------------
template <int DIM>
template <bool Wide>
std::int64_t Bvh<DIM>::FindNearestBaseline(
  const Vec<DIM>& x, double& best2, Relaxation* relax, std::int64_t start) const
{
  best2 = std::numeric_limits<double>::infinity();
  if (this->Nodes.empty())
  {
    return -1;
  }
  const double exactBelow2 = relax ? relax->ExactBelow2 : 0.0;
  const double shrink2 = relax ? relax->Shrink2 : 1.0;
  std::int64_t best = -1;
  float threshold = std::numeric_limits<float>::infinity();
  auto tighten = [&]()
  {
    threshold = detail::PruneThreshold(relax && best2 > exactBelow2 ? best2 * shrink2 : best2);
  };
  if (start >= 0 && static_cast<std::size_t>(start) < this->Primitives.size())
  {
    best2 = this->Primitives[static_cast<std::size_t>(start)].SquaredDistance(x, best2);
    best = start;
    tighten();
  }
  float minPruned2 = std::numeric_limits<float>::infinity();

  // The query in node coordinates, as a float interval [xlo, xhi] that
  // contains the exact x - Center despite the rounding of the subtraction.
  float xlo[DIM], xhi[DIM];
  // For the leaf filter: the query rounded to nearest, and the bound of its
  // displacement plus the vertices' (below 2^-23 of the largest coordinate).
  float xq[DIM];
  double largest = 0.0;
  for (int k = 0; k < DIM; ++k)
  {
    const double y = x[k] - this->Center[k];
    xlo[k] = detail::FloatDown(y - std::abs(y) * 0x1p-50);
    xhi[k] = detail::FloatUp(y + std::abs(y) * 0x1p-50);
    xq[k] = static_cast<float>(y);
    largest = std::max(largest, std::abs(y));
  }
  const double margin = this->VertexMargin + largest * 0x1p-23 * (1.0 + 0x1p-20);
  double filterBest2 = std::numeric_limits<double>::quiet_NaN(); // best2 of filterR2
  float filterR2 = 0.0f;
#ifdef GRIDFREE_BVH_USE_SSE
  __m128 qlo[DIM], qhi[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    qlo[k] = _mm_set1_ps(xlo[k]);
    qhi[k] = _mm_set1_ps(xhi[k]);
  }
  const __m128 inf4 = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 pruned4 = inf4; // nearest skipped child box, per lane
#endif

  Entry stack[kStackSize];
  int top = 0;
  stack[top++] = Entry{ 0u, 0.0f };

  while (top > 0)
  {
    const Entry entry = stack[--top];
    if (entry.Key > threshold)
    {
      minPruned2 = std::min(minPruned2, entry.Key);
      continue; // a closer primitive was found since this entry was pushed
    }
    std::uint32_t ref = entry.Ref;
    for (;;) // descend towards the nearest child, pushing the others
    {
      if (ref & kLeafFlag)
      {
        // The leaf's float groups skip the primitives they prove farther
        // than best2 (BvhLeafFilter.h); the others are measured in double.
        // All groups' bounds and masks come first: then no group's test
        // waits for another group's double tests.
        const std::uint32_t first = (ref & ~kLeafFlag) >> 3;
        const std::uint32_t count = (ref & 7u) + 1;
        const std::uint32_t numGroups = (count + 3) / 4;
        detail::BvhLeafBounds bounds[(kMaxLeafSize + 3) / 4];
        int keep[(kMaxLeafSize + 3) / 4];
        static_assert(kMaxLeafSize <= 8, "a leaf fills at most two groups");
#ifdef GRIDFREE_SIMD_DISPATCH
        if (Wide && numGroups == 2)
        {
          detail::avx2::LeafFilterBoundsPair<DIM>(&this->Groups[first], xq, bounds);
        }
        else
#endif
        {
          for (std::uint32_t j = 0; j < numGroups; ++j)
          {
            detail::LeafFilterBounds<DIM>(this->Groups[first + j], xq, bounds[j]);
          }
        }
        for (std::uint32_t j = 0; j < numGroups; ++j)
        {
          keep[j] = (1 << std::min(count - 4 * j, 4u)) - 1;
        }
        if (!(best2 < std::numeric_limits<double>::infinity()))
        {
          // Nothing to filter against yet: the primitive nearest in float
          // is measured first, and its distance filters the others.
          std::uint32_t pick = 0;
          for (std::uint32_t l = 1; l < count; ++l)
          {
            pick = bounds[l / 4].Norm2[l % 4] < bounds[pick / 4].Norm2[pick % 4] ? l : pick;
          }
          const std::uint32_t i = 4 * first + pick;
          const double d2 = this->Primitives[i].SquaredDistance(x, best2);
          best2 = d2 < best2 ? d2 : best2; // (an overflow to NaN keeps inf)
          best = i;                        // (kept even then)
          keep[pick / 4] &= ~(1 << (pick % 4));
        }
        if (best2 < std::numeric_limits<double>::infinity())
        {
          if (filterBest2 != best2)
          {
            filterBest2 = best2;
            filterR2 = detail::LeafFilterRadius2(best2, margin);
          }
          for (std::uint32_t j = 0; j < numGroups; ++j)
          {
            keep[j] &= ~detail::LeafFilterSkipMask(bounds[j], filterR2);
          }
        }
        for (std::uint32_t j = 0; j < numGroups; ++j)
        {
          const std::uint32_t base = (first + j) << 2;
          for (int lanes = keep[j]; lanes; lanes &= lanes - 1)
          {
            const std::uint32_t i = base + static_cast<std::uint32_t>(CountTrailingZeros(lanes));
            const double d2 = this->Primitives[i].SquaredDistance(x, best2);
            if (d2 < best2)
            {
              best2 = d2;
              best = i;
            }
            else if (best < 0)
            {
              // Beyond ~1e154 squared distances overflow to inf (or NaN):
              // keep the first primitive then, so that a query always gets
              // one (nothing is skipped while best2 is inf).
              best = i;
            }
          }
        }
        tighten();
        break;
      }

      // Children to visit: boxes within the threshold, empty slots left out
      // (their inverted boxes may have a finite distance). Relaxed searches
      // remember the nearest box they skip.
      const Node& node = this->Nodes[ref];
      float dist2[kWidth];
      int mask = 0;
#ifdef GRIDFREE_BVH_USE_SSE
      const __m128 t4 = _mm_set1_ps(threshold);
      for (int g = 0; g < kWidth / 4; ++g)
      {
        const __m128 d2 = BoxDistances(node, g, qlo, qhi);
        _mm_storeu_ps(dist2 + 4 * g, d2);
        const __m128 empty = _mm_castsi128_ps(_mm_cmpeq_epi32(
          _mm_loadu_si128(reinterpret_cast<const __m128i*>(node.Child + 4 * g)),
          _mm_set1_epi32(-1)));
        const __m128 pass = _mm_andnot_ps(empty, _mm_cmple_ps(d2, t4));
        mask |= _mm_movemask_ps(pass) << (4 * g);
        // minps returns its second operand when either is NaN: the running
        // minimum goes second so that it is never replaced by a NaN.
        const __m128 visitedOrEmpty = _mm_or_ps(pass, empty);
        pruned4 = _mm_min_ps(_mm_or_ps(_mm_and_ps(visitedOrEmpty, inf4),
                               _mm_andnot_ps(visitedOrEmpty, d2)),
          pruned4);
      }
#else
      mask = BoxDistances(node, xlo, xhi, threshold, dist2);
      for (int c = 0; c < kWidth; ++c)
      {
        if (node.Child[c] == kEmptyChild)
        {
          mask &= ~(1 << c);
        }
        else if (!(mask >> c & 1))
        {
          minPruned2 = std::min(minPruned2, dist2[c]);
        }
      }
#endif
      if (mask == 0)
      {
        break;
      }
      if ((mask & (mask - 1)) == 0) // a single child: nothing to sort or push
      {
        ref = node.Child[CountTrailingZeros(mask)];
        this->Prefetch(ref);
        continue;
      }
      ref = this->VisitRanked(node, mask, dist2, stack, top);
    }
  }
  if (relax)
  {
#ifdef GRIDFREE_BVH_USE_SSE
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, pruned4);
    for (const float v : lanes)
    {
      minPruned2 = std::min(minPruned2, v);
    }
#endif
    relax->MinPruned2 = std::min(relax->MinPruned2, minPruned2);
  }
  return best;
}

//------------------------------------------------------------------------------
template <int DIM>
ClosestPointResult<DIM> Bvh<DIM>::ClosestPoint(const Vec<DIM>& x, NearestHint& hint) const
{
  ClosestPointResult<DIM> result;
  if (!(hint.Exact && hint.Point == x && hint.Primitive >= 0 &&
        static_cast<std::size_t>(hint.Primitive) < this->Primitives.size()))
  {
    double best2;
    hint.Primitive = this->FindNearest(x, best2, nullptr, hint.Primitive);
    hint.Exact = true;
    hint.Point = x;
  }
  const std::int64_t best = hint.Primitive;
  if (best < 0)
  {
    return result;
  }
  const auto cp = this->Primitives[best].ClosestPoint(x);
  result.point = cp.point;
  result.distance = std::sqrt(cp.squaredDistance);
  result.primitive = this->OriginalIds[best];
  result.barycentric = cp.weights;
  return result;
}
} // namespace gridfree

#endif
