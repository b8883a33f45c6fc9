// The Robin radius of walk on stars (WalkOnStars.md §1, WoSt-7): the largest
// radius <= R at which every Robin point z of the star keeps the walk's
// weight 1 − μ|S| G(r) r^{n−1}/(n·v) >= 0 for Δ. With h the distance from x
// to a primitive's plane, n·v = h/r, so the weight is 1 − μ f(r)/h with
// f(r) = r²(1 − r/R) (3D), r² ln(R/r) (2D). f rises to its largest,
// 4R²/27 at r = 2R/3 (3D), R²/(2e) at r = R/√e (2D), and falls after. A
// primitive at distance d from x has points only at r >= d, so with
// t = h/μ it allows
//
//   3D: R = d / (1 − t/d²)   where t < d²/3 (then 2R/3 < d: f's largest
//                            over r >= d is f(d)),
//       R = sqrt(27t/4)      otherwise;
//   2D: R = d·exp(t/d²)      where t < d²/2,
//       R = sqrt(2e t)       otherwise
//
// (continuous at the switch, rising with t and with d, and never below
// sqrt(27t/4) or sqrt(2e t), so a primitive or node whose k·h/μ reaches R²
// still cannot shrink the radius; a primitive beyond R leaves it). The
// second form alone, with the radius floored at d, was used before; the
// first lets a star grow up to 1.5 (3D) or √e (2D) times the distance of a
// nearby primitive whose plane is close to x.
//
// The primitive a walker on the Robin part stands on (and the coplanar ones
// around it) still bound its next star to about ε: no ray meets that plane
// again, but it is part of the star's boundary, and its term −∫ μ G u
// has no other estimator here (WalkOnStars.md §9: leaving it out of the
// bound biased 2D Robin problems to a mean z² of 44).
//
// Each primitive within R used to be visited. Here every node of the flux
// sampler's hierarchy (ReflectingBoundarySampler.h) also keeps a bound for
// its Robin primitives, as in Miller, Sawhney, Crane and Gkioulekas 2024
// ("Walkin' Robin"): their largest μ, a cone (axis a, half-angle θ < 90°)
// holding their normals, and the range [o−, o+] of their planes' offsets
// o = (p − c)·n from the node's box centre c (p a point of the primitive).
// A primitive's signed plane distance is then
//
//   s = (p − x)·n = o + (c − x)·n,
//
// and with φ the angle between c − x and a, the angle between c − x and n
// lies in [max(φ − θ, 0), min(φ + θ, π)], so
//
//   o− + |c − x| cos(min(φ + θ, π)) <= s <= o+ + |c − x| cos(max(φ − θ, 0)),
//
// and h = |s| is at least the lower end where it is positive, minus the
// upper end where that is negative. A node whose k·h/μ_max reaches R²
// cannot shrink the radius and its subtree is skipped. The offsets keep
// the bound tight where x is close to the node, even inside its box (a
// patch of a smooth surface has o− ≈ o+), where a bound through the box's
// half-diagonal alone says nothing: on the stars bench's sphere (20,480
// triangles, Robin above z = 0.5) a query visits 1.9 primitives and tests
// 12 nodes, where that bound alone visited 25 and tested 42. The radius
// is the same as visiting every primitive; only the work changes.
#ifndef GRIDFREE_STARS_ROBIN_RADIUS_H
#define GRIDFREE_STARS_ROBIN_RADIUS_H

#include <gridfree/math/Vector.h>
#include <gridfree/stars/ReflectingBoundarySampler.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
template <int DIM>
class RobinRadiusTree
{
public:
  // The nodes' bounds for `mu` and `normals` (unit, outward) per primitive
  // of the sampler's mesh. The tree keeps no reference: the same arrays
  // (and sampler) are handed to Radius.
  void Build(const ReflectingBoundarySampler<DIM>& sampler, const std::vector<double>& mu,
    const std::vector<Vec<DIM>>& normals)
  {
    this->Nodes.assign(sampler.NodeCount(), NodeBound());
    sampler.ForEachNode([&](std::uint32_t index, const BoundingBox<DIM>& box,
                          const std::int64_t* first, const std::int64_t* last) {
      NodeBound& b = this->Nodes[index];
      Vec<DIM> sum = Vec<DIM>::Zero();
      for (const std::int64_t* p = first; p != last; ++p)
      {
        const double m = mu[static_cast<std::size_t>(*p)];
        if (m > 0.0)
        {
          b.MaxMu = std::max(b.MaxMu, m);
          sum += normals[static_cast<std::size_t>(*p)];
        }
      }
      if (!(b.MaxMu > 0.0))
      {
        return;
      }
      b.Centre = 0.5 * (box.Min + box.Max);
      b.HalfDiagonal = 0.5 * (box.Max - box.Min).norm();
      const double length = sum.norm();
      if (!(length > 0.0))
      {
        return; // normals cancel: no cone (CosTheta stays −1)
      }
      b.Axis = sum / length;
      double cosTheta = 1.0;
      for (const std::int64_t* p = first; p != last; ++p)
      {
        if (mu[static_cast<std::size_t>(*p)] > 0.0)
        {
          cosTheta = std::min(cosTheta, b.Axis.dot(normals[static_cast<std::size_t>(*p)]));
        }
      }
      b.CosTheta = std::max(-1.0, cosTheta);
      b.OffsetMin = std::numeric_limits<double>::infinity();
      b.OffsetMax = -std::numeric_limits<double>::infinity();
      for (const std::int64_t* p = first; p != last; ++p)
      {
        const std::size_t i = static_cast<std::size_t>(*p);
        if (mu[i] > 0.0)
        {
          const double o = (sampler.FirstVertex(*p) - b.Centre).dot(normals[i]);
          b.OffsetMin = std::min(b.OffsetMin, o);
          b.OffsetMax = std::max(b.OffsetMax, o);
        }
      }
    });
  }

