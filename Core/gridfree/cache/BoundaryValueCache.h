// Boundary value caching (Miller, Sawhney, Crane and Gkioulekas, SIGGRAPH
// 2023) for an interior Dirichlet problem on a closed, consistently
// oriented mesh: walks run once, at cache points on the boundary, and every
// probe point is then answered by Green's representation formula, with no
// walks of its own.
//
// For Δu − c·u = f in Ω (c = 0: Laplace, Poisson; WalkOnSpheres.h's
// convention), with the free-space Green's function G of −Δ + c (3D:
// e^{−√c r}/(4π r); 2D: K0(√c r)/(2π), −ln r/(2π) for c = 0) and
// P = ∂G/∂n_z its derivative along the outward normal at the boundary point
// z, every x inside Ω has
//
//   u(x) = ∫_∂Ω [ G(x, z) ∂u/∂n(z) − P(x, z) g(z) ] dz − ∫_Ω G(x, y) f(y) dy,
//
// and ∇u(x) the same with ∇ₓG and ∇ₓP. The volume integral takes two
// points in each cell of a grid over the boundary's box (those outside Ω
// count zero), stratified as the boundary's.
//
// g is known; ∂u/∂n is not. The cache cuts the boundary into K = M/2
// strata of equal area (triangles in Morton order of their centroids, so a
// stratum is a compact patch), draws two points z_j uniformly in each (a
// seeded stream per point: the same cache for any thread count) and
// estimates ∂u/∂n(z_j) as ∇u·n at y_j = z_j − δ n_j, just inside, by the
// problem's own gradient walks (one batch for all of them). A probe point x
// then takes the stratified mean of the terms
//
//   T_j(x) = A [ G(x, z_j) q_j − P(x, z_j) g(z_j) ],   q_j = ∇̂u(y_j)·n_j,
//
// u(x) ≈ (1/K) Σ_k (T_2k + T_2k+1)/2, whose variance is estimated without
// bias by (1/K²) Σ_k (T_2k − T_2k+1)²/4: the two draws of a stratum, and
// their walks, are independent. The mean is unbiased but for the offset
// (∂u/∂n at depth δ rather than on the boundary), and the error bar is
// calibrated at every point although nearby points share the cache (their
// errors are correlated: a smooth picture whose error does not average out
// along a slice). Stratifying removes most of the spread that the random
// positions of independent draws add.
//
// The kernels grow like 1/r² (3D) as x nears the boundary, and with them
// the variance: points closer than the shell distance are not answered here
// (InShell), but by pointwise walks, which are cheapest there.
#ifndef GRIDFREE_CACHE_BOUNDARY_VALUE_CACHE_H
#define GRIDFREE_CACHE_BOUNDARY_VALUE_CACHE_H

