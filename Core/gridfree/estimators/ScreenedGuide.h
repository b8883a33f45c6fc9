// Guided steps for strongly screened walks (Δu − c·u = f with √c·R large).
//
// Why: a screened walk's step from x_k lands uniformly on ∂B(x_k, R) and
// multiplies the weight by C = z/sinh z (3D) or 1/I0(z) (2D), z = √c·R. When
// z is large, u varies over the sphere by a factor up to e^{2z}, and the few
// landing points where u is largest carry the answer: uniform landing points
// find them rarely, so the sample variance misses them (errors 10³ times the
// reported standard error at c = 400).
//
// The guided step draws the landing point from the defensive mixture
//   q(ω) = (1 − α)·U(ω) + α·V(ω),   V(ω) ∝ e^{z ω·n},
// V the von Mises–Fisher density around a direction n, and multiplies the
// weight by C·U(ω)/q(ω) = C / ((1 − α) + α·C·e^{z ω·n}) (the importance
// weight of the exact step: E_q[C·U/q · u] = C·mean_∂B u). For u = e^{√c n·y},
// a screened-harmonic plane wave, V is the step's zero-variance density.
//
// The direction n points from x_k to the boundary point p that maximises
// log|g(p)| − √c·|x_k − p|, the largest contribution a straight path can
// bring: for large c, u(x) ≈ max_p g(p)·e^{−√c|x − p|}. Data exp(√c e·y)
// give n = e, the plane wave's own direction; Yukawa data of a pole outside
// give the pole's direction. The search is over the boundary's primitives'
// centroids, or another geometry's sampled points (Boundary::
// GeometrySamples), in a k-d tree with each node's largest log|g| (branch
// and bound).
// Any n keeps the step unbiased; a poor one costs variance only, and the
// mixture keeps each step's factor below C/(1 − α). Guiding every screened
// step, small balls included, matters: where a walk nears a peak of the
// data, its balls are small and u still varies by e^{±z} over them.
#ifndef GRIDFREE_ESTIMATORS_SCREENED_GUIDE_H
#define GRIDFREE_ESTIMATORS_SCREENED_GUIDE_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/geometry/RayParity.h>
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sampling/SphereSampling.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

namespace gridfree
{
/// The centres of a lattice of `cells` cells a side over a closed
/// boundary's box that lie inside it (a mesh's by ray parity, another
/// geometry's as it tells: Boundary::GeometryEncloses): where
/// ScreenedGuide::Agreement is asked.
template <int DIM>
std::vector<Vec<DIM>> InteriorLattice(const Boundary<DIM>& boundary, int cells)
{
  std::vector<Vec<DIM>> inside;
  const Vec<DIM> low = boundary.BoundsMin();
  const Vec<DIM> extent = boundary.BoundsMax() - low;
  int total = 1;
  for (int k = 0; k < DIM; ++k)
  {
    total *= cells;
  }
  for (int i = 0; i < total; ++i)
  {
    Vec<DIM> x;
    int rest = i;
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = low[k] + extent[k] * ((rest % cells) + 0.5) / cells;
      rest /= cells;
    }
    if (boundary.IsMesh() ? InsideClosedMesh<DIM>(boundary, x) : boundary.GeometryEncloses(x))
    {
      inside.push_back(x);
    }
  }
  return inside;
}

/// The von Mises–Fisher density on S^{DIM−1} around n with concentration z,
/// divided by the uniform density: e^{z cos θ} / mean(e^{z cos θ}), written
/// so that it neither overflows nor underflows for z up to ~700.
template <int DIM>
double VonMisesFisherOverUniform(double z, double cosine);

template <>
inline double VonMisesFisherOverUniform<3>(double z, double cosine)
{
  // mean over S² of e^{z cos θ} = sinh z / z.
  return 2.0 * z * std::exp(z * (cosine - 1.0)) / -std::expm1(-2.0 * z);
}

template <>
inline double VonMisesFisherOverUniform<2>(double z, double cosine)
{
  // mean over S¹ of e^{z cos θ} = I0(z) = e^z · BesselI0Scaled(z).
  return std::exp(z * (cosine - 1.0)) / BesselI0Scaled(z);
}

/// A unit vector with density ∝ e^{z ω·n}.
template <int DIM>
Vec<DIM> SampleVonMisesFisher(const Vec<DIM>& n, double z, RandomStream& rng);

template <>
inline Vec<3> SampleVonMisesFisher<3>(const Vec<3>& n, double z, RandomStream& rng)
{
  // cos θ by inverting its CDF (Wood 1994 for S²), the azimuth uniform.
  const double u = rng.NextDouble();
  const double w = std::clamp(1.0 + std::log(u + (1.0 - u) * std::exp(-2.0 * z)) / z, -1.0, 1.0);
  const double phi = 2.0 * M_PI * rng.NextDouble();
  const Vec<3> t1 = n.unitOrthogonal();
  const Vec<3> t2 = n.cross(t1);
  const double s = std::sqrt(std::max(0.0, 1.0 - w * w));
  return w * n + s * (std::cos(phi) * t1 + std::sin(phi) * t2);
}

