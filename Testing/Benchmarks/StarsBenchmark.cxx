// Walk on stars against walk on spheres on the same domains, one thread, in
// one run: what a Neumann or Robin part costs per walk. Each domain is
// solved with all of its boundary Dirichlet (walk on spheres, and walk on
// stars with an empty reflecting part) and with part of it Neumann or
// Robin (walk on stars); the data come from one harmonic function, so the
// RMSE against it is printed beside the rate, and the set-up time (the
// hierarchies, the silhouettes, the sampler) beside that.
//
// Domains: an L prism of 2,304 triangles (Testing/Core/Support/MixedShapes.h), with
// the bottom and back faces Dirichlet; and the unit icosphere of 20,480
// triangles, Dirichlet below z = 0.
//
// Each Neumann problem is also solved for the gradient (a first ball clear
// of the whole boundary, then walk on stars: StarDerivativeWalks.h, with
// its control variates).
//
// Configured with GRIDFREE_ZOMBIE_SOURCE_DIR (and FCPW, PCG32), the authors'
// walk on stars solves each Neumann problem (value and gradient) and each
// Robin problem too, in the same run (ZombieStarsRows.h), and a second
// table compares the two at equal error: time × MSE, the time each would
// take to reach the same RMSE (RMSE² falls like 1/walks).
//
//   GridFreeStarsBenchmark [walks per point] [points]
#include "BenchmarkRows.h"
#ifdef GRIDFREE_WITH_ZOMBIE
#include "ZombieStarsRows.h"
#endif
#include "MixedShapes.h"
#include "TestMeshes.h"
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/stars/StarDerivativeWalks.h>
#include <gridfree/stars/WalkOnStars.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;
using namespace gridfree::bench;

namespace
{
// u = e^{x/2} cos(0.3 y) sin(0.4 z) + x y − z and its gradient.
double Exact(const Vec3& x) { return LPrismSolution(x); }
Vec3 ExactGradient(const Vec3& x) { return LPrismGradient(x); }

// An estimator's row, with the set-up time before it.
template <class Estimator>
Row Run(const std::string& name, double setup, Estimator& estimator,
  const std::vector<Vec3>& points, int walks)
{
  Row row = RunEstimator(name, estimator, points, walks, Exact);
  row.SetupSeconds = setup;
  return row;
}

#ifdef GRIDFREE_WITH_ZOMBIE
// The same Neumann (or, with `robin`, Robin) problem solved by the
// authors' library (float, fcpw), for the value or value and gradient.
Row ZombieRow(const std::string& name, const SimplexMesh<3>& mesh,
  const std::function<bool(const Vec3&)>& isDirichlet, const std::vector<Vec3>& points, int walks,
  const WalkSettings& settings, bool gradient = false, const RobinRule<3>& robin = nullptr)
{
  using Point = std::array<double, 3>;
  auto vec = [](const Point& p) { return Vec3(p[0], p[1], p[2]); };
  ZombieProblem problem;
  for (const Vec3& v : mesh.Vertices)
  {
    problem.Vertices.push_back(Point{ v[0], v[1], v[2] });
  }
  problem.Triangles.assign(mesh.Simplices.begin(), mesh.Simplices.end());
  problem.IsDirichlet = [&](const Point& c) { return isDirichlet(vec(c)); };
  problem.Exact = [&](const Point& x) { return Exact(vec(x)); };
  problem.Gradient = [&](const Point& x) {
    const Vec3 g = ExactGradient(vec(x));
    return Point{ g[0], g[1], g[2] };
  };
  if (robin)
  {
    problem.Robin = [&](const Point& x) { return robin(vec(x)); };
  }
  std::vector<Point> at;
  for (const Vec3& p : points)
  {
    at.push_back(Point{ p[0], p[1], p[2] });
  }
  const ZombieResult r =
    RunZombieWalkOnStars(problem, at, walks, settings.Epsilon, settings.MaxSteps, gradient);
  Row row;
  row.Name = name;
  row.SetupSeconds = r.SetupSeconds;
  row.WalksPerSecond = r.WalksPerSecond;
  row.StepsPerWalk = r.StepsPerWalk;
  row.Rmse = r.Rmse;
  row.GradientRmse = gradient ? r.GradientRmse : -1.0;
  row.Points = static_cast<int>(points.size());
  row.Walks = walks;
  return row;
}
#endif

// The solves of one domain: all Dirichlet by walk on spheres and by walk on
// stars, then with the reflecting part `robin` decides (μ = 0: Neumann) on
// the primitives `isDirichlet` leaves: Neumann (value, then gradient) and
// Robin.
std::vector<Row> Domain(const std::string& name, const SimplexMesh<3>& mesh,
  const std::function<bool(const Vec3&)>& isDirichlet, const RobinRule<3>& robin,
  const std::vector<Vec3>& points, int walks)
{
  std::vector<Row> rows;
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  auto start = std::chrono::steady_clock::now();
  const MixedBoundary<3> allDirichlet =
    MakeMixed<3>(mesh, [](const Vec3&) { return true; }, Exact, ExactGradient);
  double setup = SecondsSince(start);
  WalkOnSpheresEstimator<3> spheres(allDirichlet.Dirichlet(), settings);
  rows.push_back(Run(name + ", all Dirichlet: walk on spheres", setup, spheres, points, walks));
  WalkOnStarsEstimator<3> starsDirichlet(allDirichlet, settings);
  rows.push_back(Run(name + ", all Dirichlet: walk on stars", setup, starsDirichlet, points, walks));
  start = std::chrono::steady_clock::now();
  const MixedBoundary<3> neumann = MakeMixed<3>(mesh, isDirichlet, Exact, ExactGradient);
  setup = SecondsSince(start);
  WalkOnStarsEstimator<3> starsNeumann(neumann, settings);
  rows.push_back(Run(name + ", Neumann part: walk on stars", setup, starsNeumann, points, walks));
#ifdef GRIDFREE_WITH_ZOMBIE
  rows.push_back(ZombieRow(name + ", Neumann part: zombie (fcpw)", mesh, isDirichlet, points,
    walks, settings));
#endif
  // The gradient with control variates, without and with antithetic pairs
  // (zombie's defaults use both; a pair's two walks count as one sample).
  for (const bool pairs : { false, true })
  {
    DerivativeRequest request;
    request.Gradient = true;
    request.AntitheticPairs = pairs;
    StarDerivativeWalks<3> gradient(neumann, settings, request);
    Row row = RunGradientEstimator(name +
        (pairs ? ", Neumann part, gradient: walk on stars"
               : ", Neumann part, gradient without antithetic pairs: walk on stars"),
      gradient, points, walks, Exact, ExactGradient);
    row.SetupSeconds = setup;
    rows.push_back(row);
  }
#ifdef GRIDFREE_WITH_ZOMBIE
  rows.push_back(ZombieRow(name + ", Neumann part, gradient: zombie (fcpw)", mesh, isDirichlet,
    points, walks, settings, true));
#endif
  start = std::chrono::steady_clock::now();
  const MixedBoundary<3> mixedRobin =
    MakeMixed<3>(mesh, isDirichlet, Exact, ExactGradient, true, 1.0, robin);
  setup = SecondsSince(start);
  WalkOnStarsEstimator<3> starsRobin(mixedRobin, settings);
  rows.push_back(Run(name + ", Robin part: walk on stars", setup, starsRobin, points, walks));
#ifdef GRIDFREE_WITH_ZOMBIE
  rows.push_back(ZombieRow(name + ", Robin part: zombie (fcpw)", mesh, isDirichlet, points,
    walks, settings, false, robin));
#endif
  return rows;
}
} // namespace

