// The Robin radius of walk on stars (WalkOnStars.md §1, WoSt-7): the largest
// radius <= R at which every Robin point z of the star keeps the walk's
// weight 1 − μ|S| G(r) r^{n−1}/(n·v) >= 0 for Δ. With h the distance from x
// to a primitive's plane, n·v = h/r, and max over r < R of r²(1 − r/R) is
// 4R²/27 (3D), of r² ln(R/r) R²/(2e) (2D): so R <= sqrt(27h/(4μ)) (3D),
// sqrt(2e h/μ) (2D) for each Robin primitive nearer than R, unless the
// primitive lies beyond R.
//
// Each primitive within R used to be visited. Here every node of the flux
// sampler's hierarchy (ReflectingBoundarySampler.h) also keeps a bound for
// its Robin primitives, as in Miller, Sawhney, Crane and Gkioulekas 2024
// ("Walkin' Robin"): their largest μ and a cone (axis a, half-angle θ)
// holding their normals. For a node with box centre c and half-diagonal ρ,
// any of its primitives' planes lies at
//
//   h >= |x − c| cos(ψ + θ) − ρ,   ψ the angle between the line x − c and a
//
// (|(x − q)·n| >= |(x − c)·n| − |(c − q)·n|, and the angle of x − c to n is
// within θ of ψ), so a node whose c·h/μ_max reaches R² cannot shrink the
// radius and its subtree is skipped. The radius is the same as visiting
// every primitive; only the work changes.
#ifndef GRIDFREE_STARS_ROBIN_RADIUS_H
#define GRIDFREE_STARS_ROBIN_RADIUS_H

#include <gridfree/math/Vector.h>
#include <gridfree/stars/ReflectingBoundarySampler.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
        const double bound2 = kFactor * h / m;
        if (!(bound2 < radius * radius))
        {
          return; // the plane is far enough: this primitive cannot shrink the radius
        }
        const double d2 = sampler.SquaredDistance(prim, x);
        if (d2 < radius * radius)
        {
          radius = std::min(radius, std::sqrt(std::max(d2, bound2)));
        }
      },
      [&](std::uint32_t node) { return this->CannotShrink(this->Nodes[node], x, radius); });
    return radius;
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
    const Vec<DIM> d = x - b.Centre;
    const double length = d.norm();
    if (!(length > b.HalfDiagonal))
    {
      return false;
    }
    // cos(ψ + θ) with ψ in [0, π/2] from |cos ψ| of the line to the axis.
    const double cosPsi = std::min(1.0, std::abs(d.dot(b.Axis)) / length);
    const double sinPsi = std::sqrt(std::max(0.0, 1.0 - cosPsi * cosPsi));
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - b.CosTheta * b.CosTheta));
    const double cosSum = cosPsi * b.CosTheta - sinPsi * sinTheta;
    if (!(cosSum > 0.0))
    {
      return false;
    }
    // (A margin of 1e-12 for the rounding of this bound.)
    const double h = (length * cosSum - b.HalfDiagonal) * (1.0 - 1e-12);
    return h > 0.0 && kFactor * h / b.MaxMu >= radius * radius;
  }

  std::vector<NodeBound> Nodes;
};
} // namespace gridfree

#endif