template <>
inline Vec<2> SampleVonMisesFisher<2>(const Vec<2>& n, double z, RandomStream& rng)
{
  // Best and Fisher's (1979) rejection sampler of the von Mises angle. Its
  // ρ = (τ − √(2τ))/(2z) loses every digit for small z (τ → 2); the same
  // number without the cancellation: τ − 2 = 4z²/(√(1 + 4z²) + 1) and
  // τ − √(2τ) = τ(τ − 2)/(τ + √(2τ)).
  const double root = std::sqrt(1.0 + 4.0 * z * z);
  const double tau = 1.0 + root;
  const double rho = 2.0 * z * tau / ((root + 1.0) * (tau + std::sqrt(2.0 * tau)));
  const double r = (1.0 + rho * rho) / (2.0 * rho);
  double f = 1.0;
  for (;;)
  {
    const double u1 = rng.NextDouble(), u2 = rng.NextDouble();
    const double c = std::cos(M_PI * u1);
    f = (1.0 + r * c) / (r + c);
    const double d = z * (r - f);
    if (d * (2.0 - d) - u2 > 0.0 || std::log(d / u2) + 1.0 - d >= 0.0)
    {
      break;
    }
  }
  const double cosine = std::clamp(f, -1.0, 1.0);
  const double sine = (rng.NextDouble() < 0.5 ? -1.0 : 1.0) * std::sqrt(1.0 - cosine * cosine);
  return Vec<2>(cosine * n[0] - sine * n[1], sine * n[0] + cosine * n[1]);
}

/// The guide: boundary points with log|g| and the search for the direction.
template <int DIM>
class ScreenedGuide
{
public:
  // The mixture's share α of guided landing points. A step's factor is at
  // most C/(1 − α) = 10·C: above 1 on small balls, so a guided walk's weight
  // can grow there (ErrorBarReliability's bounds on weights do not apply).
  static constexpr double Share = 0.9;

  /// Points and values from the boundary (each primitive's centroid of a
  /// mesh, another geometry's sampled points, and the largest |g| over the
  /// components there); empty where every value is 0.
  ScreenedGuide(const Boundary<DIM>& boundary, double c)
    : SqrtC(std::sqrt(c))
  {
    std::vector<double> value(static_cast<std::size_t>(std::max(1, boundary.Components())));
    auto take = [&](const ClosestPointResult<DIM>& hit) {
      boundary.Evaluate(hit, value.data());
      double largest = 0.0;
      for (double v : value)
      {
        largest = std::max(largest, std::abs(v));
      }
      if (largest > 0.0 && std::isfinite(largest))
      {
        this->Points.push_back(hit.point);
        this->LogValue.push_back(std::log(largest));
      }
    };
    for (const ClosestPointResult<DIM>& hit : boundary.GeometrySamples())
    {
      take(hit);
    }
    for (std::size_t i = 0; i < boundary.MeshPrimitives().size(); ++i)
    {
      take(boundary.PrimitiveCentroid(i));
    }
    this->Build();
  }

  bool Empty() const { return this->Points.empty(); }

  /// Whether a step whose boundary weight is C uses the guide.
  bool Guides(double boundaryWeight) const
  {
    return !this->Empty() && boundaryWeight < this->WeightCeiling;
  }

  /// Leaves uniform the steps whose √c·R is below z (default 0: every
  /// step is guided). Over such a sphere a plane wave varies by e^{±z} at
  /// most, so guiding gains little there while its search costs as much
  /// as on a large sphere; mild screening (Problem::LeadingGuide) takes
  /// most of its steps near the boundary, where spheres are small.
  void SetLeastConcentration(double z)
  {
    if constexpr (DIM == 3)
    {
      this->WeightCeiling = z > 0.0 ? z / std::sinh(z) : 1.0;
    }
    else
    {
      this->WeightCeiling = 1.0 / (std::exp(z) * BesselI0Scaled(z));
    }
  }

  /// The most a guided step's factor can be: C/(1 − α).
  static double LargestFactor(double boundaryWeight) { return boundaryWeight / (1.0 - Share); }

  /// The unit direction from x to the point with the largest
  /// log|g| − √c·|x − p|; false when x coincides with it.
  bool Direction(const Vec<DIM>& x, Vec<DIM>& n) const
  {
    double best = -std::numeric_limits<double>::infinity();
    std::size_t bestIndex = 0;
    this->Search(0, x, best, bestIndex);
    const Vec<DIM> d = this->Points[bestIndex] - x;
    const double length = d.norm();
    if (!(length > 0.0))
    {
      return false;
    }
    n = d / length;
    return true;
  }

