// Boundary value caching against pointwise walks on one slice (`./gridfree
// bench --cache`): a harmonic problem on an icosphere, a 100 × 100 slice
// through it, each method at several sizes, with its time and its RMSE
// against the exact solution. The cache answers the points outside its
// shell; the shell's points take pointwise walks in both methods, so the
// table splits the RMSE (and the time) there.
#include <gridfree/cache/BoundaryValueCache.h>
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
double Exact(const Vec3& x)
{
  return x[0] * x[0] - x[1] * x[1] + 0.3 * x[2];
}

double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct Slice
{
  std::vector<std::array<double, 3>> Points;
  std::vector<double> Exact;
};

// A 100 × 100 slice of the plane z = 0.1 over [−1, 1]², the points inside.
Slice MakeSlice(int n)
{
  Slice slice;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const Vec3 x(-1.0 + 2.0 * (i + 0.5) / n, -1.0 + 2.0 * (j + 0.5) / n, 0.1);
      if (x.norm() < 0.97)
      {
        slice.Points.push_back({ x[0], x[1], x[2] });
        slice.Exact.push_back(Exact(x));
      }
    }
  }
  return slice;
}

struct Errors
{
  double SumSquares = 0.0;
  int Count = 0;
  void Add(double estimate, double exact)
  {
    SumSquares += (estimate - exact) * (estimate - exact);
    ++Count;
  }
  double Rmse() const { return Count ? std::sqrt(SumSquares / Count) : 0.0; }
};
} // namespace

