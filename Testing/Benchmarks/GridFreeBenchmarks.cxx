// Closest-point and walk-on-spheres throughput, beside VTK's
// vtkStaticCellLocator::FindClosestPoint on the same queries in the same run.
//
// Usage: GridFreeBenchmarks [--data skin.vtp] [--queries N] [--walks N]
// Prints one table; quote ratios, not absolute numbers (shared machines).
#include "Boundary.h"
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

#include <chrono>
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
} // namespace

int main(int argc, char* argv[])
{
  std::string data;
  int queryCount = 200000;
  int walkPoints = 2000;
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
  return 0;
}
