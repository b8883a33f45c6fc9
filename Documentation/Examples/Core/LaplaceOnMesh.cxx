// Laplace's equation inside a triangle mesh with GridFree::Core alone: no
// VTK, no ParaView. The program reads a Wavefront OBJ or OFF file itself,
// builds the boundary (mesh, hierarchy and values) once, and estimates the
// harmonic function u = 1 / |x - p| (p a pole outside the mesh's box) from
// its boundary values at points inside, with walk on spheres (paper Eqn. 5).
// It prints each estimate with its standard error and the exact value, and
// fails when an estimate is more than 5 standard errors off.
//
//   LaplaceOnMesh mesh.obj [walks] [x y z ...]
//
// Without points it solves at the mesh's volume centroid and at six points
// around it, a tenth of the way to the box's faces (fine for a round solid
// such as the bundled Data/spot.obj; give points inside other shapes).
#include <gridfree/boundary/Boundary.h>
#include <gridfree/estimators/WalkOnSpheres.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using gridfree::Vec3;
using Triangle = gridfree::Boundary<3>::Primitive;

struct Mesh
{
  std::vector<Vec3> Vertices;
  std::vector<Triangle> Triangles;
};

// Adds a polygon as a fan of triangles.
void AddPolygon(const std::vector<std::int64_t>& polygon, Mesh& mesh)
{
  for (std::size_t k = 2; k < polygon.size(); ++k)
  {
    mesh.Triangles.push_back({ polygon[0], polygon[k - 1], polygon[k] });
  }
}

// OBJ: `v x y z` and `f i j k ...` (1-based, negative = from the end,
// `i/t/n` forms accepted); everything else is ignored.
bool ReadObj(std::istream& in, Mesh& mesh)
{
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v")
    {
      Vec3 v;
      words >> v[0] >> v[1] >> v[2];
      mesh.Vertices.push_back(v);
    }
    else if (tag == "f")
    {
      std::vector<std::int64_t> polygon;
      std::string corner;
      while (words >> corner)
      {
        const long long index = std::stoll(corner.substr(0, corner.find('/')));
        polygon.push_back(index > 0 ? index - 1
                                    : static_cast<std::int64_t>(mesh.Vertices.size()) + index);
      }
      AddPolygon(polygon, mesh);
    }
  }
  return !mesh.Triangles.empty();
}

// OFF: a header line, counts, vertices, then `n i0 ... i(n-1)` faces.
bool ReadOff(std::istream& in, Mesh& mesh)
{
  std::string header;
  long long nv = 0, nf = 0, ne = 0;
  if (!(in >> header >> nv >> nf >> ne) || header != "OFF")
  {
    return false;
  }
  mesh.Vertices.resize(static_cast<std::size_t>(nv));
  for (Vec3& v : mesh.Vertices)
  {
    in >> v[0] >> v[1] >> v[2];
  }
  for (long long f = 0; f < nf; ++f)
  {
    int n = 0;
    in >> n;
    std::vector<std::int64_t> polygon(static_cast<std::size_t>(n));
    for (std::int64_t& i : polygon)
    {
      in >> i;
    }
    AddPolygon(polygon, mesh);
  }
  return static_cast<bool>(in) && !mesh.Triangles.empty();
}

bool ReadMesh(const std::string& path, Mesh& mesh)
{
  std::ifstream in(path);
  if (!in)
  {
    return false;
  }
  const bool off = path.size() > 4 && path.compare(path.size() - 4, 4, ".off") == 0;
  if (!(off ? ReadOff(in, mesh) : ReadObj(in, mesh)))
  {
    return false;
  }
  for (const Triangle& t : mesh.Triangles)
  {
    for (std::int64_t i : t)
    {
      if (i < 0 || i >= static_cast<std::int64_t>(mesh.Vertices.size()))
      {
        return false;
      }
    }
  }
  return true;
}

