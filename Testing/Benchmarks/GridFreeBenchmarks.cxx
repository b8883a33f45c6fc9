// Closest-point and walk-on-spheres throughput, beside VTK's
// vtkStaticCellLocator::FindClosestPoint and Embree (when available) on the
// same queries in the same run, plus BVH memory, build time and scaling.
//
// Run with --help for the options. Prints Markdown tables; quote ratios, not
// absolute numbers (shared machines are noisy).
#include "BenchmarkMeshes.h"
#include "BenchmarkTables.h"
#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/SimdDispatch.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#ifdef GRIDFREE_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

#include "vtkCellArray.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

using namespace gridfree;
using namespace gridfree::bench;

namespace
{
// ---------------------------------------------------------------- options

const char* const kUsage = R"(Usage: GridFreeBenchmarks [options]

Parts (default: queries, walks, scaling and derivatives; naming parts runs
only those):
  --only-queries      closest-point, distance and ray tables, BVH memory and
                      build time, agreement with VTK and Embree
  --only-walks        walks/s
  --scaling           query cost against triangle count (bumpy spheres,
                      10k to 2.6M triangles)
  --large             build of a 10,000,000-triangle soup: seconds, bytes,
                      peak resident memory (not in the default run)
  --derivatives-only  cost of gradient and Hessian estimates
  --all               every part, --large included

Meshes (a 327,680-triangle icosphere and a 1,310,720-triangle bumpy sphere
are always included):
  --data PATH         the CT skin surface (.vtp); ./gridfree bench passes it
  --mesh PATH         one more surface (.vtp, polygons fan-triangulated), e.g.
                      a raw isosurface triangle soup; may be repeated

Sizes:
  --queries N         at most N distinct query points per set (200000)
  --walk-points N     at most N start points per walk row (2000)
  --seconds S         target time of each measurement (1.0)
  --quick             short smoke run: small counts and times, small scaling
  --help              this text
)";

struct Options
{
  std::string Data;
  std::vector<std::string> ExtraMeshes;
  std::size_t Queries = 200000;
  std::size_t WalkPoints = 2000;
  double Seconds = 1.0;
  double VtkSeconds = 3.0; // VTK's locator is slow far from the surface
  bool Quick = false;
  // Parts to run.
  bool PartQueries = false, PartWalks = false, PartScaling = false, PartLarge = false,
       PartDerivatives = false;
};

// Selects every part in `parts` (pointers into Options).
void Select(const std::vector<bool*>& parts)
{
  for (bool* p : parts)
  {
    *p = true;
  }
}

// Parses argv; returns false (after printing why) when the run should stop.
bool ParseOptions(int argc, char* argv[], Options& o, int& exitCode)
{
  const std::vector<std::pair<std::string, std::vector<bool*>>> partOptions = {
    { "--only-queries", { &o.PartQueries } }, { "--only-walks", { &o.PartWalks } },
    { "--scaling", { &o.PartScaling } }, { "--large", { &o.PartLarge } },
    { "--derivatives-only", { &o.PartDerivatives } },
    { "--all", { &o.PartQueries, &o.PartWalks, &o.PartScaling, &o.PartLarge, &o.PartDerivatives } }
  };
  bool anyPart = false;
  try
  {
    for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc)
        {
          throw std::invalid_argument(a + " needs a value");
        }
        return argv[++i];
      };
      const auto part = std::find_if(partOptions.begin(), partOptions.end(),
        [&](const auto& entry) { return a == entry.first; });
      if (part != partOptions.end())
      {
        Select(part->second);
        anyPart = true;
      }
      else if (a == "--help" || a == "-h")
      {
        std::fputs(kUsage, stdout);
        exitCode = 0;
        return false;
      }
      else if (a == "--data")
      {
        o.Data = value();
      }
      else if (a == "--mesh")
      {
        o.ExtraMeshes.push_back(value());
      }
      else if (a == "--queries")
      {
        o.Queries = std::stoul(value());
      }
      else if (a == "--walk-points")
      {
        o.WalkPoints = std::stoul(value());
      }
      else if (a == "--seconds")
      {
        o.Seconds = std::stod(value());
      }
      else if (a == "--quick")
      {
        o.Quick = true;
      }
      else
      {
        throw std::invalid_argument("unknown option " + a);
      }
    }
    if (o.Queries == 0 || o.WalkPoints == 0 || !(o.Seconds > 0.0))
    {
      throw std::invalid_argument("counts and times must be positive");
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s\n\n%s", e.what(), kUsage);
    exitCode = 2;
    return false;
  }
  if (!anyPart)
  {
    Select({ &o.PartQueries, &o.PartWalks, &o.PartScaling, &o.PartDerivatives });
  }
  if (o.Quick)
  {
    o.Queries = std::min<std::size_t>(o.Queries, 20000);
    o.WalkPoints = std::min<std::size_t>(o.WalkPoints, 200);
    o.Seconds = std::min(o.Seconds, 0.1);
    o.VtkSeconds = 0.3;
  }
  return true;
}

