// Walks per second on a CSG domain against one mesh of the same domain, one
// thread, in one run (issue "CSG at mesh speed"). Three CSG trees whose
// domain is exactly the big sphere's, so the walks solve the same problem:
//   union(big sphere, small sphere inside it),
//   intersection(big sphere, bigger sphere around it) and
//   intersection(big sphere, a sphere just around it), where both operands
//   are near the walks;
// each operand a triangle mesh (MeshSignedDistance), with the sign from
// pseudonormals (clean meshes) or from rays (the same meshes as soups).
// The boundary values are the harmonic x² − y², so the walks' RMSE against
// it is printed beside the rate, and the set-up time (hierarchies, grids,
// sign checks) beside that.
//
//   GridFreeCsgBenchmark [walks per point] [points]
#include "BenchmarkRows.h"
#include "TestMeshes.h"
#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/MeshSignedDistance.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;
using namespace gridfree::bench;

namespace
{
double Saddle(const Vec3& x)
{
  return x[0] * x[0] - x[1] * x[1];
}

class SaddleValues final : public BoundaryValueFunction<3>
{
public:
  int Components() const override { return 1; }
  void Evaluate(const ClosestPointResult<3>& hit, double* out) const override
  {
    out[0] = Saddle(hit.point);
  }
};

SimplexMesh<3> Soup(const SimplexMesh<3>& mesh)
{
  SimplexMesh<3> soup;
  for (const auto& t : mesh.Simplices)
  {
    const auto base = static_cast<std::int64_t>(soup.Vertices.size());
    for (int k = 0; k < 3; ++k)
    {
      soup.Vertices.push_back(mesh.Vertices[static_cast<std::size_t>(t[k])]);
    }
    soup.Simplices.push_back({ base, base + 1, base + 2 });
  }
  return soup;
}

std::shared_ptr<MeshSignedDistance<3>> Operand(const SimplexMesh<3>& mesh, bool soup)
{
  const SimplexMesh<3> m = soup ? Soup(mesh) : mesh;
  return std::make_shared<MeshSignedDistance<3>>(m.Vertices, m.Simplices);
}

Row Run(const std::string& name, const Boundary<3>& boundary, const std::vector<Vec3>& points,
  int walks)
{
  WalkSettings settings;
  settings.Epsilon = 1e-4;
  WalkOnSpheresEstimator<3> estimator(boundary, settings);
  return RunEstimator(name, estimator, points, walks, Saddle);
}
} // namespace

int main(int argc, char* argv[])
{
  // One thread for everything, set-up included.
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  const int walks = argc > 1 ? std::max(1, std::atoi(argv[1])) : 256;
  const int count = argc > 2 ? std::max(1, std::atoi(argv[2])) : 200;
  const SimplexMesh<3> big = MakeIcosphere(5);          // 20,480 triangles, radius 1
  const SimplexMesh<3> small = MakeIcosphere(3, 0.3);   // inside it
  const SimplexMesh<3> bigger = MakeIcosphere(3, 1.5);  // around it
  const SimplexMesh<3> around = MakeIcosphere(4, 1.05); // just around it
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < count)
  {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (p.norm() < 0.9)
    {
      points.push_back(p);
    }
  }

  std::vector<Row> rows;
  {
    const auto start = std::chrono::steady_clock::now();
    Boundary<3> mesh;
    std::vector<double> values;
    for (const Vec3& v : big.Vertices)
    {
      values.push_back(Saddle(v));
    }
    mesh.Set(big.Vertices, big.Simplices, ValueAssociation::Points, 1, values);
    const double setup = SecondsSince(start);
    rows.push_back(Run("one mesh (the big sphere)", mesh, points, walks));
    rows.back().SetupSeconds = setup;
  }
  const auto values = std::make_shared<SaddleValues>();
  for (bool soup : { false, true })
  {
    const std::string sign = soup ? "rays (soups)" : "pseudonormals";
    for (const auto& [op, other, label] :
      { std::make_tuple(CsgOperation::Union, &small, "union with a sphere inside"),
        std::make_tuple(CsgOperation::Intersection, &bigger, "intersection with a sphere around"),
        std::make_tuple(
          CsgOperation::Intersection, &around, "intersection with a sphere just around") })
    {
      const auto start = std::chrono::steady_clock::now();
      const auto a = Operand(big, soup);
      auto csg = std::make_shared<CsgDistance<3>>(op, a, Operand(*other, soup));
      Boundary<3> b;
      b.SetGeometry(std::make_shared<ImplicitBoundaryGeometry<3>>(csg), values);
      const double setup = SecondsSince(start);
      if (a->SignFromPseudonormals() == soup)
      {
        std::printf("unexpected: the operands take their sign from %s\n",
          a->SignFromPseudonormals() ? "pseudonormals" : "rays");
      }
      rows.push_back(Run(std::string("CSG ") + label + ", sign by " + sign, b, points, walks));
      rows.back().SetupSeconds = setup;
    }
  }
  std::printf("\n%d points in the unit ball, %d walks each, one thread, harmonic data x^2 - y^2\n\n",
    count, walks);
  std::printf("| domain | set-up s | walks/s | steps/walk | RMSE | mesh walks/s / this |\n"
              "|---|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows)
  {
    std::printf("| %s | %.3f | %.0f | %.1f | %.2e | %.2f |\n", r.Name.c_str(), r.SetupSeconds,
      r.WalksPerSecond, r.StepsPerWalk, r.Rmse, rows[0].WalksPerSecond / r.WalksPerSecond);
  }
  return 0;
}