#include <gridfree/cache/CacheProblemChecks.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/problem/Problem.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/statistics/RunningSumsCache.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gridfree
{
struct BoundaryCacheSettings
{
  std::size_t CachePoints = 4096; // two per stratum: rounded up to even
  // Points of the volume integral of a source (two per cell of a grid over
  // the boundary's box).
  std::size_t VolumePoints = 8192;
  int WalksPerCachePoint = 64;
  // How far inside the boundary the normal derivative is estimated, and
  // the shell whose points the cache does not answer: fractions of the
  // boundary's bounding-box diagonal.
  double Offset = 1e-2;
  double ShellDistance = 0.05;
  std::uint64_t Seed = 0;
  int Threads = 0; // 0: all
};

// One answer of the cache per probe point: u (and ∇u when asked) with the
// variances of their means; NaN, with Outside 1, for points outside, and
// with InShell 1 for points inside closer to the boundary than the shell
// distance.
// What a cache answers besides the value (a bool asks for the gradient).
struct CacheDerivatives
{
  CacheDerivatives(bool gradient = false) // NOLINT: implicit on purpose
    : Gradient(gradient)
  {
  }
  bool Gradient = false;
  bool Hessian = false;
  // Z·∇u along Direction (its first DIM components), with its variance.
  bool Directional = false;
  std::array<double, 3> Direction = { 1.0, 0.0, 0.0 };
  // ∇·u and ∇×u of a 3-component solution (∂/∂z = 0 in 2D).
  bool DivergenceCurl = false;
};


struct CacheEvaluation
{
  std::vector<double> Value, ValueVariance;       // points × components
  std::vector<double> Gradient, GradientVariance; // points × components × DIM
  std::vector<double> Hessian, HessianVariance;   // points × components × DIM × DIM
  std::vector<double> Directional, DirectionalVariance; // points × components
  std::vector<double> Divergence, DivergenceVariance;   // points
  std::vector<double> Curl, CurlVariance;               // points × 3
  std::vector<unsigned char> InShell, Outside;

  // `n` points of `nc` components, every answer NaN, no flags.
  void Reset(std::size_t n, int nc, int dim, const CacheDerivatives& want)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::size_t values = n * static_cast<std::size_t>(nc);
    const std::size_t gradients = want.Gradient ? values * static_cast<std::size_t>(dim) : 0;
    const std::size_t hessians = want.Hessian ? values * static_cast<std::size_t>(dim * dim) : 0;
    this->Value.assign(values, nan);
    this->ValueVariance.assign(values, nan);
    this->Gradient.assign(gradients, nan);
    this->GradientVariance.assign(gradients, nan);
    this->Hessian.assign(hessians, nan);
    this->HessianVariance.assign(hessians, nan);
    this->Directional.assign(want.Directional ? values : 0, nan);
    this->DirectionalVariance.assign(want.Directional ? values : 0, nan);
    this->Divergence.assign(want.DivergenceCurl ? n : 0, nan);
    this->DivergenceVariance.assign(want.DivergenceCurl ? n : 0, nan);
    this->Curl.assign(want.DivergenceCurl ? 3 * n : 0, nan);
    this->CurlVariance.assign(want.DivergenceCurl ? 3 * n : 0, nan);
    this->InShell.assign(n, 0);
    this->Outside.assign(n, 0);
  }
};

namespace detail
{
// Spreads the low 21 (3D) or 32 (2D) bits of v so that DIM coordinates
// interleave.
inline std::uint64_t SpreadBits(std::uint64_t v, int dim)
{
  std::uint64_t r = 0;
  const int bits = dim == 3 ? 21 : 32;
  for (int b = 0; b < bits; ++b)
  {
    r |= ((v >> b) & 1ULL) << (dim * b);
  }
  return r;
}

// The primitives sorted by the Morton code of their centroids in the box
// (ties by index): neighbours in the order are neighbours in space.
template <int DIM, class Primitives>
std::vector<std::size_t> MortonOrder(const std::vector<Vec<DIM>>& v, const Primitives& primitives,
  const Vec<DIM>& lo, const Vec<DIM>& hi)
{
  const int bits = DIM == 3 ? 21 : 32;
  const double cells = static_cast<double>((1ULL << bits) - 1);
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(primitives.size());
  for (std::size_t p = 0; p < primitives.size(); ++p)
  {
    Vec<DIM> c = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      c += v[static_cast<std::size_t>(primitives[p][static_cast<std::size_t>(k)])] / DIM;
    }
    std::uint64_t code = 0;
    for (int a = 0; a < DIM; ++a)
    {
      const double extent = hi[a] - lo[a];
      const double t = extent > 0.0 ? std::clamp((c[a] - lo[a]) / extent, 0.0, 1.0) : 0.0;
      code |= SpreadBits(static_cast<std::uint64_t>(t * cells), DIM) << a;
    }
    keys[p] = { code, p };
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::size_t> order(primitives.size());
  for (std::size_t o = 0; o < keys.size(); ++o)
  {
    order[o] = keys[o].second;
  }
  return order;
}
} // namespace detail

