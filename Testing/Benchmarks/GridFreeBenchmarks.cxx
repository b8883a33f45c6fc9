// Closest-point and walk-on-spheres throughput, beside VTK's
// vtkStaticCellLocator::FindClosestPoint on the same queries in the same run.
//
// Usage: GridFreeBenchmarks [--data skin.vtp] [--queries N] [--walks N]
// Prints one table; quote ratios, not absolute numbers (shared machines).
#include "Boundary.h"
#include "DerivativeWalkOnSpheres.h"
#include "ParallelExecution.h"
#include "RunningStatistics.h"
#include "TestMeshes.h"
#include "WalkOnSpheres.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStaticCellLocator.h"
#include "vtkXMLPolyDataReader.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace gridfree;
using Clock = std::chrono::steady_clock;

namespace
{
struct Mesh
{
  std::string Name;
  testing::SimplexMesh<3> Geometry;
};

double Seconds(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Mesh ReadVtp(const std::string& path)
{
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  Mesh mesh;
  mesh.Name = "CT skin (" + std::to_string(pd->GetNumberOfPolys()) + " tri)";
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double p[3];
    pd->GetPoint(i, p);
    mesh.Geometry.Vertices.emplace_back(p[0], p[1], p[2]);
  }
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      mesh.Geometry.Simplices.push_back({ ids[0], ids[k], ids[k + 1] });
    }
  }
  return mesh;
}

vtkSmartPointer<vtkPolyData> ToVtk(const testing::SimplexMesh<3>& mesh)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const Vec3& v : mesh.Vertices)
  {
    points->InsertNextPoint(v[0], v[1], v[2]);
  }
  vtkNew<vtkCellArray> polys;
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

// Queries uniform in the bounding box, or near the surface: a uniform point
// on a random triangle moved by up to 1% of the box diagonal.
std::vector<Vec3> MakeQueries(const Boundary<3>& boundary, const testing::SimplexMesh<3>& mesh,
  bool nearSurface, int count, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> queries(count);
  const Vec3 lo = boundary.BoundsMin(), hi = boundary.BoundsMax();
  const double offset = 0.01 * boundary.Diagonal();
  for (Vec3& q : queries)
  {
    if (!nearSurface)
    {
      q = lo + (hi - lo).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
      continue;
    }
    const auto& t = mesh.Simplices[static_cast<std::size_t>(u(rng) * mesh.Simplices.size())];
    double a = u(rng), b = u(rng);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    q = mesh.Vertices[t[0]] + a * (mesh.Vertices[t[1]] - mesh.Vertices[t[0]]) +
      b * (mesh.Vertices[t[2]] - mesh.Vertices[t[0]]);
    q += offset * u(rng) * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
  }
  return queries;
}

template <typename Body>
double RatePerSecond(std::size_t count, int threads, Body body)
{
  tbb::task_arena arena(threads);
  const auto start = Clock::now();
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
        {
          body(i);
        }
      });
  });
  return count / Seconds(start);
}

void Row(const std::string& mesh, const std::string& what, double ours1, double oursN,
  double vtk1)
{
  if (vtk1 <= 0.0)
  {
    // No VTK counterpart (walks): leave its columns empty.
    std::printf("| %-26s | %-34s | %12.0f | %12.0f | %12s | %8s |\n", mesh.c_str(), what.c_str(),
      ours1, oursN, "-", "-");
    return;
  }
  std::printf("| %-26s | %-34s | %12.0f | %12.0f | %12.0f | %7.1fx |\n", mesh.c_str(), what.c_str(),
    ours1, oursN, vtk1, ours1 / vtk1);
}
// Inside a closed triangle mesh: parity of the crossings of a ray in a fixed
// generic direction (brute force; only used to pick a few hundred points).
bool IsInside(const testing::SimplexMesh<3>& mesh, const Vec3& p)
{
  const Vec3 direction = Vec3(0.5773, 0.6123, 0.5402).normalized();
  int crossings = 0;
  for (const auto& t : mesh.Simplices)
  {
    const Vec3& a = mesh.Vertices[t[0]];
    const Vec3 e1 = mesh.Vertices[t[1]] - a;
    const Vec3 e2 = mesh.Vertices[t[2]] - a;
    const Vec3 h = direction.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300)
    {
      continue;
    }
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0.0 || u > 1.0)
    {
      continue;
    }
    const Vec3 q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0.0 || u + v > 1.0)
    {
      continue;
    }
    crossings += e2.dot(q) / det > 0.0 ? 1 : 0;
  }
  return crossings % 2 == 1;
}

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