// ---------------------------------------------------------------- memory

// Written once per measurement so the compiler cannot drop the queries.
volatile double g_sink = 0.0;

double PeakRssMiB()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0; // kilobytes on Linux
}

double CurrentRssMiB()
{
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  if (!(statm >> pages >> resident))
  {
    return -1.0;
  }
  return resident * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}


// ---------------------------------------------------------------- targets

// One figure of the performance targets, collected by the parts and printed
// last so a run ends with its verdict.
struct Target
{
  std::string What;
  double Measured;
  double Goal;
  bool AtLeast; // the figure must be >= Goal (else <= Goal)
  const char* Format;
};

void PrintTargets(const std::vector<Target>& targets)
{
  if (targets.empty())
  {
    return;
  }
  std::printf("\n## Targets (1 thread)\n\n");
  PrintHeader({ "figure", "measured", "target", "met" }, 1);
  for (const Target& t : targets)
  {
    const bool met = t.AtLeast ? t.Measured >= t.Goal : t.Measured <= t.Goal;
    PrintRow({ t.What, Number(t.Measured, t.Format),
      std::string(t.AtLeast ? "≥ " : "≤ ") + Number(t.Goal, t.Format), met ? "yes" : "no" });
  }
}

// ---------------------------------------------------------------- meshes

std::vector<Mesh> LoadMeshes(const Options& o)
{
  std::vector<Mesh> meshes;
  Mesh icosphere{ "icosphere", testing::MakeIcosphere(7), 1.0, 0.9, true, true };
  meshes.push_back(std::move(icosphere));
  Mesh bumpy{ "bumpy sphere", MakeBumpySphere(256), 1.0, 0.9, false };
  meshes.push_back(std::move(bumpy));
  if (!o.Data.empty())
  {
    Mesh skin{ "CT skin", ReadPolyDataTriangles(o.Data), 1.0, 1.0, true };
    skin.Scale = HalfLongestSide(skin.Geometry);
    meshes.push_back(std::move(skin));
  }
  for (const std::string& path : o.ExtraMeshes)
  {
    Mesh extra{ FileStem(path), ReadPolyDataTriangles(path), 1.0, 1.0, false };
    extra.Scale = HalfLongestSide(extra.Geometry);
    meshes.push_back(std::move(extra));
  }
  for (Mesh& m : meshes)
  {
    m.Name += " (" + Triangles(m.Geometry.Simplices.size()) + " tri)";
  }
  return meshes;
}

vtkSmartPointer<vtkPolyData> ToVtk(const TriangleMesh& mesh)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.Vertices.size()));
  for (std::size_t i = 0; i < mesh.Vertices.size(); ++i)
  {
    points->SetPoint(static_cast<vtkIdType>(i), mesh.Vertices[i].data());
  }
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(static_cast<vtkIdType>(mesh.Simplices.size()),
    static_cast<vtkIdType>(3 * mesh.Simplices.size()));
  for (const auto& t : mesh.Simplices)
  {
    const vtkIdType ids[3] = { t[0], t[1], t[2] };
    polys->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetPolys(polys);
  return pd;
}

// ---------------------------------------------------------------- queries

#ifdef GRIDFREE_HAVE_EMBREE
using Peer = EmbreePeer;
#else
struct Peer // never constructed: every Embree cell prints "–"
{};
#endif

// Per mesh, for the memory and agreement tables printed after the queries.
struct MeshReport
{
  std::string Name;
  std::size_t Triangles = 0;
  double OursBuild = 0.0, OursBytes = 0.0, VtkBuild = 0.0;
  double EmbreeBuild = -1.0, EmbreeBytes = -1.0;
  double Diagonal = 0.0;
  double VtkDiff[2] = { -1.0, -1.0 };           // uniform, near surface
  double EmbreeDiff[2] = { -1.0, -1.0 };        // uniform, near surface
  double ClosestPointVsVtk[2] = { -1.0, -1.0 }; // ours/VTK, 1 thread
  double LevelRate[2][3] = { { -1.0, -1.0, -1.0 }, { -1.0, -1.0, -1.0 } }; // per SimdLevel
};

struct Rates
{
  double One = -1.0, All = -1.0;
};

template <typename Body>
Rates MeasureBoth(std::size_t count, int allThreads, const Body& body)
{
  return { RatePerSecond(count, 1, body), RatePerSecond(count, allThreads, body) };
}

