// The project's hierarchy and walks beside the paper authors' libraries, in
// one run on one machine: fcpw's vectorized BVH (16 lanes with AVX-512, 8 with
// AVX2) for closest-point and ray queries, and zombie's walk on spheres on it
// for walks, when their public sources were given at configure time
// (FcpwPeer.h). Without them the peer columns print "–".
//
// Queries: the same query points and rays for all contenders, measured in
// alternating rounds (ours, fcpw w16, fcpw w8, again), best round kept, on 1
// thread and on all. Our answers are checked against brute force.
//
// Walks: a Laplace problem with a closed-form harmonic solution, so that RMSE
// shows any bias of relaxed steps, of the bound grid or of step hints; our
// walks with their defaults and with exact steps, zombie's beside them, set-up
// time counted; then gradients at equal error.
#include "BenchmarkMeshes.h"
#include "BenchmarkTables.h"
#ifdef GRIDFREE_WITH_FCPW
#include "FcpwPeer.h"
#endif

#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/geometry/RayKernels.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace gridfree;
using namespace gridfree::bench;

namespace
{
const char* const kUsage = R"(Usage: GridFreePeerBenchmark [options]

Parts (default: both):
  --only-queries    closest-point, distance and ray queries/s, build time,
                    memory, agreement with brute force and with fcpw
  --only-walks      walks/s and RMSE against zombie, values and gradients

Meshes (a 327,680-triangle icosphere and a 1,310,720-triangle bumpy sphere
are always included):
  --data PATH       the CT skin surface (.vtp); ./gridfree bench passes it
  --mesh PATH       one more surface (.vtp), e.g. a raw isosurface soup; may
                    be repeated

Sizes:
  --queries N       query points per set (100000)
  --seconds S       target time of each query measurement (0.5)
  --rounds N        alternating rounds per query measurement (3)
  --walk-points N   start points per walk row (200)
  --walks N         walks per point (64)
  --quick           short smoke run; do not quote its numbers
  --help            this text
)";

struct Options
{
  std::string Data;
  std::vector<std::string> ExtraMeshes;
  std::size_t Queries = 100000;
  double Seconds = 0.5;
  int Rounds = 3;
  std::size_t WalkPoints = 200;
  int Walks = 64;
  bool Quick = false;
  bool PartQueries = false, PartWalks = false;
};