int main(int argc, char** argv)
{
  int levels = 7; // 327,680 triangles
  int resolution = 100;
  double offset = BoundaryCacheSettings().Offset;
  bool quick = false;
  int seeds = 4;
  std::vector<std::size_t> cacheSizes = { 1024, 4096, 16384 };
  std::vector<int> cacheWalks = { 16, 64 };
  for (int a = 1; a < argc; ++a)
  {
    if (!std::strcmp(argv[a], "--levels") && a + 1 < argc)
    {
      levels = std::atoi(argv[++a]);
    }
    else if (!std::strcmp(argv[a], "--offset") && a + 1 < argc)
    {
      offset = std::atof(argv[++a]);
    }
    else if (!std::strcmp(argv[a], "--seeds") && a + 1 < argc)
    {
      seeds = std::max(1, std::atoi(argv[++a]));
    }
    else if (!std::strcmp(argv[a], "--cache") && a + 2 < argc)
    {
      // One cache size instead of the sweep: --cache POINTS WALKS.
      cacheSizes = { static_cast<std::size_t>(std::atol(argv[++a])) };
      cacheWalks = { std::atoi(argv[++a]) };
    }
    else if (!std::strcmp(argv[a], "--quick"))
    {
      quick = true;
    }
    else if (!std::strcmp(argv[a], "--resolution") && a + 1 < argc)
    {
      resolution = std::atoi(argv[++a]);
    }
  }
  const SimplexMesh<3> mesh = MakeIcosphere(levels);
  const auto boundary = std::make_shared<const Boundary<3>>(MakeBoundary<3>(mesh, { Exact }));
  WalkSettings walk;
  walk.Epsilon = 1e-4;
  const Problem<3> problem(boundary, walk);
  const Slice slice = MakeSlice(resolution);
  std::printf("icosphere, %zu triangles; slice %d x %d, %zu points inside\n\n",
    mesh.Simplices.size(), resolution, resolution, slice.Points.size());

  // The shell's points, as the cache sees them.
  BoundaryCacheSettings shellProbe;
  shellProbe.CachePoints = 2;
  shellProbe.WalksPerCachePoint = 2;
  const BoundaryValueCache<3> probeShell(problem, shellProbe);
  CacheEvaluation flags;
  probeShell.Evaluate(slice.Points, false, flags);
  std::vector<std::array<double, 3>> shellPoints;
  std::vector<double> shellExact;
  for (std::size_t i = 0; i < slice.Points.size(); ++i)
  {
    if (flags.InShell[i])
    {
      shellPoints.push_back(slice.Points[i]);
      shellExact.push_back(slice.Exact[i]);
    }
  }
  std::printf("%zu of them in the shell (closer than %.3f to the boundary)\n\n", shellPoints.size(),
    probeShell.ShellDistance());

  std::printf("| method | size | seconds | RMSE outside the shell | RMSE in the shell | RMSE |\n");
  std::printf("|---|---|---|---|---|---|\n");
  // (Cache rows: seconds to build and evaluate one cache; the shell's
  // pointwise walks come on top, in their last column.)
  // Pointwise walks at every point.
  for (int walks : { 16, 64, 256, 1024 })
  {
    if (quick && walks != 64)
    {
      continue;
    }
    BatchRequest request;
    request.WalksPerPoint = walks;
    const auto start = std::chrono::steady_clock::now();
    const BatchEstimates u = problem.EstimateAll(slice.Points, request);
    const double seconds = Seconds(start);
    Errors outside, shell, all;
    for (std::size_t i = 0; i < slice.Points.size(); ++i)
    {
      (flags.InShell[i] ? shell : outside).Add(u.Value(i), slice.Exact[i]);
      all.Add(u.Value(i), slice.Exact[i]);
    }
    std::printf("| pointwise | %d walks per point | %.2f | %.2e | %.2e | %.2e |\n", walks, seconds,
      outside.Rmse(), shell.Rmse(), all.Rmse());
  }
  // The shell's points by 256 pointwise walks (both methods need them).
  Errors shellErrors;
  double shellSeconds = 0.0;
  {
    BatchRequest request;
    request.WalksPerPoint = 256;
    const auto start = std::chrono::steady_clock::now();
    const BatchEstimates near = problem.EstimateAll(shellPoints, request);
    shellSeconds = Seconds(start);
    for (std::size_t s = 0; s < shellPoints.size(); ++s)
    {
      shellErrors.Add(near.Value(s), shellExact[s]);
    }
  }
  // The cache outside the shell.
  for (std::size_t points : cacheSizes)
  {
    for (int walks : cacheWalks)
    {
      if (quick && points != 16384 && cacheSizes.size() > 1)
      {
        continue;
      }
      // Errors of one cache are correlated over the slice: the RMSE of one
      // cache is a noisy figure, so it is pooled over independent caches.
      double build = 0.0, evaluate = 0.0;
      Errors outside;
      double sumZ2 = 0.0;
      int zCount = 0;
      for (int seed = 0; seed < seeds; ++seed)
      {
        BoundaryCacheSettings settings;
        settings.Offset = offset;
        settings.CachePoints = points;
        settings.WalksPerCachePoint = walks;
        settings.Seed = static_cast<std::uint64_t>(seed);
        const auto start = std::chrono::steady_clock::now();
        const BoundaryValueCache<3> cache(problem, settings);
        build += Seconds(start);
        const auto evaluation = std::chrono::steady_clock::now();
        CacheEvaluation answer;
        cache.Evaluate(slice.Points, false, answer);
        evaluate += Seconds(evaluation);
        for (std::size_t i = 0; i < slice.Points.size(); ++i)
        {
          if (!answer.InShell[i])
          {
            outside.Add(answer.Value[i], slice.Exact[i]);
            const double z = (answer.Value[i] - slice.Exact[i]) / std::sqrt(answer.ValueVariance[i]);
            sumZ2 += z * z;
            ++zCount;
          }
        }
      }
      build /= seeds;
      evaluate /= seeds;
      std::printf("| cache | %zu points x %d walks, offset %g (build %.2f s, evaluate %.2f s; "
                  "mean z2 %.2f over %d caches) | %.2f | %.2e | %.2e (the shell's %.2f s) |\n",
        points, walks, offset, build, evaluate, sumZ2 / zCount, seeds, build + evaluate,
        outside.Rmse(), shellErrors.Rmse(), shellSeconds);
      // The same caches with the exact ∂u/∂n: the positions' share of the error.
      Errors positional;
      if (walks == cacheWalks.back())
      {
        for (int seed = 0; seed < seeds; ++seed)
        {
          BoundaryCacheSettings settings;
          settings.Offset = offset;
          settings.CachePoints = points;
          settings.WalksPerCachePoint = 2;
          settings.Seed = static_cast<std::uint64_t>(seed);
          const BoundaryValueCache<3> cache(problem, settings);
          std::vector<double> exact(cache.Size());
          for (std::size_t j = 0; j < cache.Size(); ++j)
          {
            const Vec3& z = cache.CachePoints()[j];
            exact[j] = Vec3(2.0 * z[0], -2.0 * z[1], 0.3).dot(cache.CacheNormals()[j]);
          }
          CacheEvaluation answer;
          cache.WithNormalDerivatives(exact).Evaluate(slice.Points, false, answer);
          for (std::size_t i = 0; i < slice.Points.size(); ++i)
          {
            if (!answer.InShell[i])
            {
              positional.Add(answer.Value[i], slice.Exact[i]);
            }
          }
        }
        std::printf("| cache, exact normal derivatives | %zu points (the positions' error) | | "
                    "%.2e | |\n",
          points, positional.Rmse());
      }
    }
  }
  return 0;
}
