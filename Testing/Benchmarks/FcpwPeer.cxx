// One build of fcpw (and zombie) for GridFreePeerBenchmark; compiled once per
// SIMD width with GRIDFREE_FCPW_FACTORY naming its factory (FcpwPeer.h). The
// only file that includes the authors' headers; it includes none of the core.
#include "FcpwPeer.h"

#include <fcpw/fcpw.h>
#ifdef GRIDFREE_FCPW_WITH_ZOMBIE
#include <zombie/point_estimation/walk_on_spheres.h>
#include <zombie/utils/fcpw_geometric_queries.h>
#endif

#include <malloc.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#define GRIDFREE_EXPORT __attribute__((visibility("default")))

namespace gridfree
{
namespace bench
{
namespace
{
#define GRIDFREE_STRING2(x) #x
#define GRIDFREE_STRING(x) GRIDFREE_STRING2(x)

using Vector3 = fcpw::Vector<3>;

Vector3 ToFloat(const PeerPoint& p)
{
  return Vector3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
}

PeerPoint ToDouble(const Vector3& p)
{
  return PeerPoint{ p[0], p[1], p[2] };
}

double SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::size_t HeapInUse()
{
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

class Peer final : public FcpwPeer
{
public:
  explicit Peer(const PeerMesh& mesh)
  {
    this->Positions.reserve(mesh.Vertices.size());
    for (const PeerPoint& v : mesh.Vertices)
    {
      this->Positions.push_back(ToFloat(v));
    }
    this->Indices.reserve(mesh.Triangles.size());
    for (const auto& t : mesh.Triangles)
    {
      this->Indices.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2]));
    }

    const std::size_t heapBefore = HeapInUse();
    const auto start = std::chrono::steady_clock::now();
    // As zombie builds it (FcpwDirichletBoundaryHandler), memory footprint
    // reduced.
    this->Scene.setObjectCount(1);
    this->Scene.setObjectVertices(this->Positions, 0);
    this->Scene.setObjectTriangles(this->Indices, 0);
    this->Scene.build(fcpw::AggregateType::Bvh_SurfaceArea, true, false, true);
    this->Build = SecondsSince(start);
    const std::size_t heapAfter = HeapInUse();
    this->Bytes = heapAfter > heapBefore ? heapAfter - heapBefore : 0;
  }

  const char* Name() const override { return "fcpw w" GRIDFREE_STRING(FCPW_SIMD_WIDTH); }
  double BuildSeconds() const override { return this->Build; }
  std::size_t HeapBytes() const override { return this->Bytes; }

  double ClosestPoint(const PeerPoint& x, PeerPoint* point) const override
  {
    fcpw::Interaction<3> interaction;
    if (!this->Scene.findClosestPoint(ToFloat(x), interaction))
    {
      return std::numeric_limits<double>::infinity();
    }
    if (point)
    {
      *point = ToDouble(interaction.p);
    }
    return interaction.d;
  }

  bool Intersect(const PeerPoint& origin, const PeerPoint& direction, double& t) const override
  {
    fcpw::Ray<3> ray(ToFloat(origin), ToFloat(direction));
    fcpw::Interaction<3> interaction;
    if (!this->Scene.intersect(ray, interaction))
    {
      return false;
    }
    t = interaction.d;
    return true;
  }

  bool HasWalks() const override
  {
#ifdef GRIDFREE_FCPW_WITH_ZOMBIE
    return true;
#else
    return false;
#endif
  }

  PeerWalkResult Walk(const PeerWalkProblem& problem, const std::vector<PeerPoint>& points,
    int walks, double epsilon, bool gradient) const override;

private:
  std::vector<Vector3> Positions;
  std::vector<fcpw::Vector3i> Indices;
  fcpw::Scene<3> Scene;
  double Build = 0.0;
  std::size_t Bytes = 0;
};

PeerWalkResult Peer::Walk(const PeerWalkProblem& problem, const std::vector<PeerPoint>& points,
  int walks, double epsilon, bool gradient) const
{
  PeerWalkResult result;
#ifdef GRIDFREE_FCPW_WITH_ZOMBIE
  // As zombie's demo sets up a Dirichlet problem: its boundary handler builds
  // its own fcpw scene, here vectorized like the one above.
  const auto setupStart = std::chrono::steady_clock::now();
  Vector3 lo = Vector3::Constant(std::numeric_limits<float>::max());
  Vector3 hi = -lo;
  for (const Vector3& v : this->Positions)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  zombie::GeometricQueries<3> queries(true, lo, hi);
  zombie::FcpwDirichletBoundaryHandler<3> handler;
  handler.buildAccelerationStructure(this->Positions, this->Indices, true, true, false);
  zombie::populateGeometricQueriesForDirichletBoundary<3>(handler, queries);
  result.SetupSeconds = SecondsSince(setupStart);

  zombie::PDE<float, 3> pde;
  pde.source = [](const Vector3&) { return 0.0f; };
  pde.isSourceConstant = true;
  pde.dirichlet = [&problem](const Vector3& x, bool) {
    return static_cast<float>(problem.Exact(ToDouble(x)));
  };
  pde.robin = [](const Vector3&, const Vector3&, bool) { return 0.0f; };
  pde.robinCoeff = [](const Vector3&, const Vector3&, bool) { return 0.0f; };
  pde.hasReflectingBoundaryConditions = [](const Vector3&) { return false; };
  pde.areRobinConditionsPureNeumann = true;
  const float eps = static_cast<float>(epsilon);
  zombie::WalkSettings settings(eps, eps, 10000, false);
  settings.ignoreSourceContribution = true;

  std::vector<zombie::SamplePoint<float, 3>> samples;
  samples.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Vector3 x = ToFloat(points[i]);
    samples.emplace_back(x, Vector3::Zero(), zombie::SampleType::InDomain,
      gradient ? zombie::EstimationQuantity::SolutionAndGradient
               : zombie::EstimationQuantity::Solution,
      1.0f, queries.computeDistToAbsorbingBoundary(x, false), 0.0f);
    samples.back().rng = pcg32(7, i);
  }
  std::vector<zombie::SampleStatistics<float, 3>> statistics;
  const std::vector<int> walkCounts(points.size(), walks);
  zombie::WalkOnSpheres<float, 3> solver(queries);
  const auto start = std::chrono::steady_clock::now();
  solver.solve(pde, settings, walkCounts, samples, statistics, true);
  result.Seconds = SecondsSince(start);

  double steps = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    result.Values.push_back(statistics[i].getEstimatedSolution());
    if (gradient)
    {
      const float* g = statistics[i].getEstimatedGradient();
      result.Gradients.push_back(PeerPoint{ g[0], g[1], g[2] });
    }
    steps += statistics[i].getMeanWalkLength();
  }
  result.StepsPerWalk = points.empty() ? 0.0 : steps / static_cast<double>(points.size());
#else
  (void)problem;
  (void)points;
  (void)walks;
  (void)epsilon;
  (void)gradient;
#endif
  return result;
}
} // namespace

GRIDFREE_EXPORT std::unique_ptr<FcpwPeer> GRIDFREE_FCPW_FACTORY(const PeerMesh& mesh)
{
  return std::make_unique<Peer>(mesh);
}
} // namespace bench
} // namespace gridfree