bool ParseOptions(int argc, char* argv[], Options& o, int& exitCode)
{
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
      if (a == "--help" || a == "-h")
      {
        std::fputs(kUsage, stdout);
        exitCode = 0;
        return false;
      }
      else if (a == "--only-queries")
      {
        o.PartQueries = true;
      }
      else if (a == "--only-walks")
      {
        o.PartWalks = true;
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
      else if (a == "--seconds")
      {
        o.Seconds = std::stod(value());
      }
      else if (a == "--rounds")
      {
        o.Rounds = std::stoi(value());
      }
      else if (a == "--walk-points")
      {
        o.WalkPoints = std::stoul(value());
      }
      else if (a == "--walks")
      {
        o.Walks = std::stoi(value());
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
    if (o.Queries == 0 || o.WalkPoints == 0 || o.Walks < 2 || o.Rounds < 1 || !(o.Seconds > 0.0))
    {
      throw std::invalid_argument("counts and times must be positive (at least 2 walks)");
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s\n\n%s", e.what(), kUsage);
    exitCode = 2;
    return false;
  }
  if (!o.PartQueries && !o.PartWalks)
  {
    o.PartQueries = o.PartWalks = true;
  }
  if (o.Quick)
  {
    o.Queries = std::min<std::size_t>(o.Queries, 10000);
    o.Seconds = std::min(o.Seconds, 0.05);
    o.Rounds = 1;
    o.WalkPoints = std::min<std::size_t>(o.WalkPoints, 20);
    o.Walks = std::min(o.Walks, 16);
  }
  return true;
}

// ---------------------------------------------------------------- peers

constexpr int kPeerSlots = 2; // fcpw w16, fcpw w8: the table's columns

// Builds the peers for a mesh into their column slots (null: not available).
#ifdef GRIDFREE_WITH_FCPW
std::array<std::unique_ptr<FcpwPeer>, kPeerSlots> BuildPeers(const TriangleMesh& mesh)
{
  PeerMesh plain;
  plain.Vertices.reserve(mesh.Vertices.size());
  for (const Vec3& v : mesh.Vertices)
  {
    plain.Vertices.push_back(PeerPoint{ v[0], v[1], v[2] });
  }
  plain.Triangles = mesh.Simplices;
  std::array<std::unique_ptr<FcpwPeer>, kPeerSlots> peers;
  if (FcpwPeerRunsHere(16))
  {
    peers[0] = CreateFcpwPeerW16(plain);
  }
  if (FcpwPeerRunsHere(8))
  {
    peers[1] = CreateFcpwPeerW8(plain);
  }
  return peers;
}

PeerPoint Plain(const Vec3& v)
{
  return PeerPoint{ v[0], v[1], v[2] };
}
#endif

// ---------------------------------------------------------------- meshes

std::vector<Mesh> LoadMeshes(const Options& o)
{
  std::vector<Mesh> meshes;
  meshes.push_back(Mesh{ "icosphere", testing::MakeIcosphere(7), 1.0, 0.9 });
  meshes.push_back(Mesh{ "bumpy sphere", MakeBumpySphere(256), 1.0, 0.9 });
  auto load = [&](const std::string& name, const std::string& path) {
    Mesh m{ name, ReadPolyDataTriangles(path), 1.0, 1.0 };
    m.Scale = HalfLongestSide(m.Geometry);
    meshes.push_back(std::move(m));
  };
  if (!o.Data.empty())
  {
    load("CT skin", o.Data);
  }
  for (const std::string& path : o.ExtraMeshes)
  {
    load(FileStem(path), path);
  }
  if (o.Quick)
  {
    meshes[0].Geometry = testing::MakeIcosphere(4);
    meshes[1].Geometry = MakeBumpySphere(32);
  }
  for (Mesh& m : meshes)
  {
    m.Name += " (" + Triangles(m.Geometry.Simplices.size()) + " tri)";
  }
  return meshes;
}

// ---------------------------------------------------------------- queries

// Brute-force nearest distance and first ray hit, with the hierarchy's own
// kernels: the hierarchy must give the same bits.
double BruteDistance(const TriangleMesh& mesh, const Vec3& x)
{
  double best2 = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.Simplices)
  {
    best2 = std::min(best2,
      SquaredDistanceToTriangle(x, mesh.Vertices[t[0]], mesh.Vertices[t[1]], mesh.Vertices[t[2]]));
  }
  return std::sqrt(best2);
}

double BruteRay(const TriangleMesh& mesh, const Vec3& origin, const Vec3& direction)
{
  const detail::RayFrame<3> frame(origin, direction);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.Simplices)
  {
    const Vec3 v[3] = { mesh.Vertices[t[0]], mesh.Vertices[t[1]], mesh.Vertices[t[2]] };
    double tHit;
    Vec3 w;
    if (frame.Intersect(v, 0.0, best, tHit, w) && tHit < best)
    {
      best = tHit;
    }
  }
  return best;
}

struct QueryRates
{
  // [contender][threads]: contender 0 ours, 1.. the peer slots; threads 0
  // one thread, 1 all. Negative: not measured.
  double Rate[1 + kPeerSlots][2];
  QueryRates()
  {
    for (auto& r : this->Rate)
    {
      r[0] = r[1] = -1.0;
    }
  }
  double BestPeer(int threads) const
  {
    double best = -1.0;
    for (int p = 1; p <= kPeerSlots; ++p)
    {
      best = std::max(best, this->Rate[p][threads]);
    }
    return best;
  }
};

// Alternating rounds: every contender measured once per round on 1 and all
// threads, the best of the rounds kept.
void MeasureRounds(QueryRates& rates, std::size_t count, const Options& o,
  const std::vector<std::function<void(std::size_t)>>& bodies)
{
  const int allThreads = ResolveThreadCount(0);
  for (int round = 0; round < o.Rounds; ++round)
  {
    for (std::size_t c = 0; c < bodies.size(); ++c)
    {
      if (!bodies[c])
      {
        continue;
      }
      for (int threads = 0; threads < 2; ++threads)
      {
        const double r = RatePerSecond(count, threads ? allThreads : 1, bodies[c]);
        rates.Rate[c][threads] = std::max(rates.Rate[c][threads], r);
      }
    }
  }
}