// VTK's locator on one thread (FindClosestPoint keeps per-locator scratch
// state), time-boxed; writes distances for the prefix it reached.
double VtkRate(vtkStaticCellLocator* locator, const std::vector<Vec3>& queries, double seconds,
  std::vector<double>& distances, std::size_t& reached)
{
  vtkNew<vtkGenericCell> cell;
  reached = 0;
  const auto start = Clock::now();
  for (; reached < queries.size(); ++reached)
  {
    if ((reached & 63) == 0 && Seconds(start) > seconds)
    {
      break;
    }
    double x[3] = { queries[reached][0], queries[reached][1], queries[reached][2] }, cp[3], d2;
    vtkIdType cellId;
    int subId;
    locator->FindClosestPoint(x, cp, cell, cellId, subId, d2);
    distances[reached] = std::sqrt(d2);
  }
  return reached / Seconds(start);
}

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b, std::size_t n)
{
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  return worst;
}

void PrintQueryRow(
  const std::string& mesh, const std::string& what, Rates ours, double vtk, Rates embree)
{
  PrintRow({ mesh, what, Number(ours.One), Number(ours.All), Number(vtk), Number(embree.One),
    Number(embree.All), Ratio(ours.One, vtk), Ratio(ours.One, embree.One) });
}

// One query set (uniform in the box or near the surface): closest point and
// distance only, ours / VTK / Embree, then Embree rays from the same points.
void QuerySet(const Mesh& mesh, Bvh<3>& tree, vtkStaticCellLocator* locator,
  const Peer* embree, bool nearSurface, const Options& o, MeshReport& report)
{
  const int allThreads = ResolveThreadCount(0);
  const auto queries = MakeQueries(mesh.Geometry, nearSurface, o.Queries, 7);
  const std::size_t size = queries.size();
  const std::string where = nearSurface ? "near surface" : "uniform in box";
  std::vector<double> ours(size), vtk(size), theirs(size);

  // Measurements cycle through the set when they need more calls than it
  // holds; only the first pass stores answers, so no two threads write the
  // same element.
  auto store = [size](std::vector<double>& out, std::size_t i, double d) {
    if (i < size)
    {
      out[i] = d;
    }
  };
  auto oursClosest = [&](std::size_t i) {
    store(ours, i, tree.ClosestPoint(queries[i % size]).distance);
  };
  auto oursDistance = [&](std::size_t i) { store(ours, i, tree.Distance(queries[i % size])); };
  const std::size_t count = CountForSeconds(o.Seconds, 50 * size, oursClosest);

  std::size_t vtkReached = 0;
  const double vtkRate = VtkRate(locator, queries, o.VtkSeconds, vtk, vtkReached);
  const Rates oursCp = MeasureBoth(count, allThreads, oursClosest);
  const Rates oursD = MeasureBoth(count, allThreads, oursDistance);
  report.VtkDiff[nearSurface] = MaxDifference(ours, vtk, std::min(vtkReached, count));

  // The same closest-point queries with each instruction set the CPU has.
  const gridfree::SimdLevel chosen = tree.GetSimdLevel();
  for (const auto level :
    { gridfree::SimdLevel::Sse2, gridfree::SimdLevel::Avx2, gridfree::SimdLevel::Avx512 })
  {
    if (tree.SetSimdLevel(level) == level)
    {
      report.LevelRate[nearSurface][static_cast<int>(level)] = RatePerSecond(count, 1, oursClosest);
    }
  }
  tree.SetSimdLevel(chosen);

  Rates embreeCp, embreeD, rays;
  double hitFraction = -1.0;
#ifdef GRIDFREE_HAVE_EMBREE
  if (embree)
  {
    auto theirClosest = [&](std::size_t i) {
      store(theirs, i, embree->ClosestPoint(queries[i % size]).Distance);
    };
    auto theirDistance = [&](std::size_t i) {
      store(theirs, i, embree->Distance(queries[i % size]));
    };
    embreeCp = MeasureBoth(count, allThreads, theirClosest);
    embreeD = MeasureBoth(count, allThreads, theirDistance);
    report.EmbreeDiff[nearSurface] = MaxDifference(ours, theirs, std::min(count, size));

    // Rays from the same points in random directions, to the first hit.
    std::vector<Vec3> directions(size);
    std::mt19937_64 rng(23);
    std::normal_distribution<double> normal;
    for (Vec3& d : directions)
    {
      d = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    }
    std::atomic<std::size_t> hits{ 0 };
    auto ray = [&](std::size_t i) {
      float t;
      if (embree->Intersect(queries[i % size], directions[i % size], t) && i < size)
      {
        hits.fetch_add(1, std::memory_order_relaxed);
      }
    };
    const std::size_t rayCount = CountForSeconds(o.Seconds, 500 * size, ray);
    hits = 0;
    rays = MeasureBoth(rayCount, allThreads, ray);
    hitFraction = double(hits.load()) / double(2 * std::min(rayCount, size));
  }
#else
  (void)embree;
  (void)theirs;
#endif

  report.ClosestPointVsVtk[nearSurface] = oursCp.One / vtkRate;
  PrintQueryRow(mesh.Name, "closest point, " + where, oursCp, vtkRate, embreeCp);
  PrintQueryRow(mesh.Name, "distance only, " + where, oursD, vtkRate, embreeD);
  if (rays.One > 0.0)
  {
    char what[96];
    std::snprintf(what, sizeof(what), "Embree rays, from points %s (%.0f%% hit)",
      nearSurface ? "near surface" : "uniform in box", 100.0 * hitFraction);
    PrintQueryRow(mesh.Name, what, Rates{}, -1.0, rays);
  }
}

