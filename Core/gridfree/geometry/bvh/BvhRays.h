// Ray queries: the float slab traversal and the watertight primitive tests
// behind Intersect and Occluded.
// Part of the hierarchy of Bvh.h, which includes it after the class: include
// <gridfree/geometry/Bvh.h>, not this file.
#ifndef GRIDFREE_GEOMETRY_BVH_BVH_RAYS_H
#define GRIDFREE_GEOMETRY_BVH_BVH_RAYS_H

#include <gridfree/geometry/Bvh.h>

namespace gridfree
{
//------------------------------------------------------------------------------
// Ray traversal. The primitive tests use the ray as given, in double. The box
// tests use, in float, the same ray written as
//   origin + tc * direction + t' * (2^shift * direction),  t = tc + 2^-shift t'
// where the power-of-two scale brings the largest direction component into
// [1, 2) (exact, and keeps every used reciprocal within float range), and tc
// is about where the ray enters the whole boundary box, so that an origin
// far away does not cost the float boxes their precision. The shifted origin
// is rounded to a float interval that contains the exact one.
template <int DIM>
template <bool AnyHit, bool Wide>
std::int64_t Bvh<DIM>::TraceRayBaseline(const Vec<DIM>& origin, const Vec<DIM>& direction,
  double tMin, double& t, Vec<DIM>& w) const
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double tMax = t;
  const double dMax = direction.cwiseAbs().maxCoeff();
  if (this->Nodes.empty() || !origin.allFinite() || !direction.allFinite() || dMax == 0.0 ||
    !(tMin <= tMax) || tMin == inf || tMax == -inf)
  {
    return -1;
  }
  const detail::RayFrame<DIM> frame(origin, direction);

  int exponent;
  std::frexp(dMax, &exponent);
  const int shift = 1 - exponent;

  // Any start works (the bounds below hold for every tc); the entry into the
  // root box, clamped to the window, keeps the float box coordinates small.
  double entry = -inf;
  for (int k = 0; k < DIM; ++k)
  {
    if (direction[k] != 0.0)
    {
      const double a = (this->Box.Min[k] - origin[k]) / direction[k];
      const double b = (this->Box.Max[k] - origin[k]) / direction[k];
      entry = std::max(entry, std::min(a, b));
    }
  }
  double tc = std::min(std::max(entry, tMin), tMax);
  if (!std::isfinite(tc))
  {
    tc = std::min(std::max(0.0, tMin), tMax);
  }

  // Shifted origin y - Center, with a bound on the rounding of each of its 3
  // operations (each below 2^-53 of |a| + |b|).
  double y[DIM], err[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    const double a = origin[k] - this->Center[k];
    const double b = tc * direction[k];
    y[k] = a + b;
    err[k] = (std::abs(a) + std::abs(b)) * 0x1p-50;
  }

  // The leaf filter's view of the ray (BvhLeafFilter.h): the shifted origin
  // and the projection of the exact test's frame.
  detail::LeafRayProjection<DIM> projection;
  float filterR2;
  {
    int axis[DIM - 1];
    double shear[DIM - 1];
    frame.Projection(axis, shear);
    double originOffset = 0.0;
    for (int k = 0; k < DIM; ++k)
    {
      originOffset = std::max(originOffset, std::abs(origin[k] - this->Center[k]));
    }
    filterR2 = detail::LeafRayFilterSetup<DIM>(
      y, err, axis, frame.Kz, shear, this->VertexMargin, originOffset, projection);
  }

  // |t'| of any hit is below tBound: along the dominant axis j the ray moves
  // at least |t'| while it must stay within the boundary box.
  int j = 0;
  direction.cwiseAbs().maxCoeff(&j);
  const double boxLo = this->Box.Min[j] - this->Center[j];
  const double boxHi = this->Box.Max[j] - this->Center[j];
  const double tBound = (std::max(std::abs(boxLo - y[j]), std::abs(boxHi - y[j])) + err[j] +
                          (std::abs(boxLo) + std::abs(boxHi)) * 0x1p-50) *
    (1.0 + 0x1p-40);

  RayBoxQuery q;
  for (int k = 0; k < DIM; ++k)
  {
    const double dk = detail::ScaleByPowerOfTwo(direction[k], shift);
    double e = err[k];
    if (std::abs(dk) >= 0x1p-100)
    {
      q.InvDirection[k] = static_cast<float>(1.0 / dk);
      q.NearSide[k] = dk < 0.0 ? kHigh : kLow;
    }
    else
    {
      // Treated as 0 (reciprocal +inf): the ray drifts by less than
      // tBound * 2^-99 along this axis (2^-100 plus underflow of the scaling),
      // which the origin interval absorbs.
      q.InvDirection[k] = std::numeric_limits<float>::infinity();
      q.NearSide[k] = kLow;
      e += tBound * 0x1p-99;
    }
    const float lo = detail::FloatDown(y[k] - e);
    const float hi = detail::FloatUp(y[k] + e);
    const float originBounds[2] = { hi, lo }; // by near side, without a branch
    q.NearOrigin[k] = originBounds[q.NearSide[k]];
    q.FarOrigin[k] = originBounds[q.NearSide[k] ^ 1];
  }