void PrintRates(const std::string& mesh, const std::string& what, const QueryRates& r)
{
  PrintRow({ mesh, what, Number(r.Rate[0][0]), Number(r.Rate[1][0]), Number(r.Rate[2][0]),
    Gain(r.Rate[0][0], r.BestPeer(0)), Number(r.Rate[0][1]), Number(r.Rate[1][1]),
    Number(r.Rate[2][1]), Gain(r.Rate[0][1], r.BestPeer(1)) });
}

struct Agreement
{
  std::string Mesh;
  std::size_t BruteQueries = 0, BruteMismatches = 0, BruteRays = 0, BruteRayMismatches = 0;
  double PeerDistance[kPeerSlots] = { -1.0, -1.0 }; // largest |ours - fcpw| / diagonal
  double PeerRayMiss[kPeerSlots] = { -1.0, -1.0 };  // share of rays hit by one side only
};

struct BuildReport
{
  std::string Mesh;
  std::size_t Triangles = 0;
  double Seconds[1 + kPeerSlots] = { -1.0, -1.0, -1.0 };
  double BytesPerTriangle[1 + kPeerSlots] = { -1.0, -1.0, -1.0 };
};

void QueriesPart(const std::vector<Mesh>& meshes, const Options& o)
{
  const int allThreads = ResolveThreadCount(0);
  std::printf("\n## Queries/s\n\nOne thread and %d threads; the same query points (and "
              "ray directions) for all; %d alternating rounds, the best kept. Ours: "
              "Bvh<3>::ClosestPoint, Distance and Intersect (exact, double). fcpw: "
              "findClosestPoint (its distance query too) and intersect, in float, on its "
              "vectorized BVH. \"ours/best\" divides by the faster fcpw build.\n\n",
    allThreads, o.Rounds);
  PrintHeader({ "mesh", "query", "ours 1T", "fcpw w16 1T", "fcpw w8 1T", "ours/best 1T",
                "ours allT", "fcpw w16 allT", "fcpw w8 allT", "ours/best allT" },
    2);
  std::vector<BuildReport> builds;
  std::vector<Agreement> agreements;
  for (const Mesh& mesh : meshes)
  {
    const TriangleMesh& g = mesh.Geometry;
    const double n = double(g.Simplices.size());
    BuildReport build;
    build.Mesh = mesh.Name;
    build.Triangles = g.Simplices.size();
    // Builds: the best of a few, alternating, for all (a build's first
    // touch of fresh memory makes single timings noisy).
    const int buildRounds = o.Quick ? 1 : 3;
    Bvh<3> tree;
#ifdef GRIDFREE_WITH_FCPW
    std::array<std::unique_ptr<FcpwPeer>, kPeerSlots> peers;
#endif
    for (int round = 0; round < buildRounds; ++round)
    {
      tree = Bvh<3>();
      const auto start = Clock::now();
      tree.Build(g.Vertices, g.Simplices);
      const double seconds = Seconds(start);
      build.Seconds[0] = round ? std::min(build.Seconds[0], seconds) : seconds;
#ifdef GRIDFREE_WITH_FCPW
      peers = {};
      peers = BuildPeers(g);
      for (int p = 0; p < kPeerSlots; ++p)
      {
        if (peers[p])
        {
          const double theirs = peers[p]->BuildSeconds();
          build.Seconds[1 + p] = round ? std::min(build.Seconds[1 + p], theirs) : theirs;
          build.BytesPerTriangle[1 + p] = double(peers[p]->HeapBytes()) / n;
        }
      }
#endif
    }
    build.BytesPerTriangle[0] = double(tree.MemoryBytes()) / n;
    builds.push_back(build);

    Agreement agreement;
    agreement.Mesh = mesh.Name;
    const double diagonal = BoundsOf(g).Diagonal();
    for (bool nearSurface : { false, true })
    {
      const auto queries = MakeQueries(g, nearSurface, o.Queries, 7);
      const std::size_t size = queries.size();
      std::vector<Vec3> directions(size);
      std::mt19937_64 rng(23);
      std::normal_distribution<double> normal;
      for (Vec3& d : directions)
      {
        d = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      }
      const std::string where = nearSurface ? "near surface" : "uniform in box";

      // Answers, for the agreement table.
      std::vector<double> ours(size), ourRays(size);
      for (std::size_t i = 0; i < size; ++i)
      {
        ours[i] = tree.Distance(queries[i]);
        const RayHit<3> hit = tree.Intersect(queries[i], directions[i]);
        ourRays[i] = hit.primitive >= 0 ? hit.t : std::numeric_limits<double>::infinity();
      }
      const std::size_t brute = std::min<std::size_t>(size, o.Quick ? 8 : 24);
      for (std::size_t i = 0; i < brute; ++i)
      {
        agreement.BruteQueries++;
        agreement.BruteMismatches += BruteDistance(g, queries[i]) != ours[i];
        agreement.BruteRays++;
        agreement.BruteRayMismatches += BruteRay(g, queries[i], directions[i]) != ourRays[i];
      }

      double sink = 0.0;
      std::vector<std::function<void(std::size_t)>> closest(1 + kPeerSlots),
        distance(1 + kPeerSlots), rays(1 + kPeerSlots);
      closest[0] = [&](std::size_t i) { sink += tree.ClosestPoint(queries[i % size]).distance; };
      distance[0] = [&](std::size_t i) { sink += tree.Distance(queries[i % size]); };
      rays[0] = [&](std::size_t i) {
        sink += tree.Intersect(queries[i % size], directions[i % size]).t;
      };
#ifdef GRIDFREE_WITH_FCPW
      for (int p = 0; p < kPeerSlots; ++p)
      {
        const FcpwPeer* peer = peers[p].get();
        if (!peer)
        {
          continue;
        }
        std::vector<PeerPoint> plainQueries(size), plainDirections(size);
        double worst = 0.0;
        std::size_t rayMiss = 0;
        for (std::size_t i = 0; i < size; ++i)
        {
          plainQueries[i] = Plain(queries[i]);
          plainDirections[i] = Plain(directions[i]);
          worst = std::max(worst, std::abs(peer->ClosestPoint(plainQueries[i]) - ours[i]));
          double t;
          rayMiss += peer->Intersect(plainQueries[i], plainDirections[i], t) != std::isfinite(ourRays[i]);
        }
        agreement.PeerDistance[p] = std::max(agreement.PeerDistance[p], worst / diagonal);
        agreement.PeerRayMiss[p] = std::max(agreement.PeerRayMiss[p], double(rayMiss) / double(size));
        closest[1 + p] = [peer, q = plainQueries, &sink](std::size_t i) {
          PeerPoint point;
          sink += peer->ClosestPoint(q[i % q.size()], &point);
        };
        distance[1 + p] = [peer, q = plainQueries, &sink](std::size_t i) {
          sink += peer->ClosestPoint(q[i % q.size()]);
        };
        rays[1 + p] = [peer, q = plainQueries, d = plainDirections, &sink](std::size_t i) {
          double t = 0.0;
          peer->Intersect(q[i % q.size()], d[i % q.size()], t);
          sink += t;
        };
      }
#endif
      // The same number of calls for every contender: about o.Seconds of ours.
      const std::size_t count = CountForSeconds(o.Seconds, 50 * size, closest[0]);
      const std::size_t rayCount = CountForSeconds(o.Seconds, 200 * size, rays[0]);
      QueryRates cp, d, r;
      MeasureRounds(cp, count, o, closest);
      MeasureRounds(d, count, o, distance);
      MeasureRounds(r, rayCount, o, rays);
      PrintRates(mesh.Name, "closest point, " + where, cp);
      PrintRates(mesh.Name, "distance, " + where, d);
      PrintRates(mesh.Name, "ray, from points " + where, r);
      volatile double keep = sink;
      (void)keep;
    }
    agreements.push_back(agreement);
  }

  std::printf("\n## Build and memory\n\nBest of 3 builds, alternating. Ours on all threads (subtrees of 2^12 triangles or more "
              "build in parallel), fcpw's on one (its builder is sequential). Ours: "
              "Bvh<3>::Build and MemoryBytes "
              "(nodes, triangles in leaf order with their vertices inline in double and in "
              "float groups of four, original ids). "
              "fcpw: filling its scene and building its vectorized BVH; its bytes are the heap "
              "its scene holds after the build (malloc statistics: its vertex and triangle "
              "copies, primitives and nodes).\n\n");
  PrintHeader({ "mesh", "triangles", "ours (s)", "fcpw w16 (s)", "fcpw w8 (s)",
                "best fcpw / ours", "ours bytes/tri", "fcpw w16 bytes/tri", "fcpw w8 bytes/tri" },
    1);
  for (const BuildReport& b : builds)
  {
    double best = -1.0;
    for (int p = 1; p <= kPeerSlots; ++p)
    {
      if (b.Seconds[p] > 0.0 && (best < 0.0 || b.Seconds[p] < best))
      {
        best = b.Seconds[p];
      }
    }
    PrintRow({ b.Mesh, Triangles(b.Triangles), Number(b.Seconds[0], "%.3f"),
      Number(b.Seconds[1], "%.3f"), Number(b.Seconds[2], "%.3f"), Gain(best, b.Seconds[0]),
      Number(b.BytesPerTriangle[0], "%.1f"), Number(b.BytesPerTriangle[1], "%.1f"),
      Number(b.BytesPerTriangle[2], "%.1f") });
  }

  std::printf("\n## Agreement\n\nOurs against brute force with the same kernels (distances "
              "and first ray hits must be the same bits), on the first queries and rays of "
              "each set; ours against fcpw (float): the largest distance difference over the "
              "box diagonal, and the share of rays that only one of the two hits.\n\n");
  PrintHeader({ "mesh", "brute-force distances equal", "brute-force rays equal",
                "|ours - fcpw w16| / diagonal", "rays hit by one only (w16)" },
    1);
  for (const Agreement& a : agreements)
  {
    PrintRow({ a.Mesh,
      std::to_string(a.BruteQueries - a.BruteMismatches) + " of " + std::to_string(a.BruteQueries),
      std::to_string(a.BruteRays - a.BruteRayMismatches) + " of " + std::to_string(a.BruteRays),
      Number(a.PeerDistance[0], "%.1e"), Number(a.PeerRayMiss[0], "%.2e") });
  }
}