void QueriesPart(const std::vector<Mesh>& meshes, const Options& o, std::vector<Target>& targets)
{
  const int allThreads = ResolveThreadCount(0);
  std::printf("\n## Closest-point queries/s\n\nOurs on 1 and %d threads, "
              "vtkStaticCellLocator::FindClosestPoint on 1 thread (time-boxed to %.1f s), "
              "Embree rtcPointQuery with the same exact triangle distance on 1 and %d "
              "threads; same query points for all. Ratios are 1 thread against 1 thread. "
              "The Embree ray rows (rtcIntersect1 to the first hit, from the same points in "
              "random directions) are a speed-of-light reference with no counterpart of "
              "ours.\n\n",
    allThreads, o.VtkSeconds, allThreads);
  PrintHeader({ "mesh", "measure", "ours 1T", "ours allT", "VTK 1T", "Embree 1T", "Embree allT",
                "ours/VTK", "ours/Embree" },
    2);

  std::vector<MeshReport> reports;
  for (const Mesh& mesh : meshes)
  {
    MeshReport report;
    report.Name = mesh.Name;
    report.Triangles = mesh.Geometry.Simplices.size();
    report.Diagonal = BoundsOf(mesh.Geometry).Diagonal();

    Bvh<3> tree;
    const auto buildStart = Clock::now();
    tree.Build(mesh.Geometry.Vertices, mesh.Geometry.Simplices);
    report.OursBuild = Seconds(buildStart);
    report.OursBytes = double(tree.MemoryBytes());

    auto polydata = ToVtk(mesh.Geometry);
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(polydata);
    const auto locatorStart = Clock::now();
    locator->BuildLocator();
    report.VtkBuild = Seconds(locatorStart);

    std::unique_ptr<Peer> embree;
#ifdef GRIDFREE_HAVE_EMBREE
    try
    {
      embree = std::make_unique<Peer>(mesh.Geometry.Vertices, mesh.Geometry.Simplices);
      report.EmbreeBuild = embree->BuildSeconds();
      report.EmbreeBytes = double(embree->MemoryBytes());
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "Embree: %s\n", e.what());
    }
#endif
    for (bool nearSurface : { false, true })
    {
      QuerySet(mesh, tree, locator.Get(), embree.get(), nearSurface, o, report);
    }
    reports.push_back(report);
    targets.push_back({ mesh.Name + ": closest point uniform in box, ours/VTK",
      report.ClosestPointVsVtk[0], 40.0, true, "%.1fx" });
    targets.push_back({ mesh.Name + ": closest point near surface, ours/VTK",
      report.ClosestPointVsVtk[1], 25.0, true, "%.1fx" });
  }

  std::printf("\n## BVH memory and build time\n\nBytes per triangle of the hierarchy "
              "(nodes, triangles with their vertices inline, original indices); Embree's "
              "count is what its memory monitor reports for the scene (its hierarchy and "
              "its float vertex and index buffers; not the double-precision copy of the "
              "triangles its distance callback reads). Our build runs on all threads (subtrees of 2^12 triangles or more in parallel), VTK's on 1, "
              "Embree's on all threads.\n\n");
  PrintHeader({ "mesh", "triangles", "ours build (s)", "ours bytes/tri", "VTK locator build (s)",
                "Embree build (s)", "Embree bytes/tri" },
    1);
  for (const MeshReport& r : reports)
  {
    const double n = double(r.Triangles);
    PrintRow({ r.Name, Triangles(r.Triangles), Number(r.OursBuild, "%.3f"),
      Number(r.OursBytes / n, "%.1f"), Number(r.VtkBuild, "%.3f"), Number(r.EmbreeBuild, "%.3f"),
      Number(r.EmbreeBytes > 0.0 ? r.EmbreeBytes / n : -1.0, "%.1f") });
  }

  std::printf("\n## Instruction sets\n\nOur closest-point queries/s on 1 thread with the "
              "searches compiled for each instruction set this CPU supports (\"–\": not "
              "supported); all give the same answers. The tables above use %s, chosen at run "
              "time (GRIDFREE_SIMD lowers it).\n\n",
    gridfree::SimdLevelName(gridfree::DefaultSimdLevel()));
  PrintHeader({ "mesh", "query set", "sse2", "avx2", "avx512", "avx2/sse2", "avx512/sse2" }, 2);
  for (const MeshReport& r : reports)
  {
    for (int set = 0; set < 2; ++set)
    {
      const double* rate = r.LevelRate[set];
      PrintRow({ r.Name, set ? "near surface" : "uniform in box", Number(rate[0]),
        Number(rate[1]), Number(rate[2]), Gain(rate[1], rate[0]), Gain(rate[2], rate[0]) });
    }
  }

  std::printf(
    "\n## Agreement\n\nLargest absolute difference between our distances and "
    "VTK's (on the queries VTK reached) and Embree's (on all queries measured), in "
    "parentheses relative to the box diagonal. Ours are exact in double; Embree traverses in "
    "float but its callback uses our double kernel; VTK computes in double.\n\n");
  PrintHeader({ "mesh", "query set", "ours vs VTK", "ours vs Embree", "box diagonal" }, 2);
  for (const MeshReport& r : reports)
  {
    for (int set = 0; set < 2; ++set)
    {
      auto cell = [&](double d) {
        return d < 0.0 ? std::string("–")
                       : Number(d, "%.2g") + " (" + Number(d / r.Diagonal, "%.1g") + ")";
      };
      PrintRow({ r.Name, set ? "near surface" : "uniform in box", cell(r.VtkDiff[set]),
        cell(r.EmbreeDiff[set]), Number(r.Diagonal, "%.4g") });
    }
  }
}