// Centroid of the solid a closed, consistently oriented mesh bounds (signed
// tetrahedra from the origin); the vertex mean if the volume vanishes.
Vec3 VolumeCentroid(const Mesh& mesh)
{
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const Triangle& t : mesh.Triangles)
  {
    const Vec3& a = mesh.Vertices[t[0]];
    const Vec3& b = mesh.Vertices[t[1]];
    const Vec3& c = mesh.Vertices[t[2]];
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    moment += v * (a + b + c) / 4.0;
  }
  if (std::abs(volume) > 0.0)
  {
    return moment / volume;
  }
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : mesh.Vertices)
  {
    mean += v;
  }
  return mean / static_cast<double>(mesh.Vertices.size());
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    std::cerr << "usage: " << argv[0] << " mesh.obj|mesh.off [walks] [x y z ...]\n";
    return 2;
  }
  Mesh mesh;
  if (!ReadMesh(argv[1], mesh))
  {
    std::cerr << "cannot read a triangle mesh from " << argv[1] << "\n";
    return 2;
  }
  const int walks = argc > 2 ? std::atoi(argv[2]) : 4096;

  // Boundary values of a harmonic function: u = 1 / |x - pole|, the pole
  // beyond the box, so u is harmonic everywhere inside the mesh.
  Vec3 lo = mesh.Vertices.front(), hi = lo;
  for (const Vec3& v : mesh.Vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 pole = hi + 0.5 * (hi - lo);
  auto exact = [&pole](const Vec3& x) { return 1.0 / (x - pole).norm(); };
  std::vector<double> values;
  values.reserve(mesh.Vertices.size());
  for (const Vec3& v : mesh.Vertices)
  {
    values.push_back(exact(v));
  }

  std::vector<Vec3> points;
  for (int a = 3; a + 2 < argc; a += 3)
  {
    points.emplace_back(std::atof(argv[a]), std::atof(argv[a + 1]), std::atof(argv[a + 2]));
  }
  if (points.empty())
  {
    const Vec3 centre = VolumeCentroid(mesh);
    points.push_back(centre);
    for (int axis = 0; axis < 3; ++axis)
    {
      Vec3 below = centre, above = centre;
      below[axis] -= 0.1 * (centre[axis] - lo[axis]);
      above[axis] += 0.1 * (hi[axis] - centre[axis]);
      points.push_back(below);
      points.push_back(above);
    }
  }

  // The boundary: mesh, hierarchy, distance bounds and values, built once
  // and shared (read-only) by every thread's estimator.
  gridfree::Boundary<3> boundary;
  const std::size_t triangles = mesh.Triangles.size();
  boundary.Set(std::move(mesh.Vertices), std::move(mesh.Triangles),
    gridfree::ValueAssociation::Points, 1, std::move(values));

  gridfree::WalkSettings settings;
  settings.Problem = gridfree::Equation::Laplace;
  settings.Epsilon = 1e-4 * boundary.Diagonal();

  // Every point's walks on all threads; the random streams depend on the
  // seed, the point and the walk's number only, so the numbers are the same
  // for any thread count.
  const std::uint64_t seed = 7;
  std::vector<double> mean(points.size()), variance(points.size());
  gridfree::ParallelForWithProgress(points.size(), 0,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      gridfree::WalkOnSpheresEstimator<3> estimator(boundary, settings);
      gridfree::RunningStatistics stats(estimator.OutputComponents());
      for (std::size_t i = begin; i < end; ++i)
      {
        const double xyz[3] = { points[i][0], points[i][1], points[i][2] };
        gridfree::WalkCounters counters;
        stats.Reset();
        estimator.EstimatePoint(xyz, seed, 0, walks, stats, counters);
        mean[i] = stats.GetMean(0);
        variance[i] = stats.VarianceOfMean(0);
      }
    },
    nullptr, 0.1, 1);

  std::printf("%zu triangles, %d walks per point\n", triangles, walks);
  std::printf("%10s %10s %10s %12s %12s %12s %7s\n", "x", "y", "z", "estimate", "std. error",
    "exact", "z");
  int failures = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double error = std::sqrt(variance[i]);
    const double z = (mean[i] - exact(points[i])) / error;
    std::printf("%10.4g %10.4g %10.4g %12.6g %12.3g %12.6g %7.2f\n", points[i][0], points[i][1],
      points[i][2], mean[i], error, exact(points[i]), z);
    failures += std::isfinite(z) && std::abs(z) < 5.0 ? 0 : 1;
  }
  if (failures > 0)
  {
    std::printf("%d estimates are more than 5 standard errors from the exact value\n", failures);
    return 1;
  }
  std::printf("every estimate within 5 standard errors of the exact value\n");
  return 0;
}
