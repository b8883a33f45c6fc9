// Boundary value caching against pointwise walks on one slice (`./gridfree
// bench --cache`): a harmonic problem on an icosphere, a 100 × 100 slice
// through it, each method at several sizes, with its time and its RMSE
// against the exact solution. The cache answers the points outside its
// shell; the shell's points take pointwise walks in both methods, so the
// table splits the RMSE (and the time) there.
#include <gridfree/cache/BoundaryValueCache.h>
#include "EstimatorChecks.h"
#include "TestMeshes.h"

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
  // The cache outside the shell, pointwise walks in it.
  for (std::size_t points : { std::size_t(1024), std::size_t(4096), std::size_t(16384) })
  {
    for (int walks : { 16, 64 })
    {
      if (quick && points != 16384)
      {
        continue;
      }
      BoundaryCacheSettings settings;
      settings.Offset = offset;
      settings.CachePoints = points;
      settings.WalksPerCachePoint = walks;
      const auto start = std::chrono::steady_clock::now();
      const BoundaryValueCache<3> cache(problem, settings);
      const double build = Seconds(start);
      CacheEvaluation answer;
      cache.Evaluate(slice.Points, false, answer);
      const double evaluate = Seconds(start) - build;
      BatchRequest request;
      request.WalksPerPoint = 256;
      const BatchEstimates near = problem.EstimateAll(shellPoints, request);
      const double seconds = Seconds(start);
      Errors outside, shell, all;
      std::size_t s = 0;
      for (std::size_t i = 0; i < slice.Points.size(); ++i)
      {
        const double estimate = answer.InShell[i] ? near.Value(s++) : answer.Value[i];
        (answer.InShell[i] ? shell : outside).Add(estimate, slice.Exact[i]);
        all.Add(estimate, slice.Exact[i]);
      }
      std::printf("| cache + 256 walks in the shell | %zu points x %d walks, offset %g (build %.2f s, "
                  "evaluate %.2f s) | %.2f | %.2e | %.2e | %.2e |\n",
        points, walks, offset, build, evaluate, seconds, outside.Rmse(), shell.Rmse(), all.Rmse());
    }
  }
  return 0;
}
