// The flat patches of a triangle mesh: triangles joined across shared edges
// when they lie in one plane with the same orientation. Walk on stars sizes
// its draws of flux points in the walker's own plane by the patch the walker
// stands on (ReflectingBoundarySampler::PlaneShare, Documentation/
// WalkOnStars.md §2): a cube's face is one patch, a finely tessellated
// sphere has a patch per triangle, and a polygon soup (no shared vertex
// indices) too.
#ifndef GRIDFREE_STARS_FLAT_PATCHES_H
#define GRIDFREE_STARS_FLAT_PATCHES_H

#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <vector>

namespace gridfree
{
// The area of the flat patch each triangle belongs to (its own area where
// no neighbour shares its plane). `areas` holds each triangle's area.
inline std::vector<double> FlatPatchAreas(const std::vector<Vec<3>>& vertices,
  const std::vector<std::array<std::int64_t, 3>>& triangles, const std::vector<double>& areas)
{
  const std::size_t n = triangles.size();
  std::vector<Vec<3>> normals(n, Vec<3>::Zero());
  double diagonal2 = 0.0;
  if (!vertices.empty())
  {
    Vec<3> lo = vertices[0], hi = vertices[0];
    for (const Vec<3>& v : vertices)
    {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    diagonal2 = (hi - lo).squaredNorm();
  }
  // The tolerance of walk on stars' own coplanarity test (its Offset).
  const double tolerance = 1e-9 * std::sqrt(diagonal2);
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto& t = triangles[i];
    const Vec<3> c = (vertices[static_cast<std::size_t>(t[1])] - vertices[static_cast<std::size_t>(t[0])])
                       .cross(vertices[static_cast<std::size_t>(t[2])] - vertices[static_cast<std::size_t>(t[0])]);
    const double length = c.norm();
    if (length > 0.0)
    {
      normals[i] = c / length;
    }
  }
  auto coplanar = [&](std::size_t a, std::size_t b) {
    return normals[a].squaredNorm() > 0.0 && normals[a].dot(normals[b]) >= 1.0 - 1e-12 &&
      std::abs((vertices[static_cast<std::size_t>(triangles[b][0])] -
                 vertices[static_cast<std::size_t>(triangles[a][0])])
                 .dot(normals[a])) <= tolerance;
  };

  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{ 0 });
  auto find = [&parent](std::size_t i) {
    while (parent[i] != i)
    {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };

  // Edges as (smaller vertex, larger vertex, triangle), sorted so that the
  // triangles sharing an edge sit side by side.
  std::vector<std::tuple<std::int64_t, std::int64_t, std::size_t>> edges;
  edges.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = triangles[i][k], b = triangles[i][(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b), i);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t e = 0; e < edges.size();)
  {
    std::size_t end = e + 1;
    while (end < edges.size() && std::get<0>(edges[end]) == std::get<0>(edges[e]) &&
      std::get<1>(edges[end]) == std::get<1>(edges[e]))
    {
      ++end;
    }
    for (std::size_t i = e; i < end; ++i)
    {
      for (std::size_t j = i + 1; j < end; ++j)
      {
        const std::size_t a = std::get<2>(edges[i]), b = std::get<2>(edges[j]);
        if (coplanar(a, b))
        {
          parent[find(a)] = find(b);
        }
      }
    }
    e = end;
  }

  std::vector<double> patch(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    patch[find(i)] += areas[i];
  }
  std::vector<double> result(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    result[i] = patch[find(i)];
  }
  return result;
}
} // namespace gridfree

#endif