int main(int argc, char* argv[])
{
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  const int walks = argc > 1 ? std::max(1, std::atoi(argv[1])) : 256;
  const int count = argc > 2 ? std::max(1, std::atoi(argv[2])) : 100;

  std::vector<Row> rows;
  const Shape<3> prism = LPrism();
  for (const Row& r : Domain("L prism", prism.Mesh,
         LPrismDirichlet,
         [](const Vec3& c) { return c[2] > 0.59 ? 1.5 : 0.0; }, PointsInside(prism, count, 1),
         walks))
  {
    rows.push_back(r);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<Vec3> inSphere;
  while (static_cast<int>(inSphere.size()) < count)
  {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (p.norm() < 0.9)
    {
      inSphere.push_back(p);
    }
  }
  for (const Row& r : Domain("sphere", MakeIcosphere(5), [](const Vec3& c) { return c[2] < 0.0; },
         [](const Vec3& c) { return c[2] > 0.5 ? 1.5 : 0.0; }, inSphere, walks))
  {
    rows.push_back(r);
  }

  std::printf("Walk on stars against walk on spheres: %d points x %d walks, one thread, "
              "epsilon 1e-4\n\n", count, walks);
  std::printf("| domain and solver | set-up s | walks/s | steps/walk | RMSE | gradient RMSE | time per walk / walk on spheres |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  double reference = 0.0;
  for (const Row& r : rows)
  {
    if (r.Name.find("walk on spheres") != std::string::npos)
    {
      reference = r.WalksPerSecond;
    }
    char gradient[32] = "";
    if (r.GradientRmse >= 0.0)
    {
      std::snprintf(gradient, sizeof(gradient), "%.2e", r.GradientRmse);
    }
    std::printf("| %s | %.3f | %.0f | %.1f | %.2e | %s | %.2f |\n", r.Name.c_str(),
      r.SetupSeconds, r.WalksPerSecond, r.StepsPerWalk, r.Rmse, gradient,
      reference / r.WalksPerSecond);
  }

  // At equal error: each zombie row against the row of ours before it with
  // the same problem (its name with "zombie (fcpw)" for "walk on stars").
  const std::string theirs = "zombie (fcpw)", ours = "walk on stars";
  bool header = false;
  for (const Row& z : rows)
  {
    const std::size_t at = z.Name.find(theirs);
    if (at == std::string::npos)
    {
      continue;
    }
    const std::string match = z.Name.substr(0, at) + ours;
    for (const Row& r : rows)
    {
      if (r.Name != match)
      {
        continue;
      }
      if (!header)
      {
        std::printf("\nAt equal error: seconds × MSE (of the gradient where estimated), the "
                    "time each needs for the same RMSE\n\n");
        std::printf("| problem | ours: s × MSE | zombie: s × MSE | zombie / ours |\n");
        std::printf("|---|---:|---:|---:|\n");
        header = true;
      }
      const bool g = r.GradientRmse >= 0.0 && z.GradientRmse >= 0.0;
      const double e1 = g ? r.GradientRmse : r.Rmse, e2 = g ? z.GradientRmse : z.Rmse;
      const double mine = r.Seconds() * e1 * e1, yours = z.Seconds() * e2 * e2;
      std::printf("| %s | %.3e | %.3e | %.2f |\n", z.Name.substr(0, at - 2).c_str(), mine,
        yours, yours / mine);
    }
  }
  return 0;
}