// A smooth source for the Poisson rows: f = 1 + 0.5 sin(x/L) cos(y/L).
class SmoothSource : public VolumeSource<3>
{
public:
  explicit SmoothSource(double length)
    : Length(length)
  {
  }
  void Evaluate(const Vec3& y, double* f) override
  {
    f[0] = 1.0 + 0.5 * std::sin(y[0] / this->Length) * std::cos(y[1] / this->Length);
  }
  bool SupportBounds(Vec3&, Vec3&) const override { return false; }

private:
  double Length;
};

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
    const double gradient = BestWalkRate(starts.size(), walksPerPoint, withDerivatives(false, false));
    const double gradientCv = BestWalkRate(starts.size(), walksPerPoint, withDerivatives(false, true));
    const double hessianCv = BestWalkRate(starts.size(), walksPerPoint, withDerivatives(true, true));
    const char* eq = poisson ? "Poisson" : "Laplace";
    std::printf("| %-26s | %-8s | %10.0f | %10.0f (%+5.1f%%) | %10.0f (%+5.1f%%) | %10.0f (%+5.1f%%) |\n",
      name.c_str(), eq, base, gradient, 100.0 * (base / gradient - 1.0), gradientCv,
      100.0 * (base / gradientCv - 1.0), hessianCv, 100.0 * (base / hessianCv - 1.0));
  }
}
} // namespace