  /// How much the guide's directions agree: the mean resultant length
  /// |mean n(x)| over `points` (0 with none). Near 1 where the largest
  /// contributions come from one side from everywhere, as for a plane wave
  /// e^{√c e·y} (whose steps' zero-variance density the guide draws), near 0
  /// where they come from all around (radial data), where leaning each step
  /// one way makes its tail heavier.
  double Agreement(const std::vector<Vec<DIM>>& points) const
  {
    Vec<DIM> sum = Vec<DIM>::Zero();
    std::size_t counted = 0;
    for (const Vec<DIM>& x : points)
    {
      Vec<DIM> n;
      if (this->Direction(x, n))
      {
        sum += n;
        ++counted;
      }
    }
    return counted ? sum.norm() / static_cast<double>(counted) : 0.0;
  }

  /// One guided step's direction and its weight factor (times C).
  template <class Green>
  Vec<DIM> Step(const Vec<DIM>& x, double radius, const Green& green, RandomStream& rng,
    double& factor) const
  {
    const double z = this->SqrtC * radius;
    Vec<DIM> n;
    if (!this->Direction(x, n))
    {
      factor = green.BoundaryWeight();
      return SampleUnitSphere<DIM>(rng);
    }
    const Vec<DIM> omega = rng.NextDouble() < Share ? SampleVonMisesFisher<DIM>(n, z, rng)
                                                    : SampleUnitSphere<DIM>(rng);
    const double ratio = VonMisesFisherOverUniform<DIM>(z, std::clamp(omega.dot(n), -1.0, 1.0));
    factor = green.BoundaryWeight() / ((1.0 - Share) + Share * ratio);
    return omega;
  }

private:
  struct Node
  {
    Vec<DIM> Min, Max;
    double LargestLog;
    std::uint32_t Begin, End; // points [Begin, End) of Order
    std::int32_t Left = -1, Right = -1;
  };

  void Build()
  {
    this->Order.resize(this->Points.size());
    std::iota(this->Order.begin(), this->Order.end(), 0u);
    if (!this->Points.empty())
    {
      this->BuildNode(0, static_cast<std::uint32_t>(this->Points.size()));
    }
  }

  std::int32_t BuildNode(std::uint32_t begin, std::uint32_t end)
  {
    Node node;
    node.Min = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
    node.Max = -node.Min;
    node.LargestLog = -std::numeric_limits<double>::infinity();
    for (std::uint32_t i = begin; i < end; ++i)
    {
      const std::uint32_t p = this->Order[i];
      node.Min = node.Min.cwiseMin(this->Points[p]);
      node.Max = node.Max.cwiseMax(this->Points[p]);
      node.LargestLog = std::max(node.LargestLog, this->LogValue[p]);
    }
    node.Begin = begin;
    node.End = end;
    const auto index = static_cast<std::int32_t>(this->Nodes.size());
    this->Nodes.push_back(node);
    if (end - begin > 8)
    {
      int axis = 0;
      (node.Max - node.Min).maxCoeff(&axis);
      const std::uint32_t middle = begin + (end - begin) / 2;
      std::nth_element(this->Order.begin() + begin, this->Order.begin() + middle,
        this->Order.begin() + end, [&](std::uint32_t a, std::uint32_t b) {
          return this->Points[a][axis] < this->Points[b][axis];
        });
      const std::int32_t left = this->BuildNode(begin, middle);
      const std::int32_t right = this->BuildNode(middle, end);
      this->Nodes[static_cast<std::size_t>(index)].Left = left;
      this->Nodes[static_cast<std::size_t>(index)].Right = right;
    }
    return index;
  }

  double Bound(const Node& node, const Vec<DIM>& x) const
  {
    const Vec<DIM> outside = (node.Min - x).cwiseMax(x - node.Max).cwiseMax(0.0);
    return node.LargestLog - this->SqrtC * outside.norm();
  }

  void Search(std::int32_t index, const Vec<DIM>& x, double& best, std::size_t& bestIndex) const
  {
    const Node& node = this->Nodes[static_cast<std::size_t>(index)];
    if (node.Left < 0)
    {
      for (std::uint32_t i = node.Begin; i < node.End; ++i)
      {
        const std::uint32_t p = this->Order[i];
        const double score = this->LogValue[p] - this->SqrtC * (this->Points[p] - x).norm();
        if (score > best)
        {
          best = score;
          bestIndex = p;
        }
      }
      return;
    }
    const Node& left = this->Nodes[static_cast<std::size_t>(node.Left)];
    const Node& right = this->Nodes[static_cast<std::size_t>(node.Right)];
    const double boundLeft = this->Bound(left, x), boundRight = this->Bound(right, x);
    const bool leftFirst = boundLeft >= boundRight;
    const std::int32_t first = leftFirst ? node.Left : node.Right;
    const std::int32_t second = leftFirst ? node.Right : node.Left;
    if (std::max(boundLeft, boundRight) > best)
    {
      this->Search(first, x, best, bestIndex);
    }
    if (std::min(boundLeft, boundRight) > best)
    {
      this->Search(second, x, best, bestIndex);
    }
  }

  double SqrtC;
  double WeightCeiling = 1.0; // steps with C below it are guided
  std::vector<Vec<DIM>> Points;
  std::vector<double> LogValue;
  std::vector<std::uint32_t> Order;
  std::vector<Node> Nodes;
};
} // namespace gridfree

#endif