// ---------------------------------------------------------------- walks

struct WalkRates
{
  Rates PerSecond;
  double StepsPerWalk = 0.0;
};

// Laplace walks (boundary value 1) from the given starts, 16 walks per
// point, on 1 and all threads.
WalkRates MeasureWalks(
  const Boundary<3>& boundary, double epsilon, const std::vector<Vec3>& starts, const Options& o)
{
  const int walksPerPoint = 16;
  WalkSettings settings;
  settings.Epsilon = epsilon;
  settings.Problem = Equation::Laplace;
  const std::size_t size = starts.size();
  std::atomic<std::uint64_t> steps{ 0 }, walks{ 0 };
  auto walk = [&](std::size_t i) {
    WalkOnSpheresEstimator<3> estimator(boundary, settings);
    RunningStatistics stats(1);
    WalkCounters counters;
    const Vec3& p = starts[i % size];
    const double xyz[3] = { p[0], p[1], p[2] };
    estimator.EstimatePoint(xyz, 1, 0, walksPerPoint, stats, counters);
    steps.fetch_add(counters.Steps, std::memory_order_relaxed);
    walks.fetch_add(counters.Walks, std::memory_order_relaxed);
  };
  const std::size_t count = CountForSeconds(2.0 * o.Seconds, 50 * size, walk);
  steps = walks = 0;
  WalkRates result;
  result.PerSecond = MeasureBoth(count, ResolveThreadCount(0), walk);
  result.PerSecond.One *= walksPerPoint;
  result.PerSecond.All *= walksPerPoint;
  result.StepsPerWalk = double(steps.load()) / double(std::max<std::uint64_t>(walks.load(), 1));
  return result;
}

