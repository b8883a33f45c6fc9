#include "BenchmarkMeshes.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataReader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>

namespace gridfree
{
namespace bench
{
Box BoundsOf(const TriangleMesh& mesh)
{
  const double inf = std::numeric_limits<double>::infinity();
  Box box{ Vec3::Constant(inf), Vec3::Constant(-inf) };
  for (const auto& t : mesh.Simplices)
  {
    for (int k = 0; k < 3; ++k)
    {
      box.Min = box.Min.cwiseMin(mesh.Vertices[t[k]]);
      box.Max = box.Max.cwiseMax(mesh.Vertices[t[k]]);
    }
  }
  return box;
}

namespace
{
using Triangle = std::array<std::int64_t, 3>;

// Vertices on the edges of the icosahedron, (k - 1) per edge, created once per
// edge from its lower-numbered corner so that the two faces sharing an edge
// use the very same vertices (the sphere stays closed, no duplicate points).
std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> AddEdgeVertices(
  const std::vector<Triangle>& faces, int k, std::vector<Vec3>& vertices)
{
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> firstOnEdge;
  for (const Triangle& f : faces)
  {
    for (int e = 0; e < 3; ++e)
    {
      const std::int64_t lo = std::min(f[e], f[(e + 1) % 3]);
      const std::int64_t hi = std::max(f[e], f[(e + 1) % 3]);
      if (!firstOnEdge.emplace(std::make_pair(lo, hi), std::int64_t(vertices.size())).second)
      {
        continue;
      }
      const Vec3 a = vertices[lo], b = vertices[hi];
      for (int w = 1; w < k; ++w) // w: weight of the higher-numbered corner
      {
        vertices.push_back(((k - w) * a + w * b).normalized());
      }
    }
  }
  return firstOnEdge;
}

// Indices of the (k+1)(k+2)/2 grid points of one face, (i, j) being the
// weights of corners f[1] and f[2] (k - i - j that of f[0]); interior points
// are created here, corners and edge points looked up.
std::vector<std::int64_t> FaceGrid(const Triangle& f, int k,
  const std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t>& firstOnEdge,
  std::vector<Vec3>& vertices)
{
  std::vector<std::int64_t> grid(static_cast<std::size_t>(k + 1) * (k + 1), -1);
  for (int i = 0; i <= k; ++i)
  {
    for (int j = 0; i + j <= k; ++j)
    {
      const int w[3] = { k - i - j, i, j };
      int nonzero = 0, only = 0;
      for (int c = 0; c < 3; ++c)
      {
        nonzero += w[c] > 0 ? 1 : 0;
        only = w[c] == k ? c : only;
      }
      std::int64_t id;
      if (nonzero == 1)
      {
        id = f[only];
      }
      else if (nonzero == 2)
      {
        const int zero = w[0] == 0 ? 0 : (w[1] == 0 ? 1 : 2);
        const int p = (zero + 1) % 3, q = (zero + 2) % 3;
        const bool pLow = f[p] < f[q];
        const std::int64_t lo = pLow ? f[p] : f[q], hi = pLow ? f[q] : f[p];
        const int weightHi = pLow ? w[q] : w[p];
        id = firstOnEdge.at(std::make_pair(lo, hi)) + weightHi - 1;
      }
      else
      {
        id = static_cast<std::int64_t>(vertices.size());
        vertices.push_back(
          (w[0] * vertices[f[0]] + w[1] * vertices[f[1]] + w[2] * vertices[f[2]]).normalized());
      }
      grid[static_cast<std::size_t>(i) * (k + 1) + j] = id;
    }
  }
  return grid;
}
} // namespace

TriangleMesh MakeBumpySphere(int k, double amplitude, double frequency)
{
  if (k < 1)
  {
    throw std::invalid_argument("MakeBumpySphere: k must be at least 1");
  }
  const TriangleMesh icosahedron = testing::MakeIcosphere(0);
  TriangleMesh mesh;
  mesh.Vertices = icosahedron.Vertices;
  const auto firstOnEdge = AddEdgeVertices(icosahedron.Simplices, k, mesh.Vertices);
  mesh.Simplices.reserve(static_cast<std::size_t>(20) * k * k);
  for (const Triangle& f : icosahedron.Simplices)
  {
    const auto grid = FaceGrid(f, k, firstOnEdge, mesh.Vertices);
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i) * (k + 1) + j]; };
    // k² triangles with the orientation of the face: k(k+1)/2 pointing like
    // the face, k(k-1)/2 the other way.
    for (int i = 0; i < k; ++i)
    {
      for (int j = 0; i + j < k; ++j)
      {
        mesh.Simplices.push_back({ at(i, j), at(i + 1, j), at(i, j + 1) });
        if (i + j + 1 < k)
        {
          mesh.Simplices.push_back({ at(i + 1, j), at(i + 1, j + 1), at(i, j + 1) });
        }
      }
    }
  }
  for (Vec3& v : mesh.Vertices)
  {
    v *= 1.0 +
      amplitude * std::sin(frequency * v[0]) * std::sin(frequency * v[1]) *
        std::sin(frequency * v[2]);
  }
  return mesh;
}