template <int DIM>
class BoundaryValueCache
{
public:
  // Builds the cache: draws the points, estimates ∂u/∂n there. Throws
  // std::invalid_argument for what it cannot answer (not Laplace's
  // equation, mixed conditions, an implicit boundary, an open or
  // unoriented mesh). `progress` as in Problem::Estimate; an aborted build
  // leaves the cache incomplete (Complete() false), answering nothing.
  BoundaryValueCache(const Problem<DIM>& problem, const BoundaryCacheSettings& settings,
    const BatchProgressCallback& progress = BatchProgressCallback())
    : Shape(problem.SharedBoundary())
    , Settings(settings)
  {
    const Boundary<DIM>& boundary = *this->Shape;
    const Equation equation = problem.Settings().Problem;
    if (equation == Equation::Biharmonic)
    {
      throw std::invalid_argument("the boundary cache answers Laplace's, Poisson's and the "
                                  "screened Poisson equation only (yet)");
    }
    RequireDirichletWithVolumeSources<DIM>(problem, "the boundary cache");
    const SourceSet<DIM>* sources = problem.GetSources();
    this->Screening = equation == Equation::ScreenedPoisson
      ? std::sqrt(problem.Settings().ScreeningCoefficient)
      : 0.0;
    if (!boundary.IsMesh() || boundary.MeshPrimitives().empty())
    {
      throw std::invalid_argument("the boundary cache needs a mesh boundary");
    }
    if (settings.CachePoints < 2 || settings.WalksPerCachePoint < 2)
    {
      throw std::invalid_argument("the boundary cache needs at least 2 points and 2 walks each");
    }
    this->Components = boundary.Components();
    this->BuildAreaTable();
    this->DrawPoints();
    if (equation != Equation::Laplace && sources && sources->MakeVolume)
    {
      this->DrawVolumePoints(*sources->MakeVolume(boundary.Diagonal()));
    }

    this->RunWalks(problem, settings.WalksPerCachePoint, progress);
  }

  // Continues every cache point's normal-derivative walks up to
  // `walksPerCachePoint` (kept running sums: the cache then has the bits of
  // one built with that many walks). `problem` must be the one the cache
  // was built from (the same boundary, equation and sources). Fewer walks
  // than it holds change nothing; false when aborted (the cache then
  // answers nothing until a complete Refine).
  bool Refine(const Problem<DIM>& problem, int walksPerCachePoint,
    const BatchProgressCallback& progress = BatchProgressCallback())
  {
    if (walksPerCachePoint > this->WalksPerPoint || !this->CompleteBuild)
    {
      this->RunWalks(problem, std::max(walksPerCachePoint, this->WalksPerPoint), progress);
    }
    return this->CompleteBuild;
  }

  bool Complete() const { return this->CompleteBuild; }
  std::size_t Size() const { return this->Points.size(); }
  // Walks run by the last build or Refine (walks continued from kept sums
  // excluded), and the walks each cache point holds.
  std::uint64_t Walks() const { return this->WalksRun; }
  int WalksPerCachePoint() const { return this->WalksPerPoint; }
  int SolutionComponents() const { return this->Components; }
  double ShellDistance() const { return this->Settings.ShellDistance * this->Shape->Diagonal(); }

  // The cache points, their outward normals, boundary values and estimated
  // normal derivatives (components per point).
  const std::vector<Vec<DIM>>& CachePoints() const { return this->Points; }
  const std::vector<Vec<DIM>>& CacheNormals() const { return this->Normals; }
  const std::vector<double>& CacheValues() const { return this->Values; }
  const std::vector<double>& CacheNormalDerivatives() const { return this->NormalDerivatives; }
  double BoundaryArea() const { return this->Area; }

  // The same cache with other normal derivatives (components per point):
  // with exact ones, what is left of the error is the positions' (a
  // diagnostic of the benchmark and the tests).
  BoundaryValueCache WithNormalDerivatives(std::vector<double> derivatives) const
  {
    if (derivatives.size() != this->NormalDerivatives.size())
    {
      throw std::invalid_argument("normal derivatives: one per cache point and component");
    }
    BoundaryValueCache other = *this;
    other.NormalDerivatives = std::move(derivatives);
    return other;
  }