void WalksPart(const std::vector<Mesh>& meshes, const Options& o, std::vector<Target>& targets)
{
  const int allThreads = ResolveThreadCount(0);
  std::printf("\n## Walks/s\n\nLaplace walk on spheres, 16 walks per start point, on 1 and %d "
              "threads. R is the mesh's length scale: 1 for the unit spheres (so ε = 1e-3·R "
              "is ε = 1e-3 there), half the longest box side otherwise. Starts \"inside\" are "
              "uniform in the mesh scaled by 0.9 about its center for the spheres (for the "
              "icosphere: the ball of radius 0.9) and uniform inside the surface otherwise; "
              "starts \"in box\" are uniform in the bounding box, inside and outside alike.\n\n",
    allThreads);
  std::printf("Far from the mesh a step may take its radius from the distance bounds cached "
              "on a grid when they guarantee the same 1/1.2 of the distance as the hierarchy's "
              "relaxed query (Boundary::SetBoundGrid, on by default); the last two columns are "
              "the same walks without the grid. Set-up is Boundary::Set on all threads: the "
              "hierarchy and the filling of the grid.\n\n");
  PrintHeader({ "mesh", "walk", "ε", "ours 1T", "ours allT", "steps/walk", "no grid 1T",
                "no grid steps/walk" },
    3);
  std::vector<std::string> setupRows;
  for (const Mesh& mesh : meshes)
  {
    Boundary<3> boundary;
    const auto setStart = Clock::now();
    boundary.Set(mesh.Geometry.Vertices, mesh.Geometry.Simplices, ValueAssociation::Points, 1,
      std::vector<double>(mesh.Geometry.Vertices.size(), 1.0));
    const double setup = Seconds(setStart);
    const auto& grid = boundary.StepBoundGrid();
    setupRows.push_back("| " + mesh.Name + " | " + Number(setup, "%.3f") + " | " +
      Number(double(grid.NumberOfVertices())) + " | " +
      Number(grid.CellSize() / boundary.Diagonal(), "%.4f") + " | " +
      Number(double(grid.MemoryBytes()) / 1048576.0, "%.2f") + " |");
    Boundary<3> noGrid = boundary;
    noGrid.SetBoundGrid(false);

    const auto inside = MakeInsidePoints(mesh.Geometry, mesh.StartShrink, o.WalkPoints, 11);
    if (inside.empty())
    {
      PrintRow({ mesh.Name, "Laplace, starts inside", "–", "no inside points found (open surface?)",
        "–", "–" });
    }
    else
    {
      const double eps = 1e-3 * mesh.Scale;
      const WalkRates w = MeasureWalks(boundary, eps, inside, o);
      const WalkRates n = MeasureWalks(noGrid, eps, inside, o);
      PrintRow({ mesh.Name, "Laplace, starts inside", "1e-3·R = " + Number(eps, "%.3g"),
        Number(w.PerSecond.One), Number(w.PerSecond.All), Number(w.StepsPerWalk, "%.1f"),
        Number(n.PerSecond.One), Number(n.StepsPerWalk, "%.1f") });
      if (mesh.WalkTarget)
      {
        targets.push_back({ mesh.Name + ": Laplace walks/s, ε = 1e-3, starts inside",
          w.PerSecond.One, 40000.0, true, "%.0f" });
      }
    }

    const double eps = 1e-4 * boundary.Diagonal();
    const auto inBox = MakeQueries(mesh.Geometry, false, o.WalkPoints, 11);
    const WalkRates w = MeasureWalks(boundary, eps, inBox, o);
    const WalkRates n = MeasureWalks(noGrid, eps, inBox, o);
    PrintRow({ mesh.Name, "Laplace, starts in box", "1e-4·diagonal = " + Number(eps, "%.3g"),
      Number(w.PerSecond.One), Number(w.PerSecond.All), Number(w.StepsPerWalk, "%.1f"),
      Number(n.PerSecond.One), Number(n.StepsPerWalk, "%.1f") });
  }
  std::printf("\nBoundary set-up (all threads) and the bound grid: vertices, cell side "
              "relative to the box diagonal, memory.\n\n");
  PrintHeader({ "mesh", "set-up (s)", "grid vertices", "cell / diagonal", "grid MiB" }, 1);
  for (const std::string& row : setupRows)
  {
    std::printf("%s\n", row.c_str());
  }
}

// ---------------------------------------------------------------- scaling

void ScalingPart(const Options& o)
{
  std::printf("\n## Query cost against triangle count\n\nBumpy spheres (20·k² triangles), "
              "closest point on 1 thread. Three query sets: uniform in the box, near the "
              "surface (moved by up to 1%% of the box diagonal, the same distance for every "
              "size, so ever more triangle sizes away as n grows), and within 2 mean edge "
              "lengths of the surface (the same distance in triangle sizes for every n). "
              "Logarithmic growth shows as a roughly constant cost per log2(n) in the last "
              "set; in the others the answer itself involves more triangles as n grows "
              "(deep inside a closed surface, ever more are nearly equidistant).\n\n");
  PrintHeader({ "triangles", "log2(n)", "build (s)", "bytes/tri", "ns/query, uniform",
                "ns/query, near (1% diagonal)", "ns/query, near (2 edges)",
                "2 edges ÷ log2(n)" },
    0);
  std::vector<int> ks = { 23, 45, 90, 180, 320 };
  if (o.Quick)
  {
    ks.resize(3);
  }
  for (int k : ks)
  {
    const TriangleMesh mesh = MakeBumpySphere(k);
    Bvh<3> tree;
    const auto start = Clock::now();
    tree.Build(mesh.Vertices, mesh.Simplices);
    const double build = Seconds(start);
    const double n = double(mesh.Simplices.size());
    const double offsets[3] = { -1.0, 0.01 * BoundsOf(mesh).Diagonal(),
      2.0 * MeanEdgeLength(mesh) };
    double ns[3];
    for (int set = 0; set < 3; ++set)
    {
      const auto queries = MakeQueriesNear(mesh, offsets[set], o.Queries, 7);
      double sink = 0.0; // keeps the queries from being optimized away
      auto query = [&](std::size_t i) {
        sink += tree.ClosestPoint(queries[i % queries.size()]).distance;
      };
      const std::size_t count = CountForSeconds(o.Seconds, 50 * queries.size(), query);
      const auto t0 = Clock::now();
      for (std::size_t i = 0; i < count; ++i)
      {
        query(i);
      }
      ns[set] = 1e9 * Seconds(t0) / double(count);
      g_sink = sink;
    }
    const double log2n = std::log2(n);
    PrintRow({ Triangles(mesh.Simplices.size()), Number(log2n, "%.1f"), Number(build, "%.3f"),
      Number(tree.MemoryBytes() / n, "%.1f"), Number(ns[0]), Number(ns[1]), Number(ns[2]),
      Number(ns[2] / log2n, "%.0f") });
  }
}