int main(int argc, char* argv[])
{
  std::string data;
  int queryCount = 200000;
  int walkPoints = 2000;
  bool derivativesOnly = false;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--data") && i + 1 < argc)
    {
      data = argv[++i];
    }
    else if (!std::strcmp(argv[i], "--queries") && i + 1 < argc)
    {
      queryCount = std::stoi(argv[++i]);
    }
    else if (!std::strcmp(argv[i], "--walk-points") && i + 1 < argc)
    {
      walkPoints = std::stoi(argv[++i]);
    }
    else if (!std::strcmp(argv[i], "--derivatives-only"))
    {
      derivativesOnly = true;
    }
  }
  const int allThreads = ResolveThreadCount(0);

  std::vector<Mesh> meshes;
  meshes.push_back({ "icosphere (327680 tri)", testing::MakeIcosphere(7) });
  if (!data.empty())
  {
    meshes.push_back(ReadVtp(data));
  }

  std::printf("Closest-point queries/s and walks/s; ours on 1 and %d threads, "
              "vtkStaticCellLocator::FindClosestPoint on 1 thread, same queries.\n\n",
    allThreads);
  std::printf("| %-26s | %-34s | %12s | %12s | %12s | %8s |\n", "mesh", "measure", "ours 1T",
    "ours allT", "VTK 1T", "ours/VTK");
  std::printf("|%s|%s|%s|%s|%s|%s|\n", std::string(28, '-').c_str(),
    std::string(36, '-').c_str(), std::string(14, '-').c_str(), std::string(14, '-').c_str(),
    std::string(14, '-').c_str(), std::string(10, '-').c_str());

  for (const Mesh& mesh : meshes)
  {
    if (derivativesOnly)
    {
      break;
    }
    Boundary<3> boundary;
    const auto buildStart = Clock::now();
    boundary.Set(mesh.Geometry.Vertices, mesh.Geometry.Simplices, ValueAssociation::Points, 1,
      std::vector<double>(mesh.Geometry.Vertices.size(), 1.0));
    const double buildSeconds = Seconds(buildStart);

    auto polydata = ToVtk(mesh.Geometry);
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(polydata);
    const auto locatorStart = Clock::now();
    locator->BuildLocator();
    const double locatorSeconds = Seconds(locatorStart);

    for (bool nearSurface : { false, true })
    {
      const auto queries = MakeQueries(boundary, mesh.Geometry, nearSurface, queryCount, 7);
      std::vector<double> ours(queries.size()), theirs(queries.size());
      const std::string where = nearSurface ? "near surface" : "uniform in box";

      // VTK, one thread (FindClosestPoint keeps per-locator scratch state).
      vtkNew<vtkGenericCell> cell;
      // VTK's locator is slow far from the surface: time-box it to ~3 s.
      std::size_t vtkCount = 0;
      const auto vtkStart = Clock::now();
      for (std::size_t i = 0; i < queries.size(); ++i, ++vtkCount)
      {
        if ((i & 255) == 0 && Seconds(vtkStart) > 3.0)
        {
          break;
        }
        double x[3] = { queries[i][0], queries[i][1], queries[i][2] }, cp[3], d2;
        vtkIdType cellId;
        int subId;
        locator->FindClosestPoint(x, cp, cell, cellId, subId, d2);
        theirs[i] = std::sqrt(d2);
      }
      const double vtkRate = vtkCount / Seconds(vtkStart);

      const double cp1 = RatePerSecond(queries.size(), 1,
        [&](std::size_t i) { ours[i] = boundary.ClosestPoint(queries[i]).distance; });
      const double cpN = RatePerSecond(queries.size(), allThreads,
        [&](std::size_t i) { ours[i] = boundary.ClosestPoint(queries[i]).distance; });
      const double d1 = RatePerSecond(
        queries.size(), 1, [&](std::size_t i) { ours[i] = boundary.Distance(queries[i]); });
      const double dN = RatePerSecond(queries.size(), allThreads,
        [&](std::size_t i) { ours[i] = boundary.Distance(queries[i]); });

      // Same answers as VTK (up to VTK's float tolerance).
      double worst = 0.0;
      for (std::size_t i = 0; i < vtkCount; ++i)
      {
        worst = std::max(worst, std::abs(ours[i] - theirs[i]));
      }
      Row(mesh.Name, "closest point, " + where, cp1, cpN, vtkRate);
      Row(mesh.Name, "distance only, " + where, d1, dN, vtkRate);
      if (worst > 1e-6 * boundary.Diagonal())
      {
        std::printf("WARNING: answers differ from VTK by up to %g\n", worst);
      }
    }

    // Walks: Laplace WoS (epsilon 1e-4 of the diagonal) from points uniform
    // in the box of the mesh (interior and exterior walks alike).
    WalkSettings settings;
    settings.Epsilon = 1e-4 * boundary.Diagonal();
    const auto starts = MakeQueries(boundary, mesh.Geometry, false, walkPoints, 11);
    const int walksPerPoint = 16;
    std::vector<std::uint64_t> steps(starts.size());
    auto walk = [&](std::size_t i) {
      WalkOnSpheresEstimator<3> estimator(boundary, settings);
      RunningStatistics stats(1);
      WalkCounters counters;
      const double xyz[3] = { starts[i][0], starts[i][1], starts[i][2] };
      estimator.EstimatePoint(xyz, 1, 0, walksPerPoint, stats, counters);
      steps[i] = counters.Steps;
    };
    const double w1 = RatePerSecond(starts.size(), 1, walk) * walksPerPoint;
    const double wN = RatePerSecond(starts.size(), allThreads, walk) * walksPerPoint;
    std::uint64_t totalSteps = 0;
    for (auto s : steps)
    {
      totalSteps += s;
    }
    char what[64];
    std::snprintf(what, sizeof(what), "walks/s (%.1f steps/walk)",
      double(totalSteps) / (double(starts.size()) * walksPerPoint));
    Row(mesh.Name, what, w1, wN, 0.0);
    std::printf("| %-26s | build (s): ours %.3f, VTK %.3f     | %12s | %12s | %12s | %8s |\n",
      mesh.Name.c_str(), buildSeconds, locatorSeconds, "", "", "", "");
  }

  // Derivative cost, interior points of each mesh (the walks of points
  // outside are longer, which would only dilute the difference).
  std::printf("\nCost of derivatives: walks/s on 1 thread (best of 3), 16 walks per point; "
              "in parentheses the extra time per walk relative to the value alone.\n\n");
  std::printf("| %-26s | %-8s | %10s | %-21s | %-21s | %-21s |\n", "mesh", "equation",
    "value", "+ gradient", "+ gradient, CV", "+ gradient + Hessian, CV");
  std::printf("|%s|%s|%s|%s|%s|%s|\n", std::string(28, '-').c_str(),
    std::string(10, '-').c_str(), std::string(12, '-').c_str(), std::string(23, '-').c_str(),
    std::string(23, '-').c_str(), std::string(23, '-').c_str());
  for (const Mesh& mesh : meshes)
  {
    Boundary<3> boundary;
    boundary.Set(mesh.Geometry.Vertices, mesh.Geometry.Simplices, ValueAssociation::Points, 1,
      std::vector<double>(mesh.Geometry.Vertices.size(), 1.0));
    std::vector<Vec3> inside;
    for (const Vec3& p : MakeQueries(boundary, mesh.Geometry, false, 20 * walkPoints, 13))
    {
      if (static_cast<int>(inside.size()) < walkPoints / 4 && IsInside(mesh.Geometry, p))
      {
        inside.push_back(p);
      }
    }
    DerivativeCostTable(mesh.Name, boundary, inside);
  }
  return 0;
}