// ---------------------------------------------------------------- walks

// u = ((x - c_x)² - (y - c_y)²) / R² + (z - c_z) / R: harmonic, of order 1
// over the mesh, not constant on it.
struct Harmonic
{
  Vec3 C;
  double R;
  double Value(const Vec3& x) const
  {
    const Vec3 y = x - this->C;
    return (y[0] * y[0] - y[1] * y[1]) / (this->R * this->R) + y[2] / this->R;
  }
  Vec3 Gradient(const Vec3& x) const
  {
    const Vec3 y = x - this->C;
    return Vec3(2.0 * y[0] / (this->R * this->R), -2.0 * y[1] / (this->R * this->R), 1.0 / this->R);
  }
};

struct WalkRow
{
  std::string Name;
  double Setup = -1.0, WalksPerSecond = -1.0, StepsPerWalk = -1.0, Rmse = -1.0;
  double Seconds = -1.0; // the walks alone, for the equal-error comparison
};

void PrintWalkRow(const std::string& mesh, const WalkRow& r, const WalkRow* reference)
{
  // Time to reach the same RMSE, relative to the reference: the variance
  // falls as 1/walks, so time × RMSE² is the cost of a given error.
  std::string relative = "–";
  if (reference && reference->Seconds > 0.0 && r.Seconds > 0.0 && r.Rmse > 0.0)
  {
    relative = Gain(reference->Seconds * reference->Rmse * reference->Rmse,
      r.Seconds * r.Rmse * r.Rmse);
  }
  PrintRow({ mesh, r.Name, Number(r.Setup, "%.3f"), Number(r.WalksPerSecond),
    Number(r.StepsPerWalk, "%.1f"), Number(r.Rmse, "%.2e"), relative });
}