  // Answers every point (the first DIM of its coordinates), each point's
  // terms summed in cache order: the same bits for any thread count.
  void Evaluate(const std::vector<std::array<double, 3>>& at, bool gradient,
    CacheEvaluation& out) const
  {
    const std::size_t n = at.size();
    out.Reset(n, this->Components, DIM, gradient);
    if (!this->CompleteBuild)
    {
      return;
    }
    const double shell = this->ShellDistance();
    ParallelForWithProgress(
      n, this->Settings.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
        for (std::size_t i = begin; i < end; ++i)
        {
          Vec<DIM> x;
          bool finite = true;
          for (int k = 0; k < DIM; ++k)
          {
            x[k] = at[i][static_cast<std::size_t>(k)];
            finite = finite && std::isfinite(x[k]);
          }
          if (!finite)
          {
            continue;
          }
          const ClosestPointResult<DIM> hit = this->Shape->ClosestPoint(x);
          if (OutsideClosedMesh<DIM>(*this->Shape, this->Orientation, x, hit))
          {
            out.Outside[i] = 1;
            continue;
          }
          if (hit.distance < shell)
          {
            out.InShell[i] = 1;
            continue;
          }
          this->EvaluatePoint(x, gradient, i, out);
        }
      },
      [](double) { return true; }, 0.1, 16);
  }

