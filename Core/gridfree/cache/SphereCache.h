// A solution cache on spheres inside the domain, shared by every probe
// point: walks start from sample points on a sphere ∂B(c, R) that lies in
// Ω, once, and every point x of the sphere's inner part |x − c| ≤ ρR is
// answered from them by Poisson's integral formula, with no walks of its
// own. For Δu = f (Laplace: f = 0; WalkOnSpheres.h's convention),
//
//   u(x) = ∫_∂B P(x, s) u(s) ds − ∫_B G_B(x, y) f(y) dy,
//
// P the ball's Poisson kernel, G_B its Green's function of −Δ (zero on
// ∂B), and ∇u(x) the same with ∇ₓP and ∇ₓG_B. Both kernels are bounded
// for |x − c| ≤ ρR < R, so the sphere's N samples s_i (uniform on ∂B, one
// walk each for û(s_i)) answer with the variance of N/few walks every point
// of the inner ball at once: u(x) ≈ mean of
//
//   t_i = û_i + (w_i − 1)(û_i − ū₋ᵢ) − β₋ᵢ·(w_i (s_i − c) − (x − c)),
//   w_i = |∂B| P(x, s_i),
//
// (∫ P = 1 and ∫ P (s − c) = x − c, so the subtracted terms have mean
// zero: with ū₋ᵢ, the mean of the other samples, and β₋ᵢ, their slope
// across the sphere, both independent of sample i, they are exact control
// variates that remove the spread the kernel's variation would otherwise
// give the mean value and the linear part), and ∇u(x) ≈ mean of
// ∇ₓw_i (û_i − ū₋ᵢ − β₋ᵢ·(s_i − c)) + β₋ᵢ. The variance of each mean is
// the sample variance over N: calibrated per point. Points of one sphere
// share its walks, so their errors are correlated (a smooth patch); points
// of different spheres are independent.
//
// The source term is integrated per point, from x: y = x + tω, ω
// stratified over directions (two per stratum), t uniform up to ∂B (the
// samples' weights |S| t^{DIM−1} T G_B and |S| t^{DIM−1} T ∇G_B stay
// bounded), with f(x) as a control variate: ∫_B G_B(x, y) dy =
// (R² − |x − c|²)/(2·DIM) exactly.
//
// Which sphere answers x is a function of x alone: lattices of spacing
// h₀/2^ℓ over the boundary's box, ℓ = 0, 1, ..., L; at each level, from the
// coarsest, the lattice node c nearest x, inside Ω, with R = d(c) (the
// largest ball about c in Ω); the first whose inner ball holds x answers
// it. A sphere's samples depend only on its level and node (and the seed),
// so the same point gets the same answer whatever other points were asked
// before, on any number of threads. Spheres are made when a point first
// needs them and kept: a moved probe reuses those it meets again. Points
// that no level answers lie within about ShellDistance of the boundary:
// they are left to pointwise walks (InShell), which are cheap there.
//
// The screened equation Δu − k²u = f has the same formula with the
// screened ball's kernels (ScreenedBallSeries.h: series off the centre);
// its kernels' means over the sphere are a_0(ρ) and R a_1(ρ) e instead of 1
// and x − c, so the control variates subtract those.
//
// Point sources in a sphere add −s G_B(x, z) exactly; curve sources add
// −∫ s G_B dl, sampled along each piece in the sphere with density ∝
// 1/|x − y| (AddConcentratedSources).
//
// Laplace's, Poisson's and the screened Poisson equation (volume, point
// and curve sources) on a closed mesh, in 2D and 3D, with Dirichlet
// conditions, or with Neumann or Robin parts:
// then the spheres keep clear of the whole boundary (WholeBoundary.h) and
// their samples' walks are walks on stars (the problem's own estimator);
// the shell's points take their derivatives from StarDerivativeWalks.h.
#ifndef GRIDFREE_CACHE_SPHERE_CACHE_H
#define GRIDFREE_CACHE_SPHERE_CACHE_H