// Our walks on one thread from every point, with or without the gradient;
// with antithetic pairs, walks / 2 samples of two walks each.
WalkRow OurWalks(const std::string& name, const Boundary<3>& boundary, double setup,
  const std::vector<Vec3>& points, int walks, double epsilon, bool gradient, const Harmonic& u,
  bool antithetic = false)
{
  WalkSettings settings;
  settings.Epsilon = epsilon;
  settings.Problem = Equation::Laplace;
  DerivativeRequest request;
  request.Gradient = true;
  request.ControlVariates = true;
  request.AntitheticPairs = antithetic;
  const int walksPerSample = antithetic ? 2 : 1;
  const int samples = std::max(1, walks / walksPerSample);
  WalkOnSpheresEstimator<3> values(boundary, settings);
  DerivativeWalkOnSpheres<3> derivatives(boundary, settings, request);
  const SampleLayout& layout = derivatives.Layout();
  WalkCounters total;
  double squared = 0.0;
  const auto start = Clock::now();
  for (const Vec3& p : points)
  {
    const double xyz[3] = { p[0], p[1], p[2] };
    WalkCounters counters;
    if (gradient)
    {
      RunningStatistics stats(layout.Size);
      derivatives.EstimatePoint(xyz, 7, 0, samples, stats, counters);
      const Vec3 g(stats.GetMean(layout.Gradient), stats.GetMean(layout.Gradient + 1),
        stats.GetMean(layout.Gradient + 2));
      squared += (g - u.Gradient(p)).squaredNorm();
    }
    else
    {
      RunningStatistics stats(1);
      values.EstimatePoint(xyz, 7, 0, walks, stats, counters);
      const double e = stats.GetMean(0) - u.Value(p);
      squared += e * e;
    }
    total.Add(counters);
  }
  WalkRow row;
  row.Name = name;
  row.Seconds = Seconds(start);
  row.Setup = setup;
  row.WalksPerSecond = double(walksPerSample) * double(total.Walks) / row.Seconds;
  row.StepsPerWalk = total.MeanSteps() / walksPerSample;
  row.Rmse = std::sqrt(squared / double(points.size()));
  return row;
}

