// The caches against pointwise walks on one slice (`./gridfree bench
// --cache`): a harmonic problem on a closed surface (the 327,680-triangle
// icosphere, the bumpy sphere of as many triangles, which is not convex, or
// the CT skin), a 100 × 100 slice through it, each method at several sizes,
// with its time and its RMSE against the exact solution.
//
// The sphere cache (SphereCache.h) answers the slice's points but those in
// its shell, which take pointwise walks (as many as the cache's walks per
// sphere); its rows count both, and the time pointwise walks take for the
// same RMSE (RMSE² × seconds is about constant for them: fitted on their
// rows). With --boundary, the boundary value cache's rows (BoundaryValueCache.h,
// icosphere only) follow: it answers the points outside its own shell, so
// the table splits the RMSE (and the time) there. With --peers (and the
// authors' sources configured in), their boundary value caching follows on
// the same slice, with the time the sphere cache takes at its RMSE.
#include <gridfree/cache/BoundaryValueCache.h>
#include <gridfree/cache/CacheProblemChecks.h>
#include <gridfree/cache/SphereCache.h>
#include "BenchmarkMeshes.h"
#include "EstimatorChecks.h"
#include "TestMeshes.h"
#ifdef GRIDFREE_WITH_ZOMBIE_CACHE
#include "ZombieCacheRows.h"
#endif

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
// The harmonic solution, in the shape's box scaled to [−1, 1]³.
struct Harmonic
{
  Vec3 Center = Vec3::Zero();
  double Scale = 1.0;
  double operator()(const Vec3& y) const
  {
    const Vec3 x = (y - this->Center) / this->Scale;
    return x[0] * x[0] - x[1] * x[1] + 0.3 * x[2];
  }
};

double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct Slice
{
  std::vector<std::array<double, 3>> Points;
  std::vector<double> Exact;
};

