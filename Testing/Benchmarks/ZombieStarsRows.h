// The authors' walk on stars (the library "zombie" with its closest-point
// library "fcpw", Sawhney et al.) on the benchmark's mixed problems, beside
// the project's own: built only when their public sources are given at
// configure time (GRIDFREE_ZOMBIE_SOURCE_DIR, Testing/Benchmarks/
// CMakeLists.txt). Nothing of theirs is part of the project. This interface
// uses plain types only: their pcg32 and the core's (pcg-cpp's) share a
// name, so the file that includes their headers includes none of the core.
#ifndef GRIDFREE_BENCHMARKS_ZOMBIESTARSROWS_H
#define GRIDFREE_BENCHMARKS_ZOMBIESTARSROWS_H

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace gridfree
{
namespace bench
{
// A mixed Laplace problem on a triangle mesh: the triangles `isDirichlet`
// picks (by centroid) hold u = exact, the others the flux ∇u·n + μu with μ
// = Robin(x) (empty: 0, Neumann) at each point x of them.
struct ZombieProblem
{
  std::vector<std::array<double, 3>> Vertices;
  std::vector<std::array<std::int64_t, 3>> Triangles;
  std::function<bool(const std::array<double, 3>&)> IsDirichlet;
  std::function<double(const std::array<double, 3>&)> Exact;
  std::function<std::array<double, 3>(const std::array<double, 3>&)> Gradient;
  std::function<double(const std::array<double, 3>&)> Robin;
};

struct ZombieResult
{
  double SetupSeconds = 0.0; // the hierarchies and the silhouettes
  double WalksPerSecond = 0.0;
  double StepsPerWalk = 0.0;
  double Rmse = 0.0;         // against Exact over the points
  double GradientRmse = 0.0; // |∇u estimate − Gradient|, when asked for
};

// zombie's WalkOnStars<float, 3>, one thread, `walks` walks at every point,
// ε = `epsilon` for both of its ε-shells, at most `maxSteps` steps per walk,
// n the normal zombie hands over; pcg32 streams seeded per point so that
// runs repeat (zombie seeds from the clock by default). With `gradient`,
// its solution-and-gradient estimator with its default control and
// antithetic variates. With a Robin rule, its Robin hierarchy with each
// triangle's μ (at its centroid) as the bounds of its Robin radius.
ZombieResult RunZombieWalkOnStars(const ZombieProblem& problem,
  const std::vector<std::array<double, 3>>& points, int walks, double epsilon, int maxSteps,
  bool gradient = false);
} // namespace bench
} // namespace gridfree

#endif