// ---------------------------------------------------------------- large

// Runs before anything else is loaded, so that the peak resident set is the
// soup's and its hierarchy's.
void LargePart(const Options& o, std::vector<Target>& targets)
{
  const std::size_t triangles = o.Quick ? 1000000 : 10000000;
  std::printf("\n## Large build\n\nA soup of %s triangles (a bumpy sphere's triangles, "
              "shuffled, three vertices of their own each), built on all threads. Resident "
              "memory: with the soup loaded before the build, and the peak of the whole run "
              "(the soup, the hierarchy and the builder's scratch).\n\n",
    Triangles(triangles).c_str());
  TriangleMesh soup = MakeBumpySoup(triangles, 5);
  const double rssLoaded = CurrentRssMiB();
  const double peakBefore = PeakRssMiB();

  Bvh<3> tree;
  const auto start = Clock::now();
  tree.Build(soup.Vertices, soup.Simplices);
  const double build = Seconds(start);
  const double peak = PeakRssMiB();

  // A few queries, to show the cost at this size.
  double ns[2];
  for (bool nearSurface : { false, true })
  {
    const auto queries = MakeQueries(soup, nearSurface, o.Quick ? 2000 : 20000, 7);
    double sink = 0.0;
    const auto t0 = Clock::now();
    for (const Vec3& q : queries)
    {
      sink += tree.ClosestPoint(q).distance;
    }
    ns[nearSurface] = 1e9 * Seconds(t0) / double(queries.size());
    g_sink = sink;
  }

  PrintHeader({ "triangles", "build (s)", "BVH MiB", "BVH bytes/tri", "RSS with soup (MiB)",
                "peak RSS (MiB)", "ns/query, uniform", "ns/query, near surface" },
    0);
  PrintRow({ Triangles(soup.Simplices.size()), Number(build, "%.2f"),
    Number(tree.MemoryBytes() / 1048576.0, "%.0f"),
    Number(double(tree.MemoryBytes()) / double(soup.Simplices.size()), "%.1f"),
    Number(rssLoaded, "%.0f"), Number(peak, "%.0f"), Number(ns[0]), Number(ns[1]) });
  if (peakBefore >= peak)
  {
    std::printf("\n(The peak was reached while generating the soup, not during the build.)\n");
  }
  const std::string what = Triangles(soup.Simplices.size()) + "-triangle soup: ";
  targets.push_back({ what + "build (s)", build, 60.0, false, "%.1f" });
  targets.push_back({ what + "peak RSS (MiB)", peak, 2048.0, false, "%.0f" });
}

// ---------------------------------------------------------------- derivatives

// A smooth source for the Poisson rows: f = 1 + 0.5 sin(x/L) cos(y/L).
class SmoothSource : public VolumeSource<3>
{
public:
  explicit SmoothSource(double length)
    : Length(length)
  {}
  void Evaluate(const Vec3& y, double* f) override
  {
    f[0] = 1.0 + 0.5 * std::sin(y[0] / this->Length) * std::cos(y[1] / this->Length);
  }
  bool SupportBounds(Vec3&, Vec3&) const override { return false; }

private:
  double Length;
};

// Walks per second of one configuration on one thread (best of 3 runs, so a
// busy moment does not decide the comparison).
template <typename Walk>
double BestWalkRate(std::size_t points, int walksPerPoint, Walk walk)
{
  double best = 0.0;
  for (int run = 0; run < 3; ++run)
  {
    best = std::max(best, RatePerSecond(points, 1, walk) * walksPerPoint);
  }
  return best;
}