TriangleMesh MakeBumpySoup(std::size_t triangles, unsigned seed)
{
  const int k = static_cast<int>(std::ceil(std::sqrt(triangles / 20.0)));
  std::vector<std::uint32_t> order;
  TriangleMesh soup;
  {
    const TriangleMesh sphere = MakeBumpySphere(k);
    order.resize(sphere.Simplices.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
    // The sphere has a few more triangles than asked; dropping the rest of
    // the shuffled order leaves small holes, which a build does not mind.
    order.resize(std::min(triangles, order.size()));
    soup.Vertices.resize(3 * order.size());
    soup.Simplices.resize(order.size());
    for (std::size_t s = 0; s < order.size(); ++s)
    {
      const auto& t = sphere.Simplices[order[s]];
      for (int c = 0; c < 3; ++c)
      {
        soup.Vertices[3 * s + c] = sphere.Vertices[t[c]];
        soup.Simplices[s][c] = static_cast<std::int64_t>(3 * s + c);
      }
    }
  }
  return soup;
}

TriangleMesh ReadPolyDataTriangles(const std::string& path)
{
  if (!std::ifstream(path).good())
  {
    throw std::runtime_error("cannot open " + path);
  }
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  if (!pd || pd->GetNumberOfPolys() == 0)
  {
    throw std::runtime_error("no polygons in " + path);
  }
  TriangleMesh mesh;
  mesh.Vertices.reserve(static_cast<std::size_t>(pd->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double p[3];
    pd->GetPoint(i, p);
    mesh.Vertices.emplace_back(p[0], p[1], p[2]);
  }
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      mesh.Simplices.push_back({ ids[0], ids[k], ids[k + 1] });
    }
  }
  return mesh;
}

double MeanEdgeLength(const TriangleMesh& mesh)
{
  double sum = 0.0;
  for (const auto& t : mesh.Simplices)
  {
    for (int k = 0; k < 3; ++k)
    {
      sum += (mesh.Vertices[t[k]] - mesh.Vertices[t[(k + 1) % 3]]).norm();
    }
  }
  return mesh.Simplices.empty() ? 0.0 : sum / (3.0 * double(mesh.Simplices.size()));
}

std::vector<Vec3> MakeQueries(
  const TriangleMesh& mesh, bool nearSurface, std::size_t count, unsigned seed)
{
  return nearSurface ? MakeQueriesNear(mesh, 0.01 * BoundsOf(mesh).Diagonal(), count, seed)
                     : MakeQueriesNear(mesh, -1.0, count, seed);
}

