// One of the two files that include the authors' headers (see
// ZombieCacheRows.h). The steps are those of their demo's
// runBoundaryValueCaching, with their defaults but for the cache size,
// the walks and ε.
#include "ZombieCacheRows.h"

#include <zombie/point_estimation/walk_on_stars.h>
#include <zombie/utils/fcpw_geometric_queries.h>
#include <zombie/variance_reduction/boundary_value_caching.h>
#include "ZombieMesh.h"

#include <cmath>
#include <memory>

namespace gridfree
{
namespace bench
{
using namespace zombie_mesh;

ZombieCacheResult RunZombieBoundaryValueCaching(const std::vector<Point>& vertices,
  const std::vector<std::array<std::int64_t, 3>>& triangles,
  const std::function<double(const Point&)>& exact, const std::vector<Point>& points,
  const ZombieCacheSettings& settings)
{
  ZombieCacheResult result;
  const auto setupStart = std::chrono::steady_clock::now();
  Part absorbing;
  std::vector<int> map(vertices.size(), -1);
  for (const auto& t : triangles)
  {
    Add(absorbing, map, vertices, t);
  }
  zombie::Vector3 lo, hi;
  Bounds(vertices, lo, hi);
  zombie::GeometricQueries<3> queries(true, lo, hi);
  zombie::FcpwDirichletBoundaryHandler<3> dirichletHandler;
  UseDirichletPart(dirichletHandler, absorbing, queries);
  result.SetupSeconds = SecondsSince(setupStart);

  const auto start = std::chrono::steady_clock::now();
  zombie::PDE<float, 3> pde;
  pde.source = [](const zombie::Vector3&) { return 0.0f; };
  pde.isSourceConstant = true;
  pde.dirichlet = [&exact](const zombie::Vector3& x, bool) {
    return static_cast<float>(exact(ToDouble(x)));
  };
  pde.robin = [](const zombie::Vector3&, const zombie::Vector3&, bool) { return 0.0f; };
  pde.robinCoeff = [](const zombie::Vector3&, const zombie::Vector3&, bool) { return 0.0f; };
  pde.hasReflectingBoundaryConditions = [](const zombie::Vector3&) { return false; };
  pde.areRobinConditionsPureNeumann = true;

  const float epsilon = static_cast<float>(settings.Epsilon);
  const float offset = 5.0f * epsilon; // their normalOffsetForAbsorbingBoundary default
  auto absorbingSampler = zombie::createUniformTriangleBoundarySampler<float>(
    absorbing.Positions, absorbing.Indices, queries.insideBoundingDomain);
  absorbingSampler->initialize(offset, false);
  // No reflecting part: its sampler (which the solver needs) gets the same
  // triangles and is asked for no samples (an empty one prints a warning).
  auto reflectingSampler = zombie::createUniformTriangleBoundarySampler<float>(
    absorbing.Positions, absorbing.Indices, queries.insideBoundingDomain);
  reflectingSampler->initialize(0.0f, false);
  auto domainSampler = zombie::createUniformDomainSampler<float, 3>(
    queries.insideDomain, queries.domainMin, queries.domainMax, 1.0f);
  zombie::bvc::BoundaryValueCachingSolver<float, 3> solver(
    queries, absorbingSampler, reflectingSampler, domainSampler);
  solver.generateSamples(settings.CachePoints, 0, 0, offset, 0.0f, false);

  zombie::WalkSettings walk(epsilon, epsilon, 1024, false);
  walk.ignoreSourceContribution = true;
  const int solutionWalks = 128; // their default; unused on a Dirichlet-only boundary
  solver.computeSampleEstimates(pde, walk, solutionWalks, settings.GradientWalks,
    std::numeric_limits<float>::max(), false, false);

  std::vector<zombie::bvc::EvaluationPoint<float, 3>> evaluation;
  evaluation.reserve(points.size());
  for (const Point& p : points)
  {
    const zombie::Vector3 x = ToFloat(p);
    const float d = queries.computeDistToAbsorbingBoundary(x, false);
    evaluation.emplace_back(x, zombie::Vector3::Zero(), zombie::SampleType::InDomain, d,
      queries.computeDistToReflectingBoundary(x, false));
    result.NearBoundaryPoints += d < offset ? 1 : 0;
  }
  solver.splat(pde, 0.0f, 0.0f, std::numeric_limits<float>::max(), offset, 0.0f, evaluation);
  solver.estimateSolutionNearBoundary(pde, walk, offset, 0.0f, solutionWalks, evaluation, false);
  result.Seconds = SecondsSince(start);

  double squared = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double e = evaluation[i].getEstimatedSolution() - exact(points[i]);
    squared += e * e;
  }
  result.Rmse = std::sqrt(squared / static_cast<double>(points.size()));
  return result;
}
} // namespace bench
} // namespace gridfree