// What the derivative estimators cost on top of a value solve: walks/s on
// one thread for the value alone (no control variates), value + gradient,
// value + gradient with control variates, and value + gradient + Hessian.
void DerivativeCostTable(
  const std::string& name, const Boundary<3>& boundary, const std::vector<Vec3>& starts)
{
  const int walksPerPoint = 16;
  for (Equation equation : { Equation::Laplace, Equation::Poisson })
  {
    WalkSettings settings;
    settings.Epsilon = 1e-4 * boundary.Diagonal();
    settings.Problem = equation;
    const bool poisson = equation == Equation::Poisson;
    auto valueOnly = [&](std::size_t i) {
      SmoothSource source(0.1 * boundary.Diagonal());
      WalkOnSpheresEstimator<3> estimator(boundary, settings, poisson ? &source : nullptr);
      RunningStatistics stats(1);
      WalkCounters counters;
      const double xyz[3] = { starts[i][0], starts[i][1], starts[i][2] };
      estimator.EstimatePoint(xyz, 1, 0, walksPerPoint, stats, counters);
    };
    auto withDerivatives = [&](bool hessian, bool controls) {
      return [&, hessian, controls](std::size_t i) {
        SmoothSource source(0.1 * boundary.Diagonal());
        DerivativeRequest request;
        request.Gradient = true;
        request.Hessian = hessian;
        request.ControlVariates = controls;
        DerivativeWalkOnSpheres<3> estimator(
          boundary, settings, request, poisson ? &source : nullptr);
        RunningStatistics stats(estimator.Layout().Size);
        WalkCounters counters;
        const double xyz[3] = { starts[i][0], starts[i][1], starts[i][2] };
        estimator.EstimatePoint(xyz, 1, 0, walksPerPoint, stats, counters);
      };
    };
    const double base = BestWalkRate(starts.size(), walksPerPoint, valueOnly);
    const double gradient =
      BestWalkRate(starts.size(), walksPerPoint, withDerivatives(false, false));
    const double gradientCv =
      BestWalkRate(starts.size(), walksPerPoint, withDerivatives(false, true));
    const double hessianCv =
      BestWalkRate(starts.size(), walksPerPoint, withDerivatives(true, true));
    auto withChange = [&](double rate) {
      char cell[64];
      std::snprintf(cell, sizeof(cell), "%.0f (%+.1f%%)", rate, 100.0 * (base / rate - 1.0));
      return std::string(cell);
    };
    PrintRow({ name, poisson ? "Poisson" : "Laplace", Number(base), withChange(gradient),
      withChange(gradientCv), withChange(hessianCv) });
  }
}

void DerivativesPart(const std::vector<Mesh>& meshes, const Options& o)
{
  std::printf("\n## Cost of derivatives\n\nWalks/s on 1 thread (best of 3), 16 walks per "
              "point, points inside the surface, ε = 1e-4·diagonal; in parentheses the extra "
              "time per walk relative to the value alone.\n\n");
  PrintHeader(
    { "mesh", "equation", "value", "+ gradient", "+ gradient, CV", "+ gradient + Hessian, CV" }, 2);
  for (const Mesh& mesh : meshes)
  {
    if (!mesh.DerivativeTable)
    {
      continue;
    }
    Boundary<3> boundary;
    boundary.Set(mesh.Geometry.Vertices, mesh.Geometry.Simplices, ValueAssociation::Points, 1,
      std::vector<double>(mesh.Geometry.Vertices.size(), 1.0));
    // The walks of points outside are longer, which would only dilute the
    // difference.
    const auto inside =
      MakeInsidePoints(mesh.Geometry, 1.0, std::max<std::size_t>(o.WalkPoints / 4, 1), 13);
    if (!inside.empty())
    {
      DerivativeCostTable(mesh.Name, boundary, inside);
    }
  }
}
} // namespace

int main(int argc, char* argv[])
{
  Options o;
  int exitCode = 0;
  if (!ParseOptions(argc, argv, o, exitCode))
  {
    return exitCode;
  }
  std::printf("# GridFree benchmarks\n\n%d threads available; Embree: %s.\n", ResolveThreadCount(0),
#ifdef GRIDFREE_HAVE_EMBREE
    ("version " + EmbreePeer::Version()).c_str()
#else
    "not available"
#endif
  );
  std::vector<Target> targets;
  try
  {
    if (o.PartLarge)
    {
      LargePart(o, targets);
    }
    if (o.PartScaling)
    {
      ScalingPart(o);
    }
    if (o.PartQueries || o.PartWalks || o.PartDerivatives)
    {
      const std::vector<Mesh> meshes = LoadMeshes(o);
      if (o.PartQueries)
      {
        QueriesPart(meshes, o, targets);
      }
      if (o.PartWalks)
      {
        WalksPart(meshes, o, targets);
      }
      if (o.PartDerivatives)
      {
        DerivativesPart(meshes, o);
      }
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  PrintTargets(targets);
  if (o.Quick)
  {
    std::printf("\n(--quick: short measurements, for checking that everything runs; do not "
                "quote these numbers.)\n");
  }
  return 0;
}