  // Window in t' units. The margin of 2^-30 of |t| + |tc| is generous for the
  // subtraction; it also keeps boxes whose exact entry is a little beyond
  // the computed t of the best hit so far, so rounding of the primitive
  // test never makes the traversal miss a primitive whose computed t is lower.
  auto lowerT = [&](double v)
  {
    const double s =
      detail::ScaleByPowerOfTwo(v - tc - (std::abs(v) + std::abs(tc)) * 0x1p-30, -shift);
    return detail::FloatDown(std::max(s, -tBound));
  };
  auto upperT = [&](double v)
  {
    const double s =
      detail::ScaleByPowerOfTwo(v - tc + (std::abs(v) + std::abs(tc)) * 0x1p-30, -shift);
    return detail::FloatUp(std::min(s, tBound));
  };
  const float tMinBox = lowerT(tMin);
  float tMaxBox = upperT(tMax);

  Entry stack[kStackSize]; // keys: lower bounds of the entry parameter t'
  int top = 0;
  stack[top++] = Entry{ 0u, tMinBox };
  std::int64_t best = -1;

  while (top > 0)
  {
    const Entry next = stack[--top];
    if (next.Key > tMaxBox)
    {
      continue; // a nearer hit was found since this entry was pushed
    }
    std::uint32_t ref = next.Ref;
    for (;;) // descend towards the nearest child, pushing the others
    {
      if (ref & kLeafFlag)
      {
        // The float groups skip the primitives whose projection they prove
        // misses the ray; the others get the exact test, in leaf order.
        const std::uint32_t first = (ref & ~kLeafFlag) >> 3;
        const std::uint32_t count = (ref & 7u) + 1;
        const std::uint32_t numGroups = (count + 3) / 4;
        int keep[(kMaxLeafSize + 3) / 4];
        detail::BvhLeafBounds bounds[(kMaxLeafSize + 3) / 4];
#ifdef GRIDFREE_SIMD_DISPATCH
        if (Wide && numGroups == 2)
        {
          detail::avx2::LeafFilterRayBoundsPair<DIM>(&this->Groups[first], projection, bounds);
        }
        else
#endif
        {
          for (std::uint32_t g = 0; g < numGroups; ++g)
          {
            detail::LeafFilterRayBounds<DIM>(this->Groups[first + g], projection, bounds[g]);
          }
        }
        for (std::uint32_t g = 0; g < numGroups; ++g)
        {
          keep[g] = ((1 << std::min(count - 4 * g, 4u)) - 1) &
            ~detail::LeafFilterSkipMask(bounds[g], filterR2);
        }
        const std::int64_t before = best;
        for (std::uint32_t g = 0; g < numGroups; ++g)
        {
          const std::uint32_t base = (first + g) << 2;
          for (int lanes = keep[g]; lanes; lanes &= lanes - 1)
          {
            const std::uint32_t i = base + static_cast<std::uint32_t>(CountTrailingZeros(lanes));
            double tHit;
            Vec<DIM> weights;
            if (frame.Intersect(this->Primitives[i].V, tMin, t, tHit, weights) &&
              (best < 0 || tHit < t))
            {
              t = tHit;
              w = weights;
              best = i;
              if constexpr (AnyHit)
              {
                return best;
              }
            }
          }
        }
        if (best != before)
        {
          tMaxBox = std::min(tMaxBox, upperT(t));
        }
        break;
      }

      const Node& node = this->Nodes[ref];
      float entries[kWidth];
      const int mask = RayBoxes(node, q, tMinBox, tMaxBox, entries);
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
      ref = this->VisitRanked(node, mask, entries, stack, top);
    }
  }
  return best;
}

//------------------------------------------------------------------------------
template <int DIM>
RayHit<DIM> Bvh<DIM>::Intersect(
  const Vec<DIM>& origin, const Vec<DIM>& direction, double tMax, double tMin) const
{
  RayHit<DIM> hit;
  double t = tMax;
  Vec<DIM> w;
  const std::int64_t best = this->template TraceRay<false>(origin, direction, tMin, t, w);
  if (best < 0)
  {
    return hit;
  }
  hit.t = t;
  hit.primitive = this->OriginalIds[best];
  hit.barycentric = w;
  hit.point = origin + t * direction;
  return hit;
}
} // namespace gridfree

#endif
