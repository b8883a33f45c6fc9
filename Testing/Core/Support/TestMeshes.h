// Boundary meshes with known geometry for the statistical tests: spheres and
// cubes in 3D, circles and squares in 2D, as vertex + simplex lists.
#ifndef GRIDFREE_TESTING_TESTMESHES_H
#define GRIDFREE_TESTING_TESTMESHES_H

#include <gridfree/math/Vector.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

namespace gridfree
{
namespace testing
{
// A closed-form function of the position (an exact solution, boundary data).
template <int DIM>
using Field = std::function<double(const Vec<DIM>&)>;

template <int DIM>
struct SimplexMesh
{
  std::vector<Vec<DIM>> Vertices;
  std::vector<std::array<std::int64_t, DIM>> Simplices;
};

// Icosahedron subdivided `levels` times, projected on the sphere: 20 * 4^levels triangles.
inline SimplexMesh<3> MakeIcosphere(int levels, double radius = 1.0, Vec3 center = Vec3::Zero())
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 }, { 0, -1, t },
    { 0, 1, t }, { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 }, { -t, 0, -1 },
    { -t, 0, 1 } };
  for (Vec3& p : v)
  {
    p.normalize();
  }
  std::vector<std::array<std::int64_t, 3>> f = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 },
    { 0, 7, 10 }, { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 },
    { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 },
    { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  for (int level = 0; level < levels; ++level)
  {
    std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> midpoints;
    auto midpoint = [&](std::int64_t a, std::int64_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoints.find(key);
      if (it != midpoints.end())
      {
        return it->second;
      }
      v.push_back((v[a] + v[b]).normalized());
      const std::int64_t id = static_cast<std::int64_t>(v.size()) - 1;
      midpoints[key] = id;
      return id;
    };
    std::vector<std::array<std::int64_t, 3>> next;
    next.reserve(f.size() * 4);
    for (const auto& tri : f)
    {
      const std::int64_t a = midpoint(tri[0], tri[1]);
      const std::int64_t b = midpoint(tri[1], tri[2]);
      const std::int64_t c = midpoint(tri[2], tri[0]);
      next.push_back({ tri[0], a, c });
      next.push_back({ tri[1], b, a });
      next.push_back({ tri[2], c, b });
      next.push_back({ a, b, c });
    }
    f.swap(next);
  }
  SimplexMesh<3> mesh;
  for (const Vec3& p : v)
  {
    mesh.Vertices.push_back(center + radius * p);
  }
  mesh.Simplices = std::move(f);
  return mesh;
}

// Surface of the cube [-h, h]^3, each face an n x n grid of quads split in two.
inline SimplexMesh<3> MakeCube(int n, double h = 1.0)
{
  SimplexMesh<3> mesh;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = -1; side <= 1; side += 2)
    {
      const std::int64_t base = static_cast<std::int64_t>(mesh.Vertices.size());
      for (int j = 0; j <= n; ++j)
      {
        for (int i = 0; i <= n; ++i)
        {
          Vec3 p;
          p[axis] = side * h;
          p[(axis + 1) % 3] = -h + 2.0 * h * i / n;
          p[(axis + 2) % 3] = -h + 2.0 * h * j / n;
          mesh.Vertices.push_back(p);
        }
      }
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const std::int64_t a = base + j * (n + 1) + i;
          mesh.Simplices.push_back({ a, a + 1, a + n + 2 });
          mesh.Simplices.push_back({ a, a + n + 2, a + n + 1 });
        }
      }
    }
  }
  return mesh;
}

// Closed polygon approximating a circle with n segments.
inline SimplexMesh<2> MakeCircle(int n, double radius = 1.0, Vec2 center = Vec2::Zero())
{
  SimplexMesh<2> mesh;
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * M_PI * i / n;
    mesh.Vertices.push_back(center + radius * Vec2(std::cos(a), std::sin(a)));
    mesh.Simplices.push_back({ i, (i + 1) % n });
  }
  return mesh;
}

// Boundary of the square [-h, h]^2 with n segments per side.
inline SimplexMesh<2> MakeSquare(int n, double h = 1.0)
{
  SimplexMesh<2> mesh;
  const Vec2 corners[4] = { { -h, -h }, { h, -h }, { h, h }, { -h, h } };
  for (int side = 0; side < 4; ++side)
  {
    for (int i = 0; i < n; ++i)
    {
      const double t = double(i) / n;
      mesh.Vertices.push_back((1 - t) * corners[side] + t * corners[(side + 1) % 4]);
    }
  }
  const std::int64_t count = static_cast<std::int64_t>(mesh.Vertices.size());
  for (std::int64_t i = 0; i < count; ++i)
  {
    mesh.Simplices.push_back({ i, (i + 1) % count });
  }
  return mesh;
}
} // namespace testing
} // namespace gridfree

#endif