#include <gridfree/cache/BoundaryValueCache.h>
#include <gridfree/cache/CacheProblemChecks.h>
#include <gridfree/cache/ScreenedBallSeries.h>
#include <gridfree/cache/WholeBoundary.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/math/DivergenceCurl.h>
#include <gridfree/problem/Problem.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/sources/SourceSet.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace gridfree
{
struct SphereCacheSettings
{
  // Walks per sphere (one from each of as many points on it) when a sphere
  // is made; a target grows them where needed.
  int SamplesPerSphere = 256;
  // Points within Reach·R of a sphere's centre are answered by it (the
  // kernels' spread grows as this nears 1).
  double Reach = 0.6;
  // The depth (a fraction of the boundary's bounding-box diagonal) beyond
  // which every point inside is answered: it sets the finest lattice.
  double ShellDistance = 0.02;
  // Samples of the source's ball integral per point (two per stratum).
  int SourceSamples = 256;
  // Samples of each curve source's piece in a ball per point (two per
  // stratum).
  int CurveSamples = 16;
  std::uint64_t Seed = 0;
  int Threads = 0; // 0: all
};

template <int DIM>
class SphereCache
{
public:
  // Checks the problem and prepares the lattices; no walks yet. Throws
  // std::invalid_argument for what it cannot answer.
  SphereCache(const Problem<DIM>& problem, const SphereCacheSettings& settings)
    : Shape(WholeBoundaryOf<DIM>(problem))
    , Settings(settings)
  {
    const Equation equation = problem.Settings().Problem;
    if (equation != Equation::Laplace && equation != Equation::Poisson &&
      equation != Equation::ScreenedPoisson)
    {
      throw std::invalid_argument(
        "the sphere cache answers Laplace's, Poisson's and the screened Poisson equation only");
    }
    if (equation == Equation::ScreenedPoisson)
    {
      this->Screening = std::sqrt(problem.Settings().ScreeningCoefficient);
    }
    if (problem.GetMixedBoundary() && problem.GetMixedBoundary()->HasTwoSided())
    {
      // Its inside test reads the side of the whole boundary's closest
      // point, which a sheet (the domain on both sides) does not tell.
      throw std::invalid_argument(
        "the sphere cache does not answer insulating sheets (condition 3) yet");
    }
    const SourceSet<DIM>* sources = problem.GetSources();
    if (settings.SamplesPerSphere < 4 || !(settings.Reach > 0.0 && settings.Reach < 1.0) ||
      !(settings.ShellDistance > 0.0))
    {
      throw std::invalid_argument(
        "the sphere cache needs at least 4 samples per sphere, a reach in (0, 1) and a "
        "positive shell distance");
    }
    this->Orientation = OutwardOrientation<DIM>(*this->Shape);
    this->Components = this->Shape->Components();
    const bool withSources = equation == Equation::Poisson || equation == Equation::ScreenedPoisson;
    if (withSources && sources && sources->MakeVolume)
    {
      this->MakeSource = sources->MakeVolume;
    }
    this->HasConcentrated = withSources && sources && (sources->Points || sources->Curves);
    // Lattice spacings: the coarsest a quarter of the diagonal, halving
    // until a point ShellDistance deep always finds a sphere (its nearest
    // node is at most h√DIM/2 away, and needs R ≥ that / Reach).
    const double diagonal = this->Shape->Diagonal();
    this->Origin = this->Shape->BoundsMin();
    this->Coarsest = 0.25 * diagonal;
    const double finest = settings.ShellDistance * diagonal /
      ((1.0 + 1.0 / settings.Reach) * 0.5 * std::sqrt(static_cast<double>(DIM)));
    this->Levels = 1;
    while (this->Coarsest / static_cast<double>(1 << (this->Levels - 1)) > finest &&
      this->Levels < 20)
    {
      ++this->Levels;
    }
  }

  // Answers every point (the first DIM of its coordinates): makes the
  // spheres it needs (one batch of walks), and, with a positive
  // `targetVariance`, grows the samples of the spheres of points above it,
  // up to `mostSamples` per sphere. False when aborted (the spheres made
  // stay, the answers are NaN).
  bool Answer(const Problem<DIM>& problem, const std::vector<std::array<double, 3>>& at,
    const CacheDerivatives& want, CacheEvaluation& out, double targetVariance = 0.0,
    int mostSamples = 0, const BatchProgressCallback& progress = BatchProgressCallback())
  {
    if (want.DivergenceCurl && this->Components != 3)
    {
      throw std::invalid_argument("divergence and curl need a solution of 3 components");
    }
    const std::size_t n = at.size();
    this->WalksRun = 0;
    out.Reset(n, this->Components, DIM, want);
    // The problem's point and curve sources (it owns them).
    this->Concentrated = this->HasConcentrated && problem.GetSources()
      ? problem.GetSources()->Concentrated()
      : ConcentratedSourceSet<DIM>();
    // Which spheres answer each point (a function of the point alone).
    std::vector<Cover> covers = this->AssignAll(at, out);
    // The spheres not made yet, in key order.
    std::vector<std::uint64_t> missing;
    for (const Cover& cover : covers)
    {
      for (int k = 0; k < cover.Count; ++k)
      {
        if (this->Index.find(cover.Keys[static_cast<std::size_t>(k)]) == this->Index.end())
        {
          missing.push_back(cover.Keys[static_cast<std::size_t>(k)]);
        }
      }
    }
    std::sort(missing.begin(), missing.end());
    missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
    for (std::uint64_t key : missing)
    {
      this->Index.emplace(key, this->Spheres.size());
      this->Spheres.push_back(this->MakeSphere(key));
    }
    for (Cover& cover : covers)
    {
      for (int k = 0; k < cover.Count; ++k)
      {
        cover.Spheres[static_cast<std::size_t>(k)] =
          this->Index.at(cover.Keys[static_cast<std::size_t>(k)]);
      }
    }
    // The spheres needed with fewer samples than a sphere starts with (new
    // ones, and those an aborted answer left short), in one batch.
    std::vector<int> wanted(this->Spheres.size(), 0);
    for (const Cover& cover : covers)
    {
      for (int k = 0; k < cover.Count; ++k)
      {
        const std::size_t s = cover.Spheres[static_cast<std::size_t>(k)];
        wanted[s] = std::max(this->Spheres[s].Samples, this->Settings.SamplesPerSphere);
      }
    }
    if (!this->Sample(problem, wanted, progress))
    {
      return false;
    }
    std::vector<unsigned char> todo(n, 1);
    // Each point's source integral, made once per call: it depends on the
    // point and its sphere's centre and radius, not on the sphere's walks,
    // so the rounds that grow the walks reuse it.
    SourceParts sources(this->MakeSource || this->HasConcentrated ? n : 0, this->Components);
    while (true)
    {
      if (!this->EvaluatePoints(at, covers, todo, want, sources, out))
      {
        return false;
      }
      if (!(targetVariance > 0.0))
      {
        return true;
      }
      // The sphere of a point above the target grows by a quarter (up to
      // mostSamples): on the CT benchmark's slices 20–30% fewer walks than
      // doubling, calibrated from 128 samples (TestSphereCache). (Growing
      // in one step to the samples its variance asks for, with 20% to
      // spare, ran 10–20% more walks than doubling.)
      std::fill(wanted.begin(), wanted.end(), 0);
      bool growing = false;
      for (std::size_t i = 0; i < n; ++i)
      {
        bool above = false;
        for (int c = 0; c < this->Components && covers[i].Count > 0; ++c)
        {
          above = above || !(out.ValueVariance[i * this->Components + c] <= targetVariance);
        }
        for (int k = 0; above && k < covers[i].Count; ++k)
        {
          const std::size_t s = covers[i].Spheres[static_cast<std::size_t>(k)];
          const int held = this->Spheres[s].Samples;
          const int more = std::min(held + held / 4, mostSamples);
          if (more > this->Spheres[s].Samples)
          {
            wanted[s] = more;
            growing = true;
          }
        }
      }
      if (!growing)
      {
        return true;
      }
      for (std::size_t i = 0; i < n; ++i)
      {
        todo[i] = 0;
        for (int k = 0; k < covers[i].Count; ++k)
        {
          todo[i] |= wanted[covers[i].Spheres[static_cast<std::size_t>(k)]] > 0 ? 1 : 0;
        }
      }
      if (!this->Sample(problem, wanted, progress))
      {
        return false;
      }
    }
  }

  std::size_t SphereCount() const { return this->Spheres.size(); }
  // Walks run by the last Answer (0: every sphere it needed was there).
  std::uint64_t Walks() const { return this->WalksRun; }
  // Walks held by every sphere.
  std::uint64_t TotalWalks() const
  {
    std::uint64_t total = 0;
    for (const SphereData& s : this->Spheres)
    {
      total += static_cast<std::uint64_t>(s.Samples);
    }
    return total;
  }
  int LatticeLevels() const { return this->Levels; }

  // The walks a sphere starts with. Raising it tops up every sphere a later
  // Answer needs (continuing its sample sequence: the bits of a cache made
  // with the new count); the walks of spheres holding more stay.
  int SamplesPerSphere() const { return this->Settings.SamplesPerSphere; }
  void SetSamplesPerSphere(int samples)
  {
    this->Settings.SamplesPerSphere = std::max(samples, 4);
  }
  // The most walks any sphere holds (a target grows spheres past the start).
  int MostSamples() const
  {
    int most = 0;
    for (const SphereData& s : this->Spheres)
    {
      most = std::max(most, s.Samples);
    }
    return most;
  }

private:
  static constexpr std::uint64_t kNone = ~std::uint64_t(0);

  // The spheres that answer a point (one, or none); several would be
  // blended (EvaluatePoint), but each costs its walks: one was cheaper at
  // equal error in the CT benchmark.
  struct Cover
  {
    std::array<std::uint64_t, 1> Keys;
    std::array<std::size_t, 1> Spheres;
    int Count = 0;
  };

  struct SphereData
  {
    std::uint64_t Key = 0;
    Vec<DIM> Centre;
    double Radius = 0.0;
    int Samples = 0;
    std::vector<Vec<DIM>> Points;  // on the sphere
    std::vector<double> Values;    // Samples × components: one walk each
    // The screened equation's kernels for this radius (null: Laplace's).
    std::shared_ptr<const ScreenedBallSeries<DIM>> Series;
  };

  // The key of a lattice node: level, then the node's indices.
  static std::uint64_t KeyOf(int level, const std::array<std::int64_t, DIM>& node)
  {
    const int bits = DIM == 3 ? 19 : 29;
    std::uint64_t key = static_cast<std::uint64_t>(level);
    for (int a = 0; a < DIM; ++a)
    {
      key = (key << bits) | (static_cast<std::uint64_t>(node[static_cast<std::size_t>(a)]) &
                              ((1ULL << bits) - 1));
    }
    return key;
  }

  Vec<DIM> NodePoint(int level, const std::array<std::int64_t, DIM>& node) const
  {
    const double h = this->Coarsest / static_cast<double>(1 << level);
    Vec<DIM> c;
    for (int a = 0; a < DIM; ++a)
    {
      c[a] = this->Origin[a] + h * static_cast<double>(node[static_cast<std::size_t>(a)]);
    }
    return c;
  }

  // The lattice node `corner` (bits: +1 along each axis) of the cell of
  // `level` that holds x.
  std::array<std::int64_t, DIM> CornerNode(const Vec<DIM>& x, int level, int corner) const
  {
    const double h = this->Coarsest / static_cast<double>(1 << level);
    std::array<std::int64_t, DIM> node;
    for (int a = 0; a < DIM; ++a)
    {
      node[static_cast<std::size_t>(a)] =
        static_cast<std::int64_t>(std::floor((x[a] - this->Origin[a]) / h)) + ((corner >> a) & 1);
    }
    return node;
  }

  // The sphere that answers each point (none: Outside or InShell set): at
  // the coarsest level where any does, the corner of the point's lattice
  // cell whose sphere holds it best (the smallest |x − c|/R below Reach;
  // then the smallest key). The nodes' radii (the distance to the boundary,
  // −1 outside) are kept: points of a slice share most nodes, and moved
  // slices meet them again.
  std::vector<Cover> AssignAll(const std::vector<std::array<double, 3>>& at, CacheEvaluation& out)
  {
    const std::size_t n = at.size();
    std::vector<Cover> covers(n);
    std::vector<Vec<DIM>> x(n);
    std::vector<unsigned char> pending(n, 0);
    ParallelForWithProgress(
      n, this->Settings.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
        for (std::size_t i = begin; i < end; ++i)
        {
          bool finite = true;
          for (int k = 0; k < DIM; ++k)
          {
            x[i][k] = at[i][static_cast<std::size_t>(k)];
            finite = finite && std::isfinite(x[i][k]);
          }
          if (!finite)
          {
            continue;
          }
          const ClosestPointResult<DIM> own = this->Shape->ClosestPoint(x[i]);
          out.Outside[i] = OutsideClosedMesh<DIM>(*this->Shape, this->Orientation, x[i], own);
          pending[i] = !out.Outside[i];
        }
      },
      [](double) { return true; }, 0.1, 64);
    for (int level = 0; level < this->Levels; ++level)
    {
      // The radii of the nodes this level needs that are not known yet.
      std::vector<std::uint64_t> unknown;
      for (std::size_t i = 0; i < n; ++i)
      {
        for (int corner = 0; pending[i] && corner < (1 << DIM); ++corner)
        {
          const std::uint64_t key = KeyOf(level, this->CornerNode(x[i], level, corner));
          if (this->NodeRadius.find(key) == this->NodeRadius.end())
          {
            unknown.push_back(key);
          }
        }
      }
      std::sort(unknown.begin(), unknown.end());
      unknown.erase(std::unique(unknown.begin(), unknown.end()), unknown.end());
      std::vector<double> radii(unknown.size());
      ParallelForWithProgress(
        unknown.size(), this->Settings.Threads,
        [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
          for (std::size_t k = begin; k < end; ++k)
          {
            const Vec<DIM> c = this->CentreOf(unknown[k]);
            const ClosestPointResult<DIM> hit = this->Shape->ClosestPoint(c);
            radii[k] = hit.distance > 0.0 &&
                !OutsideClosedMesh<DIM>(*this->Shape, this->Orientation, c, hit)
              ? hit.distance
              : -1.0;
          }
        },
        [](double) { return true; }, 0.1, 64);
      for (std::size_t k = 0; k < unknown.size(); ++k)
      {
        this->NodeRadius.emplace(unknown[k], radii[k]);
      }
      // Each pending point's best corner at this level.
      ParallelForWithProgress(
        n, this->Settings.Threads,
        [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
          for (std::size_t i = begin; i < end; ++i)
          {
            double best = this->Settings.Reach;
            for (int corner = 0; pending[i] && corner < (1 << DIM); ++corner)
            {
              const std::array<std::int64_t, DIM> node = this->CornerNode(x[i], level, corner);
              const std::uint64_t key = KeyOf(level, node);
              const double radius = this->NodeRadius.at(key);
              if (!(radius > 0.0))
              {
                continue;
              }
              const double ratio = (x[i] - this->NodePoint(level, node)).norm() / radius;
              if (ratio < best || (ratio == best && covers[i].Count == 1 && key < covers[i].Keys[0]))
              {
                best = ratio;
                covers[i].Keys[0] = key;
                covers[i].Count = 1;
              }
            }
          }
        },
        [](double) { return true; }, 0.1, 64);
      for (std::size_t i = 0; i < n; ++i)
      {
        pending[i] = pending[i] && covers[i].Count == 0;
      }
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      out.InShell[i] = pending[i];
    }
    return covers;
  }

  // The centre of the node a key names.
  Vec<DIM> CentreOf(std::uint64_t key) const
  {
    const int bits = DIM == 3 ? 19 : 29;
    std::array<std::int64_t, DIM> node;
    std::uint64_t rest = key;
    for (int a = DIM - 1; a >= 0; --a)
    {
      std::uint64_t index = rest & ((1ULL << bits) - 1);
      // Sign-extend (nodes below the box's corner are negative).
      if (index & (1ULL << (bits - 1)))
      {
        index |= ~((1ULL << bits) - 1);
      }
      node[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(index);
      rest >>= bits;
    }
    return this->NodePoint(static_cast<int>(rest), node);
  }

  // A sphere about a node whose radius AssignAll found.
  SphereData MakeSphere(std::uint64_t key) const
  {
    SphereData s;
    s.Key = key;
    s.Centre = this->CentreOf(key);
    s.Radius = this->NodeRadius.at(key);
    if (this->Screening > 0.0)
    {
      s.Series = std::make_shared<const ScreenedBallSeries<DIM>>(
        this->Screening, s.Radius, this->Settings.Reach);
    }
    return s;
  }

  // Brings each sphere s to wanted[s] samples (0: leave it): the new points
  // on each sphere (from the sphere's own stream), one walk from each, one
  // batch. An abort leaves every sphere as it was.
  bool Sample(const Problem<DIM>& problem, const std::vector<int>& wanted,
    const BatchProgressCallback& progress)
  {
    std::vector<std::array<double, 3>> points;
    std::vector<std::pair<std::size_t, int>> owner;
    const std::uint64_t salt = MixBits(this->Settings.Seed ^ 0x3c6ef372fe94f82bULL);
    for (std::size_t s = 0; s < wanted.size(); ++s)
    {
      const SphereData& sphere = this->Spheres[s];
      for (int k = sphere.Samples; k < wanted[s]; ++k)
      {
        RandomStream random(HashCombine(salt, sphere.Key), static_cast<std::uint64_t>(k));
        const Vec<DIM> y = sphere.Centre + sphere.Radius * SampleUnitSphere<DIM>(random);
        std::array<double, 3> xyz = { 0.0, 0.0, 0.0 };
        for (int a = 0; a < DIM; ++a)
        {
          xyz[static_cast<std::size_t>(a)] = y[a];
        }
        points.push_back(xyz);
        owner.emplace_back(s, k);
      }
    }
    if (points.empty())
    {
      return true;
    }
    BatchRequest request;
    request.WalksPerPoint = 1;
    request.Seed = this->Settings.Seed;
    request.Threads = this->Settings.Threads;
    request.AddPolynomialShift = false; // the cache holds w = u − P (PolynomialShift.h)
    const BatchEstimates walked = problem.EstimateAll(points, request, progress);
    if (!walked.Summary.Completed)
    {
      return false;
    }
    this->WalksRun += walked.Summary.WalksRun;
    const int nc = this->Components;
    for (std::size_t s = 0; s < wanted.size(); ++s)
    {
      if (wanted[s] > this->Spheres[s].Samples)
      {
        this->Spheres[s].Points.resize(static_cast<std::size_t>(wanted[s]));
        this->Spheres[s].Values.resize(static_cast<std::size_t>(wanted[s] * nc));
      }
    }
    for (std::size_t j = 0; j < points.size(); ++j)
    {
      SphereData& sphere = this->Spheres[owner[j].first];
      const auto k = static_cast<std::size_t>(owner[j].second);
      for (int a = 0; a < DIM; ++a)
      {
        sphere.Points[k][a] = points[j][static_cast<std::size_t>(a)];
      }
      for (int c = 0; c < nc; ++c)
      {
        sphere.Values[k * nc + c] = walked.Value(j, c);
      }
    }
    for (std::size_t s = 0; s < wanted.size(); ++s)
    {
      this->Spheres[s].Samples = std::max(this->Spheres[s].Samples, wanted[s]);
    }
    return true;
  }

  // One sphere's answer at a point, or several blended: value and
  // gradient per component with the variances of their means.
  struct SphereEstimate
  {
    explicit SphereEstimate(int nc)
      : Value(static_cast<std::size_t>(nc))
      , ValueVariance(static_cast<std::size_t>(nc))
      , Gradient(static_cast<std::size_t>(nc * DIM))
      , GradientVariance(static_cast<std::size_t>(nc * DIM))
      , Hessian(static_cast<std::size_t>(nc * DIM * DIM))
      , HessianVariance(static_cast<std::size_t>(nc * DIM * DIM))
      , Directional(static_cast<std::size_t>(nc))
      , DirectionalVariance(static_cast<std::size_t>(nc))
      , DivergenceCurl(4)
      , DivergenceCurlVariance(4)
    {
    }
    std::vector<double> Value, ValueVariance, Gradient, GradientVariance, Hessian, HessianVariance,
      Directional, DirectionalVariance;
    // ∇·u, then ∇×u (3-component solutions).
    std::vector<double> DivergenceCurl, DivergenceCurlVariance;

    void Clear()
    {
      for (std::vector<double>* v : { &Value, &ValueVariance, &Gradient, &GradientVariance,
             &Hessian, &HessianVariance, &Directional, &DirectionalVariance, &DivergenceCurl,
             &DivergenceCurlVariance })
      {
        std::fill(v->begin(), v->end(), 0.0);
      }
    }
    // Adds a·other (independent of what is there: variances add as a²).
    void Add(double a, const SphereEstimate& other)
    {
      for (std::size_t k = 0; k < Value.size(); ++k)
      {
        Value[k] += a * other.Value[k];
        ValueVariance[k] += a * a * other.ValueVariance[k];
        Directional[k] += a * other.Directional[k];
        DirectionalVariance[k] += a * a * other.DirectionalVariance[k];
      }
      for (std::size_t k = 0; k < Gradient.size(); ++k)
      {
        Gradient[k] += a * other.Gradient[k];
        GradientVariance[k] += a * a * other.GradientVariance[k];
      }
      for (std::size_t k = 0; k < Hessian.size(); ++k)
      {
        Hessian[k] += a * other.Hessian[k];
        HessianVariance[k] += a * a * other.HessianVariance[k];
      }
      for (std::size_t k = 0; k < DivergenceCurl.size(); ++k)
      {
        DivergenceCurl[k] += a * other.DivergenceCurl[k];
        DivergenceCurlVariance[k] += a * a * other.DivergenceCurlVariance[k];
      }
    }
    void WriteTo(CacheEvaluation& out, std::size_t i, const CacheDerivatives& want) const
    {
      const bool gradient = want.Gradient;
      std::copy(Value.begin(), Value.end(), out.Value.begin() + static_cast<std::ptrdiff_t>(i * Value.size()));
      std::copy(ValueVariance.begin(), ValueVariance.end(),
        out.ValueVariance.begin() + static_cast<std::ptrdiff_t>(i * Value.size()));
      if (gradient)
      {
        std::copy(Gradient.begin(), Gradient.end(),
          out.Gradient.begin() + static_cast<std::ptrdiff_t>(i * Gradient.size()));
        std::copy(GradientVariance.begin(), GradientVariance.end(),
          out.GradientVariance.begin() + static_cast<std::ptrdiff_t>(i * Gradient.size()));
      }
      if (want.Directional)
      {
        std::copy(Directional.begin(), Directional.end(),
          out.Directional.begin() + static_cast<std::ptrdiff_t>(i * Value.size()));
        std::copy(DirectionalVariance.begin(), DirectionalVariance.end(),
          out.DirectionalVariance.begin() + static_cast<std::ptrdiff_t>(i * Value.size()));
      }
      if (want.DivergenceCurl)
      {
        out.Divergence[i] = DivergenceCurl[0];
        out.DivergenceVariance[i] = DivergenceCurlVariance[0];
        for (std::size_t a = 0; a < 3; ++a)
        {
          out.Curl[3 * i + a] = DivergenceCurl[1 + a];
          out.CurlVariance[3 * i + a] = DivergenceCurlVariance[1 + a];
        }
      }
      if (want.Hessian)
      {
        std::copy(Hessian.begin(), Hessian.end(),
          out.Hessian.begin() + static_cast<std::ptrdiff_t>(i * Hessian.size()));
        std::copy(HessianVariance.begin(), HessianVariance.end(),
          out.HessianVariance.begin() + static_cast<std::ptrdiff_t>(i * Hessian.size()));
      }
    }
  };

  // A point's source integral over its sphere, kept across the rounds of
  // one Answer.
  struct SourcePart
  {
    explicit SourcePart(int nc)
      : Part(nc)
    {
    }
    SphereEstimate Part;
    bool Made = false;
  };
  struct SourceParts
  {
    SourceParts(std::size_t n, int nc)
      : Parts(n, SourcePart(nc))
    {
    }
    SourcePart* Of(std::size_t i) { return this->Parts.empty() ? nullptr : &this->Parts[i]; }
    std::vector<SourcePart> Parts;
  };

  // The answers at the points marked in `todo`.
  bool EvaluatePoints(const std::vector<std::array<double, 3>>& at,
    const std::vector<Cover>& covers, const std::vector<unsigned char>& todo,
    const CacheDerivatives& want, SourceParts& sources, CacheEvaluation& out) const
  {
    return ParallelForWithProgress(
      at.size(), this->Settings.Threads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
        std::unique_ptr<VolumeSource<DIM>> source =
          this->MakeSource ? this->MakeSource(this->Shape->Diagonal()) : nullptr;
        SphereEstimate one(this->Components), blend(this->Components);
        for (std::size_t i = begin; i < end; ++i)
        {
          if (todo[i] && covers[i].Count > 0)
          {
            this->EvaluatePoint(at[i], covers[i], want, source.get(), sources.Of(i), one, blend);
            blend.WriteTo(out, i, want);
          }
        }
      },
      [](double) { return true; }, 0.1, 16);
  }

  // A point from its spheres, blended with weights (1 − (ρ/Reach)²)², ρ =
  // |x − c|/R, normalised: each sphere's answer is unbiased and the spheres
  // are independent, so the blend is too, with the weights' squares on the
  // variances; a weight that falls to zero at the edge of a sphere's reach
  // makes the answer change smoothly where a sphere joins or leaves.
  void EvaluatePoint(const std::array<double, 3>& p, const Cover& cover,
    const CacheDerivatives& want, VolumeSource<DIM>* source, SourcePart* kept, SphereEstimate& one,
    SphereEstimate& blend) const
  {
    Vec<DIM> x;
    for (int k = 0; k < DIM; ++k)
    {
      x[k] = p[static_cast<std::size_t>(k)];
    }
    std::array<double, 1> weights;
    double total = 0.0;
    for (int k = 0; k < cover.Count; ++k)
    {
      const SphereData& s = this->Spheres[cover.Spheres[static_cast<std::size_t>(k)]];
      const double rho = (x - s.Centre).norm() / (this->Settings.Reach * s.Radius);
      weights[static_cast<std::size_t>(k)] = (1.0 - rho * rho) * (1.0 - rho * rho);
      total += weights[static_cast<std::size_t>(k)];
    }
    blend.Clear();
    for (int k = 0; k < cover.Count; ++k)
    {
      const SphereData& s = this->Spheres[cover.Spheres[static_cast<std::size_t>(k)]];
      this->EvaluateSphere(x, s, want, one);
      if (kept)
      {
        // (A point has one sphere: Cover holds one.)
        if (!kept->Made)
        {
          kept->Part.Clear();
          if (source)
          {
            this->AddSourceIntegral(x, s, want, *source, kept->Part);
          }
          if (this->HasConcentrated)
          {
            this->AddConcentratedSources(x, s, want, kept->Part);
          }
          kept->Made = true;
        }
        one.Add(1.0, kept->Part);
      }
      blend.Add(weights[static_cast<std::size_t>(k)] / total, one);
    }
  }

  // One sphere's answer: the kernel-weighted samples with the
  // leave-one-out control variates (the mean value, and the linear part).
  // The Hessian (Laplace's kernel) is the mean of ∇ₓ²w_i times the same
  // residual: ∫∇²P = 0 and ∫∇²P (s − c)ᵀ = 0, so no mean is added back.
  void EvaluateSphere(
    const Vec<DIM>& x, const SphereData& s, const CacheDerivatives& want, SphereEstimate& e) const
  {
    // (The directional derivative is Z·g per sample: its variance is
    // exact, with the gradient's covariances.)
    // (So are ∇·u and ∇×u, from the samples' Jacobians.)
    const bool gradient = want.Gradient || want.Directional || want.DivergenceCurl;
    const bool hessian = want.Hessian;
    thread_local std::vector<Vec<DIM>> jacobians; // per sample and component
    if (want.DivergenceCurl)
    {
      jacobians.resize(static_cast<std::size_t>(s.Samples * this->Components));
    }
    Vec<DIM> along = Vec<DIM>::Zero();
    for (int a = 0; a < DIM; ++a)
    {
      along[a] = want.Direction[static_cast<std::size_t>(a)];
    }
    const int nc = this->Components;
    const int m = s.Samples;
    const double R = s.Radius;
    const Vec<DIM> p = x - s.Centre;
    const double r2 = p.squaredNorm();
    // The sum of the samples' offsets s_k − c (for the linear part's
    // centring).
    Vec<DIM> offsets = Vec<DIM>::Zero();
    for (int k = 0; k < m; ++k)
    {
      offsets += s.Points[static_cast<std::size_t>(k)] - s.Centre;
    }
    // The slope's control variate from 128 samples on: with fewer, the
    // variance left (the walks' heavy-tailed noise) is estimated too
    // roughly (the cache benchmark's mean z² rose from 1.1–1.2 to 1.3 at
    // 64 samples per sphere, from 1.5–2.1 to 2.0–2.3 at 16).
    const double slope =
      m >= 128 ? DIM / (R * R * static_cast<double>(m - 1)) : 0.0;
    // The kernel's exact means over the sphere, E[w] and E[w (s − c)]
    // (Laplace: 1 and x − c), which the control variates subtract.
    double meanW = 1.0;
    Vec<DIM> meanWo = p;
    // Screened: the kernel per sample (shared by the components), and the
    // means' x-gradients.
    thread_local std::vector<double> screenedW;
    thread_local std::vector<Vec<DIM>> screenedDW;
    thread_local std::vector<Mat<DIM>> screenedD2W;
    // Screened: the means' x-Hessians, ∇²a_0 (times ū) and ∇²(R a_1 e·β).
    Mat<DIM> meanWHessian = Mat<DIM>::Zero();
    const ScreenedBallSeries<DIM>* series = s.Series.get();
    typename ScreenedBallSeries<DIM>::Radial radial;
    Vec<DIM> direction = Vec<DIM>::Unit(0);
    if (series)
    {
      const double rho = std::sqrt(r2);
      direction = rho > 0.0 ? Vec<DIM>(p / rho) : direction;
      series->RadialAt(rho, radial, hessian);
      meanW = radial.A[0];
      meanWo = (R * (radial.Terms > 1 ? radial.A[1] : 0.0)) * direction;
      screenedW.resize(static_cast<std::size_t>(m));
      screenedDW.resize(static_cast<std::size_t>(m));
      screenedD2W.resize(hessian ? static_cast<std::size_t>(m) : 0);
      for (int k = 0; k < m; ++k)
      {
        const auto i = static_cast<std::size_t>(k);
        const Vec<DIM> n = (s.Points[i] - s.Centre) / R;
        screenedW[i] = series->Kernel(radial, direction, n,
          gradient || hessian ? &screenedDW[i] : nullptr, hessian ? &screenedD2W[i] : nullptr);
      }
      if (hessian)
      {
        meanWHessian = series->ZerothOrderHessian(radial, direction);
      }
    }
    for (int c = 0; c < nc; ++c)
    {
      double total = 0.0;
      Vec<DIM> moment = Vec<DIM>::Zero();
      for (int k = 0; k < m; ++k)
      {
        const double u = s.Values[static_cast<std::size_t>(k * nc + c)];
        total += u;
        moment += u * (s.Points[static_cast<std::size_t>(k)] - s.Centre);
      }
      double sum = 0.0, squares = 0.0;
      Vec<DIM> gsum = Vec<DIM>::Zero(), gsquares = Vec<DIM>::Zero();
      Mat<DIM> hsum = Mat<DIM>::Zero(), hsquares = Mat<DIM>::Zero();
      double dsum = 0.0, dsquares = 0.0;
      for (int k = 0; k < m; ++k)
      {
        const double u = s.Values[static_cast<std::size_t>(k * nc + c)];
        const Vec<DIM> o = s.Points[static_cast<std::size_t>(k)] - s.Centre;
        // From the other samples only (so independent of this one): their
        // mean, and the slope β of their linear part, DIM/R² times the mean
        // of (u_j − ū)(s_j − c) (the sphere's mean of u·(s − c) is R²/DIM
        // times a harmonic function's gradient at c).
        const double others = (total - u) / static_cast<double>(m - 1);
        const Vec<DIM> beta =
          slope * ((moment - u * o) - (total - u) * (offsets - o) / static_cast<double>(m - 1));
        const Vec<DIM> d = x - s.Points[static_cast<std::size_t>(k)];
        const double d2 = d.squaredNorm();
        // w = |∂B| P(x, s): 3D R(R² − r²)/|x − s|³, 2D (R² − r²)/|x − s|².
        double w;
        Vec<DIM> dw;
        if (series)
        {
          w = screenedW[static_cast<std::size_t>(k)];
          dw = gradient ? screenedDW[static_cast<std::size_t>(k)] : Vec<DIM>::Zero();
        }
        else if constexpr (DIM == 3)
        {
          const double inv3 = 1.0 / (d2 * std::sqrt(d2));
          w = R * (R * R - r2) * inv3;
          dw = R * (-2.0 * inv3) * p - (3.0 * w / d2) * d;
        }
        else
        {
          w = (R * R - r2) / d2;
          dw = (-2.0 / d2) * p - (2.0 * w / d2) * d;
        }
        // Poisson's formula reproduces constants and linear functions
        // exactly (∫P = 1, ∫P (s − c) = x − c, ∫∇ₓP (s − c)ᵀ = I), so
        // both terms subtracted have mean zero; what is left is the
        // spread of u beyond its linear part, and the walks' noise.
        // (Screened: w u − (w − E[w]) ū − β·(w o − E[w o]), the same
        // with E[w] = a_0 and E[w o] = R a_1 e; its gradient gains the
        // means' gradients ∇a_0 ū and ∇(R a_1 e) β.)
        const double residual = u - others - beta.dot(o);
        const double t = meanW * u + (w - meanW) * (u - others) - beta.dot(w * o - meanWo);
        sum += t;
        squares += t * t;
        if (gradient)
        {
          Vec<DIM> g;
          if (series)
          {
            const double along = direction.dot(beta);
            const double a1 = radial.Terms > 1 ? radial.D[1] : 0.0;
            const double b1 = radial.Terms > 1 ? radial.B[1] : 0.0;
            g = residual * dw + (radial.D[0] * others) * direction +
              R * (a1 * along * direction + b1 * (beta - along * direction));
          }
          else
          {
            g = residual * dw + beta;
          }
          gsum += g;
          gsquares += g.cwiseProduct(g);
          const double dz = along.dot(g);
          dsum += dz;
          dsquares += dz * dz;
          if (want.DivergenceCurl)
          {
            jacobians[static_cast<std::size_t>(k * nc + c)] = g;
          }
        }
        if (hessian && series)
        {
          // Screened: ∇ₓ²w times the residual, plus the means' Hessians
          // (∫∇ₓ²P = ∇²a_0 and ∫∇ₓ²P (s − c) = ∇²(R a_1 e) are not zero).
          const Mat<DIM> term = residual * screenedD2W[static_cast<std::size_t>(k)] +
            others * meanWHessian + R * series->FirstOrderHessian(radial, direction, beta);
          hsum += term;
          hsquares += term.cwiseProduct(term);
        }
        else if (hessian)
        {
          // ∇ₓ²w = −2ρ I/|d|^DIM − DIM w I/|d|² + 2·DIM ρ (p dᵀ + d pᵀ)/|d|^{DIM+2}
          // + DIM(DIM+2) w d dᵀ/|d|⁴, ρ = R (3D) or 1 (2D), d = x − s
          // (harmonic: its trace is 0).
          const double scale = DIM == 3 ? R : 1.0;
          const double dn = DIM == 3 ? d2 * std::sqrt(d2) : d2;
          const Mat<DIM> pd = p * d.transpose();
          const Mat<DIM> h = (-2.0 * scale / dn - DIM * w / d2) * Mat<DIM>::Identity() +
            (2.0 * DIM * scale / (dn * d2)) * (pd + pd.transpose()) +
            (DIM * (DIM + 2.0) * w / (d2 * d2)) * (d * d.transpose());
          const Mat<DIM> term = residual * h;
          hsum += term;
          hsquares += term.cwiseProduct(term);
        }
      }
      const double mean = sum / m;
      e.Value[static_cast<std::size_t>(c)] = mean;
      e.ValueVariance[static_cast<std::size_t>(c)] =
        std::max(0.0, (squares - m * mean * mean) / (static_cast<double>(m) * (m - 1)));
      const double dmean = gradient ? dsum / m : 0.0;
      e.Directional[static_cast<std::size_t>(c)] = dmean;
      e.DirectionalVariance[static_cast<std::size_t>(c)] = gradient
        ? std::max(0.0, (dsquares - m * dmean * dmean) / (static_cast<double>(m) * (m - 1)))
        : 0.0;
      for (int a = 0; a < DIM; ++a)
      {
        const double gm = gradient ? gsum[a] / m : 0.0;
        e.Gradient[static_cast<std::size_t>(c * DIM + a)] = gm;
        e.GradientVariance[static_cast<std::size_t>(c * DIM + a)] = gradient
          ? std::max(0.0, (gsquares[a] - m * gm * gm) / (static_cast<double>(m) * (m - 1)))
          : 0.0;
        for (int b = 0; b < DIM; ++b)
        {
          const double hm = hessian ? hsum(a, b) / m : 0.0;
          const auto slot = static_cast<std::size_t>((c * DIM + a) * DIM + b);
          e.Hessian[slot] = hm;
          e.HessianVariance[slot] = hessian
            ? std::max(0.0, (hsquares(a, b) - m * hm * hm) / (static_cast<double>(m) * (m - 1)))
            : 0.0;
        }
      }
    }
    if (want.DivergenceCurl)
    {
      double sums[4] = { 0.0, 0.0, 0.0, 0.0 }, squares[4] = { 0.0, 0.0, 0.0, 0.0 };
      for (int k = 0; k < m; ++k)
      {
        double divergence, curl[3];
        DivergenceAndCurl<DIM>(
          [&](int i, int j) { return jacobians[static_cast<std::size_t>(k * nc + i)][j]; },
          divergence, curl);
        const double values[4] = { divergence, curl[0], curl[1], curl[2] };
        for (int v = 0; v < 4; ++v)
        {
          sums[v] += values[v];
          squares[v] += values[v] * values[v];
        }
      }
      for (int v = 0; v < 4; ++v)
      {
        const double mean = sums[v] / m;
        e.DivergenceCurl[static_cast<std::size_t>(v)] = mean;
        e.DivergenceCurlVariance[static_cast<std::size_t>(v)] =
          std::max(0.0, (squares[v] - m * mean * mean) / (static_cast<double>(m) * (m - 1)));
      }
    }
  }

  // A point x of a sphere's ball, with what its Green's function needs:
  // x − c, its length and direction, and (screened) the series' radial
  // coefficients at |x − c|.
  struct BallPoint
  {
    BallPoint(const Vec<DIM>& x, const SphereData& s)
      : X(x)
      , P(x - s.Centre)
    {
      this->R2 = this->P.squaredNorm();
      this->R = std::sqrt(this->R2);
      this->A = this->R / s.Radius;
      this->E = this->R > 0.0 ? Vec<DIM>(this->P / this->R) : Vec<DIM>::Unit(0);
      if (s.Series)
      {
        // (With the second-order coefficients: BallGreen's Hessian.)
        s.Series->RadialAt(this->R, this->AtX, true);
      }
    }
    Vec<DIM> X, P, E;
    double R2 = 0.0, R = 0.0;
    double A = 0.0; // the image point's scaling, |x − c|/R
    typename ScreenedBallSeries<DIM>::Radial AtX;
  };

  // The ball's Green's function G_B(x, y) (zero on the sphere) of −Δ, or
  // of −Δ + k² (G − H from the series), and its x-gradient, for y in the
  // ball at t = |y − x| along the unit w = (y − x)/t; with `d2G`, its
  // x-Hessian: screened, G''(t) wwᵀ + G'(t)/t (I − wwᵀ) − ∇ₓ²H; for −Δ,
  // with v = b² p − q (b = |q|/R, p = x − c,
  // q = y − c) and ρ the image distance, ∇ρ = v/ρ, so 3D:
  // ∇²G_B = [(3wwᵀ − I)/t³ + b² I/ρ³ − 3vvᵀ/ρ⁵]/(4π); 2D:
  // [(2wwᵀ − I)/t² + b² I/ρ² − 2vvᵀ/ρ⁴]/(2π).
  double BallGreen(const BallPoint& at, const SphereData& s, const Vec<DIM>& y, double t,
    const Vec<DIM>& w, typename ScreenedBallSeries<DIM>::Radial& atY, Vec<DIM>& dG,
    Mat<DIM>* d2G = nullptr) const
  {
    constexpr double kPi = 3.14159265358979323846;
    const double R = s.Radius;
    const Vec<DIM> q = y - s.Centre;
    if (const ScreenedBallSeries<DIM>* series = s.Series.get())
    {
      const double qn = q.norm();
      series->RadialAt(qn, atY);
      Vec<DIM> dH;
      Mat<DIM> d2H;
      double slope;
      const double free = series->FreeSpace(t, &slope);
      const double G = free -
        series->Regular(at.AtX, atY, at.E, qn > 0.0 ? Vec<DIM>(q / qn) : Vec<DIM>::Unit(0), &dH,
          d2G ? &d2H : nullptr);
      dG = -slope * w - dH;
      if (d2G)
      {
        const Mat<DIM> ww = w * w.transpose();
        *d2G = series->FreeSpaceSecond(t, free, slope) * ww +
          (slope / t) * (Mat<DIM>::Identity() - ww) - d2H;
      }
      return G;
    }
    const double b = q.norm() / R;
    const Vec<DIM> image = at.A * q - R * at.E; // |image| = |x − c||y − x*|/R
    const Vec<DIM> imageX =
      b * at.P - R * (q.norm() > 0.0 ? Vec<DIM>(q / q.norm()) : Vec<DIM>::Unit(0));
    if (d2G)
    {
      const Vec<DIM> v = b * imageX;
      const double rho2 = imageX.squaredNorm();
      const Mat<DIM> I = Mat<DIM>::Identity();
      if constexpr (DIM == 3)
      {
        const double rho3 = rho2 * std::sqrt(rho2);
        *d2G = ((3.0 * w * w.transpose() - I) / (t * t * t) + (b * b / rho3) * I -
                 (3.0 / (rho3 * rho2)) * (v * v.transpose())) /
          (4.0 * kPi);
      }
      else
      {
        *d2G = ((2.0 * w * w.transpose() - I) / (t * t) + (b * b / rho2) * I -
                 (2.0 / (rho2 * rho2)) * (v * v.transpose())) /
          (2.0 * kPi);
      }
    }
    if constexpr (DIM == 3)
    {
      dG = (w / (t * t) + b * imageX / PowerOf<3>(imageX.norm())) / (4.0 * kPi);
      return (1.0 / t - 1.0 / image.norm()) / (4.0 * kPi);
    }
    else
    {
      dG = (w / t + b * imageX / imageX.squaredNorm()) / (2.0 * kPi);
      return (std::log(image.norm()) - std::log(t)) / (2.0 * kPi);
    }
  }

  // −Σ s_j G_B(x, z_j) over the point sources in the ball (exact), and
  // −∫ s G_B(x, y) dl over the curve sources' pieces in it: per piece,
  // samples with density ∝ 1/|x − y| along its line (ℓ = h sinh u, u
  // uniform, h the line's distance from x), which cancels G's 1/r in 3D
  // (2D: its log), stratified in u with two draws per stratum for the
  // variance. With their x-gradients.
  void AddConcentratedSources(const Vec<DIM>& x, const SphereData& s,
    const CacheDerivatives& want, SphereEstimate& into) const
  {
    const int nc = this->Components;
    const bool gradient = want.Gradient || want.Directional || want.DivergenceCurl;
    const bool hessian = want.Hessian;
    const bool directional = want.Directional;
    const bool divergenceCurl = want.DivergenceCurl;
    const auto toward = [&](const Vec<DIM>& g) {
      double dz = 0.0;
      for (int d = 0; d < DIM; ++d)
      {
        dz += want.Direction[static_cast<std::size_t>(d)] * g[d];
      }
      return dz;
    };
    const BallPoint at(x, s);
    typename ScreenedBallSeries<DIM>::Radial atY;
    Vec<DIM> dG;
    Mat<DIM> d2G = Mat<DIM>::Zero();
    Mat<DIM>* withHessian = hessian ? &d2G : nullptr;
    if (const PointSources<DIM>* points = this->Concentrated.Points)
    {
      points->ForEachInBall(s.Centre, s.Radius, [&](const Vec<DIM>& z, const double* strength) {
        const double t = (z - x).norm();
        const Vec<DIM> w = t > 0.0 ? Vec<DIM>((z - x) / t) : Vec<DIM>::Unit(0);
        const double G = this->BallGreen(at, s, z, t, w, atY, dG, withHessian);
        for (int c = 0; c < nc; ++c)
        {
          into.Value[static_cast<std::size_t>(c)] -= strength[c] * G;
          into.Directional[static_cast<std::size_t>(c)] -= directional ? strength[c] * toward(dG) : 0.0;
          for (int d = 0; d < DIM && gradient; ++d)
          {
            into.Gradient[static_cast<std::size_t>(c * DIM + d)] -= strength[c] * dG[d];
          }
          for (int a = 0; a < DIM * DIM && hessian; ++a)
          {
            into.Hessian[static_cast<std::size_t>(c * DIM * DIM + a)] -=
              strength[c] * d2G(a / DIM, a % DIM);
          }
        }
        if (divergenceCurl)
        {
          double divergence, curl[3];
          DivergenceAndCurl<DIM>(
            [&](int i, int j) { return -strength[i] * dG[j]; }, divergence, curl);
          into.DivergenceCurl[0] += divergence;
          for (std::size_t a = 0; a < 3; ++a)
          {
            into.DivergenceCurl[1 + a] += curl[a];
          }
        }
      });
    }
    const CurveSources<DIM>* curves = this->Concentrated.Curves;
    if (!curves)
    {
      return;
    }
    double pointCoordinates[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < DIM; ++k)
    {
      pointCoordinates[k] = x[k];
    }
    const std::uint64_t key =
      HashCombine(PointKey(this->Settings.Seed ^ 0x9b05688c2b3e6c1fULL, pointCoordinates), s.Key);
    const int strata = std::max(1, this->Settings.CurveSamples / 2);
    // Per component: value, then gradient, then Hessian entries.
    const int gradients = nc, hessians = nc + nc * DIM, directionals = hessians + nc * DIM * DIM;
    const int divergences = directionals + nc;
    std::vector<double> first(static_cast<std::size_t>(divergences + 4), 0.0),
      term(first.size(), 0.0);
    typename CurveSources<DIM>::Scratch scratch;
    curves->ForEachPieceInBall(s.Centre, s.Radius, scratch,
      [&](std::uint32_t segment, const Vec<DIM>& a, const Vec<DIM>& d, double t0, double t1,
        const double* s0, const double* s1) {
        const NearLinePiece<DIM> near(a, d, t0, t1, x, 1e-12 * s.Radius);
        const Vec<DIM> along = d / near.Length;
        const double width = near.Width() / strata;
        std::vector<double> sum(first.size(), 0.0), squares(first.size(), 0.0);
        for (int k = 0; k < strata; ++k)
        {
          for (int draw = 0; draw < 2; ++draw)
          {
            RandomStream random(HashCombine(key, segment), static_cast<std::uint64_t>(2 * k + draw));
            const double u = near.U0 + width * (k + random.NextDouble());
            const double t = near.ParameterAt(u);
            const Vec<DIM> y = a + t * d;
            const double r = (y - x).norm();
            const Vec<DIM> w = r > 0.0 ? Vec<DIM>((y - x) / r) : along;
            const double G = this->BallGreen(at, s, y, r, w, atY, dG, withHessian);
            // dl = h cosh u du = |x − y| du (per unit of u).
            const double jacobian = near.Jacobian(u);
            for (int c = 0; c < nc; ++c)
            {
              const double strength = (1.0 - t) * s0[c] + t * s1[c];
              term[static_cast<std::size_t>(c)] = -strength * G * jacobian;
              for (int e = 0; e < DIM && gradient; ++e)
              {
                term[static_cast<std::size_t>(gradients + c * DIM + e)] =
                  -strength * dG[e] * jacobian;
              }
              for (int e = 0; e < DIM * DIM && hessian; ++e)
              {
                term[static_cast<std::size_t>(hessians + c * DIM * DIM + e)] =
                  -strength * d2G(e / DIM, e % DIM) * jacobian;
              }
              term[static_cast<std::size_t>(directionals + c)] =
                directional ? -strength * toward(dG) * jacobian : 0.0;
            }
            if (divergenceCurl)
            {
              this->AddDivergenceCurlTerms(term, nc, divergences);
            }
            if (draw == 0)
            {
              first = term;
            }
          }
          AddStratumPair(first, term, sum, squares);
        }
        for (int c = 0; c < nc; ++c)
        {
          into.Value[static_cast<std::size_t>(c)] += width * sum[static_cast<std::size_t>(c)];
          into.ValueVariance[static_cast<std::size_t>(c)] +=
            width * width * squares[static_cast<std::size_t>(c)];
          for (int e = 0; e < DIM && gradient; ++e)
          {
            const std::size_t v = static_cast<std::size_t>(gradients + c * DIM + e);
            into.Gradient[static_cast<std::size_t>(c * DIM + e)] += width * sum[v];
            into.GradientVariance[static_cast<std::size_t>(c * DIM + e)] += width * width * squares[v];
          }
          if (directional)
          {
            const std::size_t v = static_cast<std::size_t>(directionals + c);
            into.Directional[static_cast<std::size_t>(c)] += width * sum[v];
            into.DirectionalVariance[static_cast<std::size_t>(c)] += width * width * squares[v];
          }
          if (divergenceCurl && c == 0)
          {
            for (int v = 0; v < 4; ++v)
            {
              const std::size_t slot = static_cast<std::size_t>(divergences + v);
              into.DivergenceCurl[static_cast<std::size_t>(v)] += width * sum[slot];
              into.DivergenceCurlVariance[static_cast<std::size_t>(v)] +=
                width * width * squares[slot];
            }
          }
          for (int e = 0; e < DIM * DIM && hessian; ++e)
          {
            const std::size_t v = static_cast<std::size_t>(hessians + c * DIM * DIM + e);
            into.Hessian[static_cast<std::size_t>(c * DIM * DIM + e)] += width * sum[v];
            into.HessianVariance[static_cast<std::size_t>(c * DIM * DIM + e)] +=
              width * width * squares[v];
          }
        }
      });
  }

  // −∫_B G_B(x, y) f(y) dy (and its x-gradient): f(x) times the exact
  // ∫ G_B = (R² − r²)/(2·DIM) (∫ ∇ₓG_B = −(x − c)/DIM; screened:
  // ScreenedBallSeries::BallIntegral), plus the
  // stratified mean of the samples of G_B (f(y) − f(x)), each stratum's
  // two draws giving its variance.
  // The Hessian: ∫∇ₓ²G_B (f(y) − f(x)) converges (∇²G_B ~ r^{−DIM}, the
  // difference ~ r), and ∇²∫G_B = −I/DIM gives f(x) I/DIM.
  void AddSourceIntegral(const Vec<DIM>& x, const SphereData& s, const CacheDerivatives& want,
    VolumeSource<DIM>& source, SphereEstimate& into) const
  {
    const bool gradient = want.Gradient || want.Directional || want.DivergenceCurl;
    const bool hessian = want.Hessian;
    const bool directional = want.Directional;
    const bool divergenceCurl = want.DivergenceCurl;
    constexpr double kPi = 3.14159265358979323846;
    const int nc = this->Components;
    const double R = s.Radius;
    const Vec<DIM> p = x - s.Centre;
    const double r2 = p.squaredNorm();
    const double r = std::sqrt(r2);
    std::vector<double> fx(static_cast<std::size_t>(nc)), fy(static_cast<std::size_t>(nc));
    source.Evaluate(x, fx.data());
    // Strata of directions: a g × g grid of the square that maps to the
    // sphere with equal area (3D), g intervals of the angle (2D).
    const int half = std::max(1, this->Settings.SourceSamples / 2);
    const int g = DIM == 3 ? std::max(1, static_cast<int>(std::lround(std::sqrt(half)))) : half;
    const int strata = DIM == 3 ? g * g : g;
    double pointCoordinates[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < DIM; ++k)
    {
      pointCoordinates[k] = x[k];
    }
    // The point's stream for this sphere (the spheres blended at a point
    // have independent source samples).
    const std::uint64_t key =
      HashCombine(PointKey(this->Settings.Seed ^ 0x510e527fade682d1ULL, pointCoordinates), s.Key);
    // Per component: sum and squares of the strata's means, value then
    // gradient (then Hessian).
    const int hessians = nc + nc * DIM;
    const int directionals = hessians + (hessian ? nc * DIM * DIM : 0);
    const int divergences = directionals + (directional ? nc : 0);
    std::vector<double> sum(static_cast<std::size_t>(divergences + (divergenceCurl ? 4 : 0)), 0.0);
    Mat<DIM> d2G = Mat<DIM>::Zero();
    std::vector<double> squares(sum.size(), 0.0), first(sum.size(), 0.0), term(sum.size(), 0.0);
    const BallPoint at(x, s);
    const ScreenedBallSeries<DIM>* series = s.Series.get();
    typename ScreenedBallSeries<DIM>::Radial atY;
    for (int k = 0; k < strata; ++k)
    {
      for (int draw = 0; draw < 2; ++draw)
      {
        RandomStream random(key, static_cast<std::uint64_t>(2 * k + draw));
        Vec<DIM> w;
        if constexpr (DIM == 3)
        {
          const double u1 = (static_cast<double>(k % g) + random.NextDouble()) / g;
          const double u2 = (static_cast<double>(k / g) + random.NextDouble()) / g;
          const double z = 1.0 - 2.0 * u1;
          const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
          w = Vec<3>(rho * std::cos(2.0 * kPi * u2), rho * std::sin(2.0 * kPi * u2), z);
        }
        else
        {
          const double angle = 2.0 * kPi * (static_cast<double>(k) + random.NextDouble()) / g;
          w = Vec<2>(std::cos(angle), std::sin(angle));
        }
        // Distance from x to ∂B along ω, and the point y at a uniform
        // fraction of it.
        const double pw = p.dot(w);
        const double T = -pw + std::sqrt(std::max(0.0, pw * pw + R * R - r2));
        const double t = T * random.NextDouble();
        const Vec<DIM> y = x + t * w;
        source.Evaluate(y, fy.data());
        // G_B and ∇ₓG_B in the ball; 1/pdf = |S| t^{DIM−1} T.
        Vec<DIM> dG;
        const double G = this->BallGreen(at, s, y, t, w, atY, dG, hessian ? &d2G : nullptr);
        const double inverse = (DIM == 3 ? 4.0 * kPi * t * t : 2.0 * kPi * t) * T;
        for (int c = 0; c < nc; ++c)
        {
          const double df = fy[static_cast<std::size_t>(c)] - fx[static_cast<std::size_t>(c)];
          term[static_cast<std::size_t>(c)] = -G * inverse * df;
          for (int d = 0; d < DIM && gradient; ++d)
          {
            term[static_cast<std::size_t>(nc + c * DIM + d)] = -dG[d] * inverse * df;
          }
          for (int e = 0; e < DIM * DIM && hessian; ++e)
          {
            term[static_cast<std::size_t>(hessians + c * DIM * DIM + e)] =
              -d2G(e / DIM, e % DIM) * inverse * df;
          }
          if (directional)
          {
            double dz = 0.0;
            for (int d = 0; d < DIM; ++d)
            {
              dz += want.Direction[static_cast<std::size_t>(d)] *
                term[static_cast<std::size_t>(nc + c * DIM + d)];
            }
            term[static_cast<std::size_t>(directionals + c)] = dz;
          }
        }
        if (divergenceCurl)
        {
          this->AddDivergenceCurlTerms(term, nc, divergences);
        }
        if (draw == 0)
        {
          first = term;
        }
      }
      AddStratumPair(first, term, sum, squares);
    }
    const double K = static_cast<double>(strata);
    // Screened: ∫_B G_B dy = (1 − a_0)/k², its x-gradient −a_0' e/k².
    const double ball = series ? series->BallIntegral(r, at.AtX) : 0.0;
    const Vec<DIM> ballGradient =
      series ? series->BallIntegralGradient(at.AtX, at.E) : Vec<DIM>::Zero();
    // ∇²∫_B G_B: −I/DIM for −Δ; −∇²a_0/k² screened.
    const Mat<DIM> ballHessian = series && hessian
      ? Mat<DIM>(-series->ZerothOrderHessian(at.AtX, at.E) / (this->Screening * this->Screening))
      : Mat<DIM>(-Mat<DIM>::Identity() / DIM);
    for (int c = 0; c < nc; ++c)
    {
      const double f = fx[static_cast<std::size_t>(c)];
      const double exact = series ? -f * ball : -f * (R * R - r2) / (2.0 * DIM);
      into.Value[static_cast<std::size_t>(c)] += exact + sum[static_cast<std::size_t>(c)] / K;
      into.ValueVariance[static_cast<std::size_t>(c)] += squares[static_cast<std::size_t>(c)] / (K * K);
      for (int d = 0; d < DIM && gradient; ++d)
      {
        const std::size_t v = static_cast<std::size_t>(nc + c * DIM + d);
        const double exactGradient = series ? -f * ballGradient[d] : f * p[d] / DIM;
        into.Gradient[static_cast<std::size_t>(c * DIM + d)] += exactGradient + sum[v] / K;
        into.GradientVariance[static_cast<std::size_t>(c * DIM + d)] += squares[v] / (K * K);
      }
      if (directional)
      {
        const std::size_t v = static_cast<std::size_t>(directionals + c);
        double exactDirectional = 0.0;
        for (int d = 0; d < DIM; ++d)
        {
          exactDirectional += want.Direction[static_cast<std::size_t>(d)] *
            (series ? -f * ballGradient[d] : f * p[d] / DIM);
        }
        into.Directional[static_cast<std::size_t>(c)] += exactDirectional + sum[v] / K;
        into.DirectionalVariance[static_cast<std::size_t>(c)] += squares[v] / (K * K);
      }
      for (int e = 0; e < DIM * DIM && hessian; ++e)
      {
        const std::size_t v = static_cast<std::size_t>(hessians + c * DIM * DIM + e);
        const double exactHessian = -f * ballHessian(e / DIM, e % DIM);
        into.Hessian[static_cast<std::size_t>(c * DIM * DIM + e)] += exactHessian + sum[v] / K;
        into.HessianVariance[static_cast<std::size_t>(c * DIM * DIM + e)] += squares[v] / (K * K);
      }
    }
    if (divergenceCurl)
    {
      // The exact part's Jacobian: −f_i(x) times ∇∫G_B.
      double divergence, curl[3];
      DivergenceAndCurl<DIM>(
        [&](int i, int j) {
          return series ? -fx[static_cast<std::size_t>(i)] * ballGradient[j]
                        : fx[static_cast<std::size_t>(i)] * p[j] / DIM;
        },
        divergence, curl);
      const double exact[4] = { divergence, curl[0], curl[1], curl[2] };
      for (int v = 0; v < 4; ++v)
      {
        into.DivergenceCurl[static_cast<std::size_t>(v)] +=
          exact[v] + sum[static_cast<std::size_t>(divergences + v)] / K;
        into.DivergenceCurlVariance[static_cast<std::size_t>(v)] +=
          squares[static_cast<std::size_t>(divergences + v)] / (K * K);
      }
    }
  }

  // A stratum's two draws (each a vector of terms): their mean joins `sum`,
  // and the square of their half difference, an unbiased estimate of the
  // mean's variance, joins `squares`.
  static void AddStratumPair(const std::vector<double>& first, const std::vector<double>& second,
    std::vector<double>& sum, std::vector<double>& squares)
  {
    for (std::size_t v = 0; v < second.size(); ++v)
    {
      sum[v] += 0.5 * (first[v] + second[v]);
      squares[v] += 0.25 * (first[v] - second[v]) * (first[v] - second[v]);
    }
  }

  // ∇·u and ∇×u of a sample's gradient entries (term[nc + c·DIM + d]) into
  // term[at .. at + 3].
  static void AddDivergenceCurlTerms(std::vector<double>& term, int nc, int at)
  {
    double divergence, curl[3];
    DivergenceAndCurl<DIM>(
      [&](int i, int j) { return term[static_cast<std::size_t>(nc + i * DIM + j)]; }, divergence,
      curl);
    term[static_cast<std::size_t>(at)] = divergence;
    for (int a = 0; a < 3; ++a)
    {
      term[static_cast<std::size_t>(at + 1 + a)] = curl[a];
    }
  }

  std::shared_ptr<const Boundary<DIM>> Shape;
  SphereCacheSettings Settings;
  std::function<std::unique_ptr<VolumeSource<DIM>>(double)> MakeSource;
  bool HasConcentrated = false;
  ConcentratedSourceSet<DIM> Concentrated; // the problem's, during an Answer
  int Orientation = 1;
  int Components = 1;
  double Screening = 0.0; // k = √c of the screened equation (0: Laplace's, Poisson's)
  Vec<DIM> Origin;
  double Coarsest = 1.0;
  int Levels = 1;
  std::unordered_map<std::uint64_t, std::size_t> Index;
  std::unordered_map<std::uint64_t, double> NodeRadius; // −1: outside
  std::vector<SphereData> Spheres;
  std::uint64_t WalksRun = 0;
};
} // namespace gridfree

#endif
