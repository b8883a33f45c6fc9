// Fits the polynomial control variate (PolynomialShift.h) of a Dirichlet
// problem on a closed mesh, and makes the problem of w = u − P.
//
// The samples: g at the mesh's vertices (at most kBoundarySamples of them,
// evenly strided) and f at kSourceSamples points drawn uniformly in the
// boundary's box and kept when inside the closed mesh (a fixed seed: the
// same data give the same P, on any thread count). The source rows weigh
// mean(d²), d a sample's distance to the boundary: an error δ of the source
// moves u by about δ·d² in a domain of that thickness (a ball of radius R:
// u(centre) = δ R²/(2·DIM)). On the CT workflow (degree 6) this weight left
// the walks 11 °C² of spread where a third of it left 18 and ten times 15.
#ifndef GRIDFREE_PROBLEM_POLYNOMIAL_SHIFT_FIT_H
#define GRIDFREE_PROBLEM_POLYNOMIAL_SHIFT_FIT_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/cache/BoundaryValueCache.h>
#include <gridfree/cache/CacheProblemChecks.h>
#include <gridfree/geometry/RayParity.h>
#include <gridfree/problem/Problem.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sources/PolynomialShift.h>
#include <gridfree/sources/ShiftedSource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace gridfree
{
struct PolynomialShiftSamples
{
  static constexpr std::size_t kBoundarySamples = 20000;
  static constexpr std::size_t kSourceSamples = 8000;
  // Draws before giving up on a domain that fills little of its box.
  static constexpr std::size_t kMostDraws = 400000;
};

// P of total degree `degree` for Δu − c·u = f (f from `source`, null for
// none) with u = g on the closed mesh `boundary` (one component, one-sided
// values). Throws std::invalid_argument when the boundary is not a closed
// mesh or the samples do not determine P.
template <int DIM>
std::shared_ptr<PolynomialShift<DIM>> FitPolynomialShift(const Boundary<DIM>& boundary,
  VolumeSource<DIM>* source, double screening, int degree)
{
  if (!boundary.IsMesh() || boundary.Components() != 1 || boundary.IsTwoSided())
  {
    throw std::invalid_argument("the polynomial control variate needs a closed mesh boundary "
                                "with one-sided values of one component");
  }
  try
  {
    (void)OutwardOrientation<DIM>(boundary); // a mesh enclosing a volume
  }
  catch (const std::invalid_argument&)
  {
    throw std::invalid_argument("the polynomial control variate needs a closed mesh enclosing "
                                "a volume (the points it answers are those inside)");
  }
  auto shift =
    std::make_shared<PolynomialShift<DIM>>(degree, boundary.BoundsMin(), boundary.BoundsMax());

  std::vector<Vec<DIM>> onBoundary, inside;
  std::vector<double> g, f;
  const std::vector<Vec<DIM>>& vertices = boundary.MeshVertices();
  const std::size_t stride =
    std::max<std::size_t>(1, vertices.size() / PolynomialShiftSamples::kBoundarySamples);
  for (std::size_t i = 0; i < vertices.size(); i += stride)
  {
    const auto hit = boundary.ClosestPoint(vertices[i]);
    double value = 0.0;
    boundary.Evaluate(hit, &value);
    onBoundary.push_back(hit.point);
    g.push_back(value);
  }

  RandomStream rng(0x9e3779b97f4a7c15ULL, static_cast<std::uint64_t>(degree));
  const Vec<DIM> low = boundary.BoundsMin();
  const Vec<DIM> size = boundary.BoundsMax() - low;
  double meanD2 = 0.0;
  for (std::size_t draw = 0; draw < PolynomialShiftSamples::kMostDraws &&
       inside.size() < PolynomialShiftSamples::kSourceSamples;
       ++draw)
  {
    Vec<DIM> y;
    for (int i = 0; i < DIM; ++i)
    {
      y[i] = low[i] + size[i] * rng.NextDouble();
    }
    const auto hit = boundary.ClosestPoint(y);
    if (hit.primitive < 0 || !(hit.distance > 0.0) || !InsideClosedMesh<DIM>(boundary, y))
    {
      continue;
    }
    double value = 0.0;
    if (source)
    {
      source->Evaluate(y, &value);
    }
    inside.push_back(y);
    f.push_back(value);
    meanD2 += hit.distance * hit.distance;
  }
  if (inside.empty())
  {
    throw std::invalid_argument("the polynomial control variate found no point inside the "
                                "boundary to fit the source at");
  }
  meanD2 /= static_cast<double>(inside.size());
  if (!shift->Fit(onBoundary, g, inside, f, screening, meanD2))
  {
    throw std::invalid_argument("the polynomial control variate could not be fitted (too few "
                                "boundary samples for degree " +
      std::to_string(degree) + ", or values that are not finite)");
  }
  return shift;
}

// The problem of w = u − P for the Dirichlet problem (boundary, settings,
// sources): a copy of the boundary that reads g − P, the source
// f − (ΔP − c·P), and P set on the problem, which adds it back to every
// answer (Problem::SetPolynomialShift). Volume sources only.
template <int DIM>
std::shared_ptr<Problem<DIM>> MakeShiftedProblem(const Boundary<DIM>& boundary,
  const WalkSettings& settings, const SourceSet<DIM>* sources, int degree)
{
  if (settings.Problem != Equation::Laplace && settings.Problem != Equation::Poisson &&
    settings.Problem != Equation::ScreenedPoisson)
  {
    throw std::invalid_argument("the polynomial control variate takes the Laplace, Poisson and "
                                "screened Poisson equations");
  }
  const double screening =
    settings.Problem == Equation::ScreenedPoisson ? settings.ScreeningCoefficient : 0.0;
  const bool withSources = settings.Problem != Equation::Laplace && sources && sources->MakeVolume;
  std::unique_ptr<VolumeSource<DIM>> f =
    withSources ? sources->MakeVolume(boundary.Diagonal()) : nullptr;
  std::shared_ptr<const PolynomialShift<DIM>> shift =
    FitPolynomialShift<DIM>(boundary, f.get(), screening, degree);

  auto shifted = std::make_shared<Boundary<DIM>>(boundary);
  shifted->SetValueShift(shift);
  // The Laplace equation of w has a source, −ΔP: solve it as Poisson.
  WalkSettings w = settings;
  if (w.Problem == Equation::Laplace)
  {
    w.Problem = Equation::Poisson;
  }
  auto problem = std::make_shared<Problem<DIM>>(
    shifted, w, ShiftedSources<DIM>(withSources ? sources : nullptr, shift));
  problem->SetPolynomialShift(shift);
  return problem;
}

// Adds P's part to a cache's answers of w (CacheEvaluation: NaN stays NaN);
// `direction` is the directional derivative's. An answered point that ray
// parity finds outside `boundary` (the closed mesh P was fitted in) becomes
// NaN and Outside, as Problem::Estimate leaves such points: the caches'
// own inside test reads the closest triangle's side, which a contour's
// stray flipped triangle can turn, and outside, w grows like P.
template <int DIM>
void AddShiftToCacheAnswers(const PolynomialShift<DIM>& shift, const Boundary<DIM>& boundary,
  const std::vector<std::array<double, 3>>& points, const std::array<double, 3>& direction,
  CacheEvaluation& e)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    Vec<DIM> x;
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = points[i][static_cast<std::size_t>(k)];
    }
    if (!x.allFinite() || !std::isfinite(e.Value[i]))
    {
      continue;
    }
    if (!InsideClosedMesh<DIM>(boundary, x))
    {
      for (std::vector<double>* a : { &e.Value, &e.ValueVariance, &e.Gradient, &e.GradientVariance,
             &e.Hessian, &e.HessianVariance, &e.Directional, &e.DirectionalVariance })
      {
        if (a->empty())
        {
          continue;
        }
        const std::size_t per = a->size() / points.size();
        std::fill(a->begin() + static_cast<std::ptrdiff_t>(i * per),
          a->begin() + static_cast<std::ptrdiff_t>((i + 1) * per), nan);
      }
      e.Outside[i] = 1;
      continue;
    }
    e.Value[i] += shift.Value(x);
    const Vec<DIM> g = shift.Gradient(x);
    for (int k = 0; k < DIM && !e.Gradient.empty(); ++k)
    {
      e.Gradient[i * DIM + static_cast<std::size_t>(k)] += g[k];
    }
    if (!e.Directional.empty())
    {
      double dz = 0.0;
      for (int k = 0; k < DIM; ++k)
      {
        dz += direction[static_cast<std::size_t>(k)] * g[k];
      }
      e.Directional[i] += dz;
    }
    if (!e.Hessian.empty())
    {
      const Mat<DIM> h = shift.Hessian(x);
      for (int a = 0; a < DIM; ++a)
      {
        for (int b = 0; b < DIM; ++b)
        {
          e.Hessian[(i * DIM + static_cast<std::size_t>(a)) * DIM + static_cast<std::size_t>(b)] +=
            h(a, b);
        }
      }
    }
  }
}
} // namespace gridfree

#endif