  // The Robin radius at x for a star of radius R (R when no Robin
  // primitive shrinks it), with the arrays Build was given.
  double Radius(const ReflectingBoundarySampler<DIM>& sampler, const std::vector<double>& mu,
    const std::vector<Vec<DIM>>& normals, const Vec<DIM>& x, double R) const
  {
    double radius = R;
    sampler.VisitWithin(
      x, radius,
      [&](std::int64_t prim) {
        const std::size_t i = static_cast<std::size_t>(prim);
        const double m = mu[i];
        if (!(m > 0.0))
        {
          return;
        }
        const double h = std::abs((x - sampler.FirstVertex(prim)).dot(normals[i]));
        if (!(kFactor * h / m < radius * radius))
        {
          return; // the plane is far enough: this primitive cannot shrink the radius
        }
        const double d2 = sampler.SquaredDistance(prim, x);
        if (d2 < radius * radius)
        {
          radius = std::min(radius, PrimitiveRadius(h / m, std::sqrt(d2)));
        }
      },
      [&](std::uint32_t node) { return this->CannotShrink(this->Nodes[node], x, radius); });
    return radius;
  }

  // The largest star radius at which a Robin primitive at distance d from
  // x, whose plane lies h from x, keeps the weights >= 0: t = h/μ (above).
  static double PrimitiveRadius(double t, double d)
  {
    const double d2 = d * d;
    if constexpr (DIM == 3)
    {
      return t < d2 / 3.0 ? d / (1.0 - t / d2) : std::sqrt(kFactor * t);
    }
    else
    {
      return t < 0.5 * d2 ? d * std::exp(t / d2) : std::sqrt(kFactor * t);
    }
  }

private:
  static constexpr double kFactor = DIM == 3 ? 27.0 / 4.0 : 2.0 * M_E;

  struct NodeBound
  {
    double MaxMu = 0.0; // 0: no Robin primitive below
    Vec<DIM> Centre = Vec<DIM>::Zero();
    double HalfDiagonal = 0.0;
    Vec<DIM> Axis = Vec<DIM>::Zero();
    double CosTheta = -1.0; // the cone's half-angle; −1: none
    double OffsetMin = 0.0, OffsetMax = 0.0; // the planes' offsets from Centre
  };

  // Whether no Robin primitive below the node can shrink `radius`.
  static bool CannotShrink(const NodeBound& b, const Vec<DIM>& x, double radius)
  {
    if (!(b.MaxMu > 0.0))
    {
      return true;
    }
    if (!(b.CosTheta > 0.0))
    {
      return false;
    }
    const Vec<DIM> w = b.Centre - x;
    const double length = w.norm();
    double lower = b.OffsetMin, upper = b.OffsetMax;
    if (length > 0.0)
    {
      const double cosPhi = std::max(-1.0, std::min(1.0, w.dot(b.Axis) / length));
      const double sinPhi = std::sqrt(std::max(0.0, 1.0 - cosPhi * cosPhi));
      const double sinTheta = std::sqrt(std::max(0.0, 1.0 - b.CosTheta * b.CosTheta));
      // cos(min(φ + θ, π)) and cos(max(φ − θ, 0)); φ + θ >= π where
      // cos φ <= −cos θ, φ < θ where cos φ > cos θ.
      const double cosSum =
        cosPhi <= -b.CosTheta ? -1.0 : cosPhi * b.CosTheta - sinPhi * sinTheta;
      const double cosDifference =
        cosPhi > b.CosTheta ? 1.0 : cosPhi * b.CosTheta + sinPhi * sinTheta;
      lower += length * cosSum;
      upper += length * cosDifference;
    }
    // A margin for the rounding of the terms above.
    const double margin = 1e-12 * (std::abs(b.OffsetMin) + std::abs(b.OffsetMax) + length);
    const double h = lower > 0.0 ? lower - margin : (upper < 0.0 ? -upper - margin : 0.0);
    return h > 0.0 && kFactor * h / b.MaxMu >= radius * radius;
  }

  std::vector<NodeBound> Nodes;
};
} // namespace gridfree

#endif