std::vector<Vec3> MakeQueriesNear(
  const TriangleMesh& mesh, double offset, std::size_t count, unsigned seed)
{
  const bool nearSurface = offset >= 0.0;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Box box = BoundsOf(mesh);
  std::vector<Vec3> queries(count);
  for (Vec3& q : queries)
  {
    if (!nearSurface)
    {
      q = box.Min + (box.Max - box.Min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
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

std::vector<Vec3> MakeInsidePoints(
  const TriangleMesh& mesh, double shrink, std::size_t count, unsigned seed)
{
  const InsideTest inside(mesh);
  const Box box = BoundsOf(mesh);
  const Vec3 c = box.Center();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points;
  for (std::size_t tries = 0; points.size() < count && tries < 200 * count; ++tries)
  {
    const Vec3 p = box.Min + (box.Max - box.Min).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    if (inside.Contains(c + (p - c) / shrink))
    {
      points.push_back(p);
    }
  }
  return points;
}

InsideTest::InsideTest(const TriangleMesh& mesh)
  : Mesh(mesh)
{
  if (mesh.Simplices.size() >= std::numeric_limits<std::uint32_t>::max())
  {
    throw std::length_error("InsideTest: too many triangles");
  }
  const Box box = BoundsOf(mesh);
  // About two triangles per cell on a closed surface (its shadow covers each
  // point twice), capped to keep the table small.
  const int n = std::clamp(static_cast<int>(std::sqrt(mesh.Simplices.size() / 2.0)), 1, 2048);
  this->Ny = this->Nz = n;
  this->Y0 = box.Min[1];
  this->Z0 = box.Min[2];
  const double dy = box.Max[1] - box.Min[1], dz = box.Max[2] - box.Min[2];
  this->InvCellY = dy > 0.0 ? n / dy : 0.0;
  this->InvCellZ = dz > 0.0 ? n / dz : 0.0;

  // Two passes over the triangles' (y, z) boxes: count per cell, then fill.
  auto forEachCell = [&](const std::array<std::int64_t, 3>& t, auto visit) {
    double ylo = mesh.Vertices[t[0]][1], yhi = ylo, zlo = mesh.Vertices[t[0]][2], zhi = zlo;
    for (int c = 1; c < 3; ++c)
    {
      ylo = std::min(ylo, mesh.Vertices[t[c]][1]);
      yhi = std::max(yhi, mesh.Vertices[t[c]][1]);
      zlo = std::min(zlo, mesh.Vertices[t[c]][2]);
      zhi = std::max(zhi, mesh.Vertices[t[c]][2]);
    }
    const int c0 = this->Cell(ylo, zlo), c1 = this->Cell(yhi, zhi);
    for (int iy = c0 / this->Nz; iy <= c1 / this->Nz; ++iy)
    {
      for (int iz = c0 % this->Nz; iz <= c1 % this->Nz; ++iz)
      {
        visit(iy * this->Nz + iz);
      }
    }
  };
  this->CellStart.assign(static_cast<std::size_t>(this->Ny) * this->Nz + 1, 0);
  for (const auto& t : mesh.Simplices)
  {
    forEachCell(t, [&](int cell) { ++this->CellStart[cell + 1]; });
  }
  std::partial_sum(this->CellStart.begin(), this->CellStart.end(), this->CellStart.begin());
  this->CellTriangles.resize(this->CellStart.back());
  std::vector<std::uint64_t> next(this->CellStart.begin(), this->CellStart.end() - 1);
  for (std::size_t i = 0; i < mesh.Simplices.size(); ++i)
  {
    forEachCell(mesh.Simplices[i],
      [&](int cell) { this->CellTriangles[next[cell]++] = static_cast<std::uint32_t>(i); });
  }
}

int InsideTest::Cell(double y, double z) const
{
  const int iy = std::clamp(static_cast<int>((y - this->Y0) * this->InvCellY), 0, this->Ny - 1);
  const int iz = std::clamp(static_cast<int>((z - this->Z0) * this->InvCellZ), 0, this->Nz - 1);
  return iy * this->Nz + iz;
}

bool InsideTest::Contains(const Vec3& p) const
{
  const int cell = this->Cell(p[1], p[2]);
  int crossings = 0;
  for (std::uint64_t k = this->CellStart[cell]; k < this->CellStart[cell + 1]; ++k)
  {
    const auto& t = this->Mesh.Simplices[this->CellTriangles[k]];
    const Vec3& a = this->Mesh.Vertices[t[0]];
    const Vec3& b = this->Mesh.Vertices[t[1]];
    const Vec3& c = this->Mesh.Vertices[t[2]];
    // Barycentric weights of the point's shadow in the triangle's shadow.
    const double e1y = b[1] - a[1], e1z = b[2] - a[2];
    const double e2y = c[1] - a[1], e2z = c[2] - a[2];
    const double det = e1y * e2z - e1z * e2y;
    if (det == 0.0)
    {
      continue; // the triangle is parallel to the ray
    }
    const double qy = p[1] - a[1], qz = p[2] - a[2];
    const double u = (qy * e2z - qz * e2y) / det;
    const double v = (e1y * qz - e1z * qy) / det;
    if (u < 0.0 || v < 0.0 || u + v > 1.0)
    {
      continue;
    }
    const double x = a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]);
    crossings += x > p[0] ? 1 : 0;
  }
  return crossings % 2 == 1;
}
} // namespace bench
} // namespace gridfree