void WalksPart(const std::vector<Mesh>& meshes, const Options& o)
{
  std::printf("\n## Walks against zombie\n\nLaplace, u = ((x−c_x)² − (y−c_y)²)/R² + "
              "(z−c_z)/R with c the box centre and R half its longest side; %d walks at each "
              "of up to %zu points inside (spheres: inside the surface scaled by 0.9), "
              "ε = 1e-3·R, one thread. Ours take u at the vertices (linear on each "
              "triangle), zombie calls u at the closest point. Set-up: ours Boundary::Set on "
              "all threads (hierarchy, bound grid); zombie's boundary handler (fcpw's "
              "vectorized BVH, the widest build this CPU runs). RMSE of u over the points, and for the gradient rows of "
              "|∇u| error; \"cost ratio\" is zombie's walk time × RMSE² over ours: above 1, "
              "ours reaches the same error sooner.\n\n",
    o.Walks, o.WalkPoints);
  PrintHeader(
    { "mesh", "estimator", "set-up (s)", "walks/s", "steps/walk", "RMSE", "cost ratio" }, 2);
  for (const Mesh& mesh : meshes)
  {
    const TriangleMesh& g = mesh.Geometry;
    const Box box = BoundsOf(g);
    const Harmonic u{ box.Center(), HalfLongestSide(g) };
    const double epsilon = 1e-3 * u.R;
    const auto points = MakeInsidePoints(g, mesh.StartShrink, o.WalkPoints, 11);
    if (points.empty())
    {
      PrintRow({ mesh.Name, "no inside points (open surface?)", "–", "–", "–", "–", "–" });
      continue;
    }
    std::vector<double> values(g.Vertices.size());
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      values[i] = u.Value(g.Vertices[i]);
    }
    const auto setStart = Clock::now();
    Boundary<3> boundary;
    boundary.Set(g.Vertices, g.Simplices, ValueAssociation::Points, 1, values);
    const double setup = Seconds(setStart);
    Boundary<3> exact = boundary;
    exact.SetStepRelaxation(0.0);
    exact.SetBoundGrid(false);

    WalkRow peerValue, peerGradient;
#ifdef GRIDFREE_WITH_FCPW
    auto peers = BuildPeers(g);
    const FcpwPeer* peer = peers[0] ? peers[0].get() : peers[1].get();
    if (peer && peer->HasWalks())
    {
      std::vector<PeerPoint> plain;
      for (const Vec3& p : points)
      {
        plain.push_back(Plain(p));
      }
      PeerWalkProblem problem;
      problem.Exact = [&u](const PeerPoint& x) { return u.Value(Vec3(x[0], x[1], x[2])); };
      for (bool gradient : { false, true })
      {
        const PeerWalkResult result = peer->Walk(problem, plain, o.Walks, epsilon, gradient);
        WalkRow& row = gradient ? peerGradient : peerValue;
        row.Name = std::string(gradient ? "gradient: " : "value: ") + "zombie on " + peer->Name();
        row.Setup = result.SetupSeconds;
        row.Seconds = result.Seconds;
        row.WalksPerSecond = double(o.Walks) * double(points.size()) / result.Seconds;
        row.StepsPerWalk = result.StepsPerWalk;
        double squared = 0.0;
        for (std::size_t i = 0; i < points.size(); ++i)
        {
          if (gradient)
          {
            const auto& e = result.Gradients[i];
            squared += (Vec3(e[0], e[1], e[2]) - u.Gradient(points[i])).squaredNorm();
          }
          else
          {
            const double e = result.Values[i] - u.Value(points[i]);
            squared += e * e;
          }
        }
        row.Rmse = std::sqrt(squared / double(points.size()));
      }
    }
#endif
    const bool havePeer = peerValue.Seconds > 0.0;
    const WalkRow relaxed = OurWalks("value: ours (relaxed steps, bound grid)", boundary, setup,
      points, o.Walks, epsilon, false, u);
    const WalkRow exactRow = OurWalks(
      "value: ours, exact steps", exact, setup, points, o.Walks, epsilon, false, u);
    PrintWalkRow(mesh.Name, relaxed, havePeer ? &peerValue : nullptr);
    PrintWalkRow(mesh.Name, exactRow, havePeer ? &peerValue : nullptr);
    if (havePeer)
    {
      PrintWalkRow(mesh.Name, peerValue, nullptr);
    }
    const WalkRow gradient = OurWalks("gradient: ours (control variates)", boundary, setup,
      points, o.Walks, epsilon, true, u);
    PrintWalkRow(mesh.Name, gradient, havePeer ? &peerGradient : nullptr);
    const WalkRow antithetic = OurWalks("gradient: ours (control variates, antithetic pairs)",
      boundary, setup, points, o.Walks, epsilon, true, u, true);
    PrintWalkRow(mesh.Name, antithetic, havePeer ? &peerGradient : nullptr);
    if (havePeer)
    {
      PrintWalkRow(mesh.Name, peerGradient, nullptr);
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
  std::printf("# GridFree against the authors' libraries\n\n%d threads available. Peers: %s.\n",
    ResolveThreadCount(0),
#ifdef GRIDFREE_WITH_FCPW
#ifdef GRIDFREE_WITH_ZOMBIE_WALKS
    "fcpw (w16 where the CPU has AVX-512, w8 with AVX2) and zombie's walk on spheres"
#else
    "fcpw (w16 where the CPU has AVX-512, w8 with AVX2); zombie not configured"
#endif
#else
    "none configured (GRIDFREE_FCPW_SOURCE_DIR, GRIDFREE_ZOMBIE_SOURCE_DIR and "
    "GRIDFREE_PCG32_INCLUDE_DIR at configure time)"
#endif
  );
  try
  {
    const std::vector<Mesh> meshes = LoadMeshes(o);
    if (o.PartQueries)
    {
      QueriesPart(meshes, o);
    }
    if (o.PartWalks)
    {
      WalksPart(meshes, o);
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  if (o.Quick)
  {
    std::printf("\n(--quick: short measurements, for checking that everything runs; do not "
                "quote these numbers.)\n");
  }
  return 0;
}
