// One of the two files that include the authors' headers (see ZombieStarsRows.h).
#include "ZombieStarsRows.h"

#include <zombie/point_estimation/walk_on_stars.h>
#include <zombie/utils/fcpw_geometric_queries.h>
#include "ZombieMesh.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
namespace bench
{
using namespace zombie_mesh;

ZombieResult RunZombieWalkOnStars(const ZombieProblem& problem,
  const std::vector<std::array<double, 3>>& points, int walks, double epsilon, int maxSteps,
  bool gradient)
{
  const auto setupStart = std::chrono::steady_clock::now();
  Part absorbing, reflecting;
  std::vector<float> reflectingMu; // per reflecting triangle
  const std::vector<Point>& vertices = problem.Vertices;
  std::vector<int> mapA(vertices.size(), -1), mapR(vertices.size(), -1);
  for (const auto& t : problem.Triangles)
  {
    Point centroid{ 0.0, 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      for (int d = 0; d < 3; ++d)
      {
        centroid[d] += vertices[static_cast<std::size_t>(t[k])][d] / 3.0;
      }
    }
    if (problem.IsDirichlet(centroid))
    {
      Add(absorbing, mapA, vertices, t);
    }
    else
    {
      Add(reflecting, mapR, vertices, t);
      reflectingMu.push_back(problem.Robin ? static_cast<float>(problem.Robin(centroid)) : 0.0f);
    }
  }
  zombie::Vector3 lo, hi;
  Bounds(vertices, lo, hi);
  zombie::GeometricQueries<3> queries(true, lo, hi);
  zombie::FcpwDirichletBoundaryHandler<3> dirichletHandler;
  UseDirichletPart(dirichletHandler, absorbing, queries);
  zombie::FcpwNeumannBoundaryHandler<3> neumannHandler;
  zombie::FcpwRobinBoundaryHandler<3> robinHandler;
  const bool robin = static_cast<bool>(problem.Robin);
  if (robin)
  {
    robinHandler.buildAccelerationStructure(reflecting.Positions, reflecting.Indices,
      zombie::getIgnoreCandidateSilhouetteCallback(false), reflectingMu, reflectingMu, true,
      false, false);
    zombie::populateGeometricQueriesForRobinBoundary<3>(
      robinHandler, zombie::getBranchTraversalWeightCallback(), queries);
  }
  else
  {
    neumannHandler.buildAccelerationStructure(reflecting.Positions, reflecting.Indices,
      zombie::getIgnoreCandidateSilhouetteCallback(false), true, false, false);
    zombie::populateGeometricQueriesForNeumannBoundary<3>(
      neumannHandler, zombie::getBranchTraversalWeightCallback(), queries);
  }
  ZombieResult result;
  result.SetupSeconds = SecondsSince(setupStart);

  // Laplace: u = g on the absorbing part, ∂u/∂n + μu = h on the reflecting one.
  zombie::PDE<float, 3> pde;
  pde.source = [](const zombie::Vector3&) { return 0.0f; };
  pde.isSourceConstant = true;
  pde.dirichlet = [&problem](const zombie::Vector3& x, bool) {
    return static_cast<float>(problem.Exact(ToDouble(x)));
  };
  auto mu = [&problem](const zombie::Vector3& x) {
    return problem.Robin ? problem.Robin(ToDouble(x)) : 0.0;
  };
  pde.robin = [&problem, mu](const zombie::Vector3& x, const zombie::Vector3& n, bool) {
    const Point g = problem.Gradient(ToDouble(x));
    return static_cast<float>(
      g[0] * n[0] + g[1] * n[1] + g[2] * n[2] + mu(x) * problem.Exact(ToDouble(x)));
  };
  pde.robinCoeff = [mu](const zombie::Vector3& x, const zombie::Vector3&, bool) {
    return static_cast<float>(mu(x));
  };
  pde.hasReflectingBoundaryConditions = [&problem](const zombie::Vector3& x) {
    return !problem.IsDirichlet(ToDouble(x));
  };
  pde.areRobinConditionsPureNeumann = !robin;
  const float eps = static_cast<float>(epsilon);
  zombie::WalkSettings settings(eps, eps, maxSteps, false);
  settings.ignoreSourceContribution = true;

  std::vector<zombie::SamplePoint<float, 3>> samples;
  samples.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const zombie::Vector3 x = ToFloat(points[i]);
    samples.emplace_back(x, zombie::Vector3::Zero(), zombie::SampleType::InDomain,
      gradient ? zombie::EstimationQuantity::SolutionAndGradient
               : zombie::EstimationQuantity::Solution,
      1.0f, queries.computeDistToAbsorbingBoundary(x, false),
      queries.computeDistToReflectingBoundary(x, false));
    samples.back().rng = pcg32(7, i);
  }
  std::vector<zombie::SampleStatistics<float, 3>> statistics;
  const std::vector<int> walkCounts(points.size(), walks);
  zombie::WalkOnStars<float, 3> solver(queries);
  const auto start = std::chrono::steady_clock::now();
  solver.solve(pde, settings, walkCounts, samples, statistics, true);
  const double seconds = SecondsSince(start);

  double squared = 0.0, gradientSquared = 0.0, steps = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double e = statistics[i].getEstimatedSolution() - problem.Exact(points[i]);
    squared += e * e;
    steps += statistics[i].getMeanWalkLength();
    if (gradient)
    {
      const Point exact = problem.Gradient(points[i]);
      const float* estimate = statistics[i].getEstimatedGradient();
      for (int d = 0; d < 3; ++d)
      {
        gradientSquared += (estimate[d] - exact[d]) * (estimate[d] - exact[d]);
      }
    }
  }
  const double n = static_cast<double>(points.size());
  result.WalksPerSecond = static_cast<double>(walks) * n / seconds;
  result.StepsPerWalk = steps / n;
  result.Rmse = std::sqrt(squared / n);
  result.GradientRmse = std::sqrt(gradientSquared / n);
  return result;
}
} // namespace bench
} // namespace gridfree