private:
  // ∇u just inside each cache point, y = z − δn, by the problem's gradient
  // walks (one batch for all of them, continued from the kept sums), and
  // the normal derivatives q = ∇u(y)·n from their means.
  void RunWalks(const Problem<DIM>& problem, int walks, const BatchProgressCallback& progress)
  {
    std::vector<std::array<double, 3>> inside(this->Points.size(), { 0.0, 0.0, 0.0 });
    const double delta = this->Settings.Offset * this->Shape->Diagonal();
    for (std::size_t j = 0; j < this->Points.size(); ++j)
    {
      const Vec<DIM> y = this->Points[j] - delta * this->Normals[j];
      for (int k = 0; k < DIM; ++k)
      {
        inside[j][static_cast<std::size_t>(k)] = y[k];
      }
    }
    BatchRequest request;
    request.WalksPerPoint = walks;
    request.Seed = this->Settings.Seed;
    request.Threads = this->Settings.Threads;
    request.AddPolynomialShift = false; // the cache holds w = u − P (PolynomialShift.h)
    request.Derivatives.Gradient = true;
    const BatchEstimates walked = problem.EstimateAll(inside, request, progress, &this->Kept);
    this->CompleteBuild = walked.Summary.Completed;
    this->WalksRun = walked.Summary.WalksRun;
    this->WalksPerPoint = this->CompleteBuild ? walks : 0;
    const int gradient = walked.Summary.Layout.Gradient;
    this->NormalDerivatives.assign(this->Points.size() * this->Components, 0.0);
    for (std::size_t j = 0; j < this->Points.size(); ++j)
    {
      for (int c = 0; c < this->Components; ++c)
      {
        double q = 0.0;
        for (int a = 0; a < DIM; ++a)
        {
          q += walked.Mean(j, gradient + c * DIM + a) * this->Normals[j][a];
        }
        this->NormalDerivatives[j * this->Components + c] = q;
      }
    }
  }

  // Triangle (segment) areas and their running sums in Morton order, for
  // drawing points by strata; the orientation that makes the primitives'
  // normals point outward.
  void BuildAreaTable()
  {
    const std::vector<Vec<DIM>>& v = this->Shape->MeshVertices();
    const auto& primitives = this->Shape->MeshPrimitives();
    this->Orientation = OutwardOrientation<DIM>(*this->Shape);
    this->Order = detail::MortonOrder<DIM>(v, primitives, this->Shape->BoundsMin(), this->Shape->BoundsMax());
    this->CumulativeArea.resize(primitives.size());
    double total = 0.0;
    for (std::size_t o = 0; o < primitives.size(); ++o)
    {
      const auto& ids = primitives[this->Order[o]];
      if constexpr (DIM == 3)
      {
        const Vec<3>& a = v[static_cast<std::size_t>(ids[0])];
        total += 0.5 *
          (v[static_cast<std::size_t>(ids[1])] - a).cross(v[static_cast<std::size_t>(ids[2])] - a).norm();
      }
      else
      {
        total += (v[static_cast<std::size_t>(ids[1])] - v[static_cast<std::size_t>(ids[0])]).norm();
      }
      this->CumulativeArea[o] = total;
    }
    this->Area = total;
  }

  // Two points uniform over each of the M/2 strata of equal area, each
  // from its own seeded stream.
  void DrawPoints()
  {
    const std::vector<Vec<DIM>>& v = this->Shape->MeshVertices();
    const auto& primitives = this->Shape->MeshPrimitives();
    const std::size_t m = 2 * ((this->Settings.CachePoints + 1) / 2);
    const double stratum = this->Area / static_cast<double>(m / 2);
    this->Points.resize(m);
    this->Normals.resize(m);
    this->Values.resize(m * this->Components);
    const std::uint64_t key = MixBits(this->Settings.Seed ^ 0x9e3779b97f4a7c15ULL);
    std::vector<double> g(static_cast<std::size_t>(this->Components));
    for (std::size_t j = 0; j < m; ++j)
    {
      RandomStream random(key, j);
      const double pick = (static_cast<double>(j / 2) + random.NextDouble()) * stratum;
      const std::size_t p = this->Order[std::min<std::size_t>(
        static_cast<std::size_t>(
          std::upper_bound(this->CumulativeArea.begin(), this->CumulativeArea.end(), pick) -
          this->CumulativeArea.begin()),
        primitives.size() - 1)];
      const auto& ids = primitives[p];
      ClosestPointResult<DIM> hit;
      hit.primitive = static_cast<std::int64_t>(p);
      if constexpr (DIM == 3)
      {
        // Uniform on the triangle: barycentric (1 − √u, √u (1 − w), √u w).
        const double su = std::sqrt(random.NextDouble());
        const double w = random.NextDouble();
        hit.barycentric = Vec<3>(1.0 - su, su * (1.0 - w), su * w);
      }
      else
      {
        const double t = random.NextDouble();
        hit.barycentric = Vec<2>(1.0 - t, t);
      }
      hit.point = Vec<DIM>::Zero();
      for (int k = 0; k < DIM; ++k)
      {
        hit.point += hit.barycentric[k] * v[static_cast<std::size_t>(ids[static_cast<std::size_t>(k)])];
      }
      hit.distance = 0.0;
      this->Points[j] = hit.point;
      this->Normals[j] = static_cast<double>(this->Orientation) * SimplexUnitNormal<DIM>(v, ids);
      this->Shape->Evaluate(hit, g.data());
      for (int c = 0; c < this->Components; ++c)
      {
        this->Values[j * this->Components + c] = g[static_cast<std::size_t>(c)];
      }
    }
  }

  // The stratified mean of the terms T_j(x) and of their x-gradients, with
  // the variances of those means from each stratum's two draws, summed in
  // cache order.
  void EvaluatePoint(const Vec<DIM>& x, bool gradient, std::size_t i, CacheEvaluation& out) const
  {
    const int nc = this->Components;
    const std::size_t m = this->Points.size();
    std::vector<double> sum(static_cast<std::size_t>(nc * (1 + DIM)), 0.0);
    std::vector<double> squares(sum.size(), 0.0);
    std::vector<double> term(sum.size(), 0.0), first(sum.size(), 0.0);
    for (std::size_t j = 0; j < m; ++j)
    {
      const Vec<DIM> d = x - this->Points[j]; // x − z
      const double r2 = d.squaredNorm();
      const double r = std::sqrt(r2);
      const Vec<DIM>& n = this->Normals[j];
      const double dn = n.dot(d);
      // G, P = ∂G/∂n_z = −G′ (n·d)/r, and their x-gradients
      // ∇G = G′ d/r, ∇P = −(G″ − G′/r)(n·d) d/r² − G′ n/r.
      const Kernel k = this->KernelAt(r);
      const double G = k.G;
      const double P = -k.G1 * dn / r;
      const Vec<DIM> dG = (k.G1 / r) * d;
      const Vec<DIM> dP = (-(k.G2 - k.G1 / r) * dn / r2) * d - (k.G1 / r) * n;
      for (int c = 0; c < nc; ++c)
      {
        const double q = this->NormalDerivatives[j * nc + c];
        const double g = this->Values[j * nc + c];
        term[static_cast<std::size_t>(c)] = this->Area * (G * q - P * g);
        for (int a = 0; a < DIM && gradient; ++a)
        {
          term[static_cast<std::size_t>(nc + c * DIM + a)] = this->Area * (dG[a] * q - dP[a] * g);
        }
      }
      if (j % 2 == 0)
      {
        first = term;
        continue;
      }
      for (std::size_t s = 0; s < term.size(); ++s)
      {
        sum[s] += 0.5 * (first[s] + term[s]);
        squares[s] += 0.25 * (first[s] - term[s]) * (first[s] - term[s]);
      }
    }
    const double strata = static_cast<double>(m / 2);
    // The source's volume integral, −∫ G f, stratified over its cells: the
    // cells' sums and variances added to the boundary's (independent draws).
    std::vector<double> volume(sum.size(), 0.0), volumeSquares(sum.size(), 0.0);
    for (std::size_t j = 0; j < this->VolumeSamples.size(); ++j)
    {
      const Vec<DIM> d = x - this->VolumeSamples[j];
      const double r = d.norm();
      const Kernel k = this->KernelAt(r);
      for (int c = 0; c < nc; ++c)
      {
        const double f = this->VolumeValues[j * nc + c];
        term[static_cast<std::size_t>(c)] = -this->CellVolume * k.G * f;
        for (int a = 0; a < DIM && gradient; ++a)
        {
          term[static_cast<std::size_t>(nc + c * DIM + a)] = -this->CellVolume * k.G1 * d[a] / r * f;
        }
      }
      if (j % 2 == 0)
      {
        first = term;
        continue;
      }
      for (std::size_t s = 0; s < term.size(); ++s)
      {
        volume[s] += 0.5 * (first[s] + term[s]);
        volumeSquares[s] += 0.25 * (first[s] - term[s]) * (first[s] - term[s]);
      }
    }
    for (std::size_t s = 0; s < sum.size(); ++s)
    {
      // In units of the boundary's strata: the mean is sum / strata.
      sum[s] += volume[s] * strata;
      squares[s] += volumeSquares[s] * strata * strata;
    }
    for (int c = 0; c < nc; ++c)
    {
      out.Value[i * nc + c] = sum[static_cast<std::size_t>(c)] / strata;
      out.ValueVariance[i * nc + c] = squares[static_cast<std::size_t>(c)] / (strata * strata);
      for (int a = 0; a < DIM && gradient; ++a)
      {
        const std::size_t s = static_cast<std::size_t>(nc + c * DIM + a);
        out.Gradient[(i * nc + c) * DIM + a] = sum[s] / strata;
        out.GradientVariance[(i * nc + c) * DIM + a] = squares[s] / (strata * strata);
      }
    }
  }

  // The free-space Green's function of −Δ + s² at distance r, and its first
  // two derivatives in r.
  struct Kernel
  {
    double G, G1, G2;
  };
  Kernel KernelAt(double r) const
  {
    constexpr double kPi = 3.14159265358979323846;
    const double s = this->Screening;
    if constexpr (DIM == 3)
    {
      const double e = s > 0.0 ? std::exp(-s * r) : 1.0;
      const double G = e / (4.0 * kPi * r);
      const double G1 = -G * (1.0 + s * r) / r;
      const double G2 = G * (2.0 + 2.0 * s * r + s * s * r * r) / (r * r);
      return { G, G1, G2 };
    }
    else
    {
      if (!(s > 0.0))
      {
        return { -std::log(r) / (2.0 * kPi), -1.0 / (2.0 * kPi * r), 1.0 / (2.0 * kPi * r * r) };
      }
      // K0′(x) = −K1(x), K0″(x) = K0(x) + K1(x)/x, with the scaled forms.
      const double x = s * r;
      const double e = std::exp(-x);
      const double k0 = BesselK0Scaled(x) * e;
      const double k1 = BesselK1Scaled(x) * e;
      return { k0 / (2.0 * kPi), -s * k1 / (2.0 * kPi), s * s * (k0 + k1 / x) / (2.0 * kPi) };
    }
  }

  // Two points uniform in each cell of a grid of about VolumePoints/2 cells
  // over the boundary's box, with the source there (0 outside Ω).
  void DrawVolumePoints(VolumeSource<DIM>& source)
  {
    const Boundary<DIM>& boundary = *this->Shape;
    const Vec<DIM> lo = boundary.BoundsMin();
    const Vec<DIM> extent = boundary.BoundsMax() - lo;
    const double cells = static_cast<double>(std::max<std::size_t>(1, this->Settings.VolumePoints / 2));
    double boxVolume = 1.0;
    for (int a = 0; a < DIM; ++a)
    {
      boxVolume *= extent[a];
    }
    const double side = std::pow(boxVolume / cells, 1.0 / DIM);
    std::array<std::int64_t, DIM> counts;
    std::size_t total = 1;
    Vec<DIM> cell;
    for (int a = 0; a < DIM; ++a)
    {
      counts[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(extent[a] / side)));
      cell[a] = extent[a] / static_cast<double>(counts[a]);
      total *= static_cast<std::size_t>(counts[a]);
    }
    this->CellVolume = 1.0;
    for (int a = 0; a < DIM; ++a)
    {
      this->CellVolume *= cell[a];
    }
    const std::uint64_t key = MixBits(this->Settings.Seed ^ 0x6a09e667f3bcc909ULL);
    std::vector<double> f(static_cast<std::size_t>(this->Components));
    this->VolumeSamples.resize(2 * total);
    this->VolumeValues.assign(2 * total * this->Components, 0.0);
    for (std::size_t j = 0; j < 2 * total; ++j)
    {
      RandomStream random(key, j);
      std::size_t index = j / 2;
      Vec<DIM> y;
      for (int a = 0; a < DIM; ++a)
      {
        const auto at = static_cast<std::int64_t>(index % static_cast<std::size_t>(counts[a]));
        index /= static_cast<std::size_t>(counts[a]);
        y[a] = lo[a] + (static_cast<double>(at) + random.NextDouble()) * cell[a];
      }
      this->VolumeSamples[j] = y;
      const ClosestPointResult<DIM> hit = boundary.ClosestPoint(y);
      if (OutsideClosedMesh<DIM>(boundary, this->Orientation, y, hit) || hit.distance <= 0.0)
      {
        continue; // outside Ω: no source
      }
      source.Evaluate(y, f.data());
      for (int c = 0; c < this->Components; ++c)
      {
        this->VolumeValues[j * this->Components + c] = f[static_cast<std::size_t>(c)];
      }
    }
  }

  std::shared_ptr<const Boundary<DIM>> Shape;
  BoundaryCacheSettings Settings;
  double Screening = 0.0; // √c
  std::vector<Vec<DIM>> VolumeSamples;
  std::vector<double> VolumeValues;
  double CellVolume = 0.0;
  int Components = 1;
  double Area = 0.0;
  int Orientation = 1;
  std::vector<std::size_t> Order; // primitives in Morton order
  std::vector<double> CumulativeArea;
  std::vector<Vec<DIM>> Points, Normals;
  std::vector<double> Values, NormalDerivatives;
  bool CompleteBuild = false;
  std::uint64_t WalksRun = 0;
  int WalksPerPoint = 0;
  RunningSumsCache Kept; // the walks' sums, for Refine
};
} // namespace gridfree

#endif