// An n × n slice of the plane z = 0.1 (in the box scaled to [−1, 1]³) over
// the box, the points inside at least 3% of the scale from the boundary
// (on the unit icosphere: |x| < 0.97).
Slice MakeSlice(const Boundary<3>& boundary, const Harmonic& exact, const bench::Box& box, int n)
{
  const int orientation = OutwardOrientation<3>(boundary);
  Slice slice;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const Vec3 x(box.Min[0] + (box.Max[0] - box.Min[0]) * (i + 0.5) / n,
        box.Min[1] + (box.Max[1] - box.Min[1]) * (j + 0.5) / n,
        exact.Center[2] + 0.1 * exact.Scale);
      const ClosestPointResult<3> hit = boundary.ClosestPoint(x);
      if (!OutsideClosedMesh<3>(boundary, orientation, x, hit) && hit.distance > 0.03 * exact.Scale)
      {
        slice.Points.push_back({ x[0], x[1], x[2] });
        slice.Exact.push_back(exact(x));
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
// The boundary value cache's rows (the unit icosphere only: the exact
// normal derivatives below are the icosphere's).
void BoundaryCacheRows(const Problem<3>& problem, const Slice& slice, double offset, bool quick,
  int seeds, const std::vector<std::size_t>& cacheSizes, const std::vector<int>& cacheWalks)
{
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

  std::printf("Boundary value cache:\n\n| method | size | seconds | RMSE outside the shell | RMSE in the shell | RMSE |\n");
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
}

// Pointwise walks at every point of the slice: one row per walk count,
// and the constant C of RMSE² × seconds ≈ C (their mean), for the time
// they would take at another RMSE.
double PointwiseRows(const Problem<3>& problem, const Slice& slice, bool quick)
{
  double constant = 0.0;
  int rows = 0;
  for (int walks : { 16, 64, 256, 1024 })
  {
    if (quick && (walks == 16 || walks == 1024))
    {
      continue;
    }
    BatchRequest request;
    request.WalksPerPoint = walks;
    const auto start = std::chrono::steady_clock::now();
    const BatchEstimates u = problem.EstimateAll(slice.Points, request);
    const double seconds = Seconds(start);
    Errors all;
    for (std::size_t i = 0; i < slice.Points.size(); ++i)
    {
      all.Add(u.Value(i), slice.Exact[i]);
    }
    constant += all.Rmse() * all.Rmse() * seconds;
    ++rows;
    std::printf("| pointwise | %d walks per point | %.2f | %.2e | | |\n", walks, seconds, all.Rmse());
  }
  return constant / rows;
}

// The sphere cache at several walks per sphere, each pooled over `seeds`
// caches (one cache's errors are correlated within a sphere): seconds to
// make the spheres and answer, plus the shell's pointwise walks; the RMSE
// over every point; the pointwise time at that RMSE. Returns the rows'
// (seconds, RMSE).
struct TimeAndError
{
  double Seconds;
  double Rmse;
};

std::vector<TimeAndError> SphereCacheRows(const Problem<3>& problem, const Slice& slice,
  bool quick, int seeds, double pointwiseConstant)
{
  std::vector<TimeAndError> rows;
  for (int samples : { 16, 64, 256, 1024 })
  {
    if (quick && (samples == 16 || samples == 1024))
    {
      continue;
    }
    double seconds = 0.0, sumZ2 = 0.0;
    std::size_t spheres = 0, zCount = 0, shell = 0;
    Errors all;
    for (int seed = 0; seed < seeds; ++seed)
    {
      SphereCacheSettings settings;
      settings.SamplesPerSphere = samples;
      settings.Seed = static_cast<std::uint64_t>(seed);
      const auto start = std::chrono::steady_clock::now();
      SphereCache<3> cache(problem, settings);
      CacheEvaluation answer;
      cache.Answer(problem, slice.Points, false, answer);
      std::vector<std::array<double, 3>> walked;
      std::vector<std::size_t> walkedIndex;
      for (std::size_t i = 0; i < slice.Points.size(); ++i)
      {
        if (!std::isfinite(answer.Value[i]))
        {
          walked.push_back(slice.Points[i]);
          walkedIndex.push_back(i);
        }
      }
      BatchRequest request;
      request.WalksPerPoint = samples;
      request.Seed = static_cast<std::uint64_t>(seed);
      const BatchEstimates near = problem.EstimateAll(walked, request);
      seconds += Seconds(start);
      spheres += cache.SphereCount();
      shell += walked.size();
      for (std::size_t k = 0; k < walked.size(); ++k)
      {
        answer.Value[walkedIndex[k]] = near.Value(k);
        answer.ValueVariance[walkedIndex[k]] = near.ValueVariance(k);
      }
      for (std::size_t i = 0; i < slice.Points.size(); ++i)
      {
        all.Add(answer.Value[i], slice.Exact[i]);
        const double z = (answer.Value[i] - slice.Exact[i]) / std::sqrt(answer.ValueVariance[i]);
        sumZ2 += z * z;
        ++zCount;
      }
    }
    seconds /= seeds;
    const double equal = pointwiseConstant / (all.Rmse() * all.Rmse());
    std::printf("| sphere cache | %d walks per sphere (%zu spheres, %zu points walked in the "
                "shell; mean z2 %.2f over %d caches) | %.2f | %.2e | %.2f | %.1fx |\n",
      samples, spheres / static_cast<std::size_t>(seeds), shell / static_cast<std::size_t>(seeds),
      sumZ2 / static_cast<double>(zCount), seeds, seconds, all.Rmse(), equal, equal / seconds);
    rows.push_back({ seconds, all.Rmse() });
  }
  return rows;
}

// The seconds a method with these rows takes for `rmse`: interpolated in
// log–log between the two rows around it, or from the nearest row with
// RMSE² × seconds constant (the Monte Carlo rate) outside them.
double SecondsAtRmse(std::vector<TimeAndError> rows, double rmse)
{
  std::sort(rows.begin(), rows.end(),
    [](const TimeAndError& a, const TimeAndError& b) { return a.Rmse > b.Rmse; });
  for (std::size_t k = 0; k + 1 < rows.size(); ++k)
  {
    const TimeAndError& a = rows[k];
    const TimeAndError& b = rows[k + 1];
    if (rmse <= a.Rmse && rmse >= b.Rmse)
    {
      const double t = std::log(rmse / a.Rmse) / std::log(b.Rmse / a.Rmse);
      return std::exp(std::log(a.Seconds) + t * std::log(b.Seconds / a.Seconds));
    }
  }
  const TimeAndError& nearest = rmse > rows.front().Rmse ? rows.front() : rows.back();
  return nearest.Seconds * (nearest.Rmse / rmse) * (nearest.Rmse / rmse);
}

#ifdef GRIDFREE_WITH_ZOMBIE_CACHE
// The authors' boundary value caching on the same slice, at several cache
// sizes and walks per cache point, three caches each, against the sphere
// cache's time at the same RMSE (their defaults: 1,024 points, 640 walks).
void ZombieCacheRows(const SimplexMesh<3>& mesh, const Harmonic& exact, const Slice& slice,
  double epsilon, bool quick, const std::vector<TimeAndError>& ours)
{
  std::vector<std::array<double, 3>> vertices;
  for (const Vec3& v : mesh.Vertices)
  {
    vertices.push_back({ v[0], v[1], v[2] });
  }
  const std::vector<std::array<std::int64_t, 3>> triangles(mesh.Simplices.begin(), mesh.Simplices.end());
  const auto u = [&exact](const std::array<double, 3>& x) { return exact(Vec3(x[0], x[1], x[2])); };
  std::printf("\n| zombie boundary value caching | seconds (+ hierarchy) | RMSE | points walked "
              "near the boundary | sphere cache seconds at this RMSE | less time |\n");
  std::printf("|---|---|---|---|---|---|\n");
  const std::vector<std::pair<int, int>> sizes = quick
    ? std::vector<std::pair<int, int>>{ { 1024, 640 }, { 4096, 128 } }
    : std::vector<std::pair<int, int>>{ { 1024, 128 }, { 1024, 640 }, { 4096, 128 }, { 4096, 640 },
        { 16384, 128 } };
  for (const auto& size : sizes)
  {
    bench::ZombieCacheSettings settings;
    settings.CachePoints = size.first;
    settings.GradientWalks = size.second;
    settings.Epsilon = epsilon;
    // Pooled over `runs` caches, as the sphere cache's rows are (their
    // samplers draw a new cache each run): the RMSE over all their
    // answers, the mean seconds.
    const int runs = quick ? 1 : 3;
    double seconds = 0.0, setup = 0.0, squares = 0.0;
    int near = 0;
    for (int run = 0; run < runs; ++run)
    {
      const bench::ZombieCacheResult r =
        bench::RunZombieBoundaryValueCaching(vertices, triangles, u, slice.Points, settings);
      seconds += r.Seconds / runs;
      setup += r.SetupSeconds / runs;
      squares += r.Rmse * r.Rmse / runs;
      near = std::max(near, r.NearBoundaryPoints);
    }
    const double rmse = std::sqrt(squares);
    const double equal = SecondsAtRmse(ours, rmse);
    std::printf("| %d cache points x %d walks | %.2f (+ %.2f) | %.2e | %d | %.2f | %.1fx |\n",
      size.first, size.second, seconds, setup, rmse, near, equal, seconds / equal);
    std::fflush(stdout);
  }
}
#endif
} // namespace

int main(int argc, char** argv)
{
  int levels = 7; // 327,680 triangles
  int resolution = 100;
  double offset = BoundaryCacheSettings().Offset;
  bool quick = false, boundaryRows = false, peers = false;
  int seeds = 4;
  std::string shape = "icosphere", data;
  std::vector<std::size_t> cacheSizes = { 1024, 4096, 16384 };
  std::vector<int> cacheWalks = { 16, 64 };
  for (int a = 1; a < argc; ++a)
  {
    if (!std::strcmp(argv[a], "--levels") && a + 1 < argc)
    {
      levels = std::atoi(argv[++a]);
    }
    else if (!std::strcmp(argv[a], "--shape") && a + 1 < argc)
    {
      shape = argv[++a];
    }
    else if (!std::strcmp(argv[a], "--data") && a + 1 < argc)
    {
      data = argv[++a];
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
      // One boundary cache size instead of the sweep: --cache POINTS WALKS.
      cacheSizes = { static_cast<std::size_t>(std::atol(argv[++a])) };
      cacheWalks = { std::atoi(argv[++a]) };
    }
    else if (!std::strcmp(argv[a], "--quick"))
    {
      quick = true;
    }
    else if (!std::strcmp(argv[a], "--boundary"))
    {
      boundaryRows = true;
    }
    else if (!std::strcmp(argv[a], "--peers"))
    {
      peers = true;
    }
    else if (!std::strcmp(argv[a], "--resolution") && a + 1 < argc)
    {
      resolution = std::atoi(argv[++a]);
    }
  }
  SimplexMesh<3> mesh;
  if (shape == "bumpy")
  {
    mesh = bench::MakeBumpySphere(128); // 327,680 triangles
  }
  else if (shape == "ct")
  {
    // The CT skin: --data, or the Data folder GRIDFREE_DATA names.
    if (data.empty() && std::getenv("GRIDFREE_DATA"))
    {
      data = std::string(std::getenv("GRIDFREE_DATA")) + "/headsq_skin_iso500_closed.vtp";
    }
    if (data.empty())
    {
      std::fprintf(stderr, "--shape ct needs --data FILE.vtp (or GRIDFREE_DATA)\n");
      return 1;
    }
    mesh = bench::ReadPolyDataTriangles(data);
  }
  else
  {
    shape = "icosphere";
    mesh = MakeIcosphere(levels);
  }
  const bench::Box box = bench::BoundsOf(mesh);
  Harmonic exact;
  exact.Center = box.Center();
  exact.Scale = 0.5 * (box.Max - box.Min).maxCoeff();
  const auto boundary = std::make_shared<const Boundary<3>>(
    MakeBoundary<3>(mesh, { [exact](const Vec3& x) { return exact(x); } }));
  WalkSettings walk;
  walk.Epsilon = 1e-4 * exact.Scale;
  const Problem<3> problem(boundary, walk);
  const Slice slice = MakeSlice(*boundary, exact, box, resolution);
  std::printf("%s, %zu triangles; slice %d x %d, %zu points inside\n\n", shape.c_str(),
    mesh.Simplices.size(), resolution, resolution, slice.Points.size());

  std::printf("| method | size | seconds | RMSE | pointwise seconds at this RMSE | less time |\n");
  std::printf("|---|---|---|---|---|---|\n");
  const double constant = PointwiseRows(problem, slice, quick);
  const std::vector<TimeAndError> sphereRows = SphereCacheRows(problem, slice, quick, seeds, constant);
  if (peers)
  {
#ifdef GRIDFREE_WITH_ZOMBIE_CACHE
    ZombieCacheRows(mesh, exact, slice, walk.Epsilon, quick, sphereRows);
#else
    std::printf("\n(no zombie rows: configure with GRIDFREE_ZOMBIE_SOURCE_DIR, "
                "GRIDFREE_FCPW_SOURCE_DIR and GRIDFREE_PCG32_INCLUDE_DIR)\n");
#endif
  }
  if (boundaryRows && shape == "icosphere")
  {
    std::printf("\n");
    BoundaryCacheRows(problem, slice, offset, quick, seeds, cacheSizes, cacheWalks);
  }
  return 0;
}
