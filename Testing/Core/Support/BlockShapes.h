// Closed, consistently oriented boundaries of unions of unit squares (2D) or
// cubes (3D): L, U and comb shapes with reflex corners and edges, for the
// walk-on-stars tests. Each cell side not shared with another cell of the
// set is cut into n × n pieces (n in 2D), oriented with the domain on the
// left of every segment (2D) or with outward right-handed normals (3D),
// and vertices are shared, so the mesh is watertight.
#ifndef GRIDFREE_TESTING_BLOCKSHAPES_H
#define GRIDFREE_TESTING_BLOCKSHAPES_H

#include "TestMeshes.h"

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

namespace gridfree
{
namespace testing
{
template <int DIM>
using Cell = std::array<int, DIM>;

// The boundary of the union of `cells`, each side cut n times, scaled by
// `size` per cell and moved by `origin`.
template <int DIM>
SimplexMesh<DIM> MakeBlockShape(
  const std::vector<Cell<DIM>>& cells, int n, double size = 1.0, Vec<DIM> origin = Vec<DIM>::Zero())
{
  const std::set<Cell<DIM>> filled(cells.begin(), cells.end());
  SimplexMesh<DIM> mesh;
  std::map<std::array<int, DIM>, std::int64_t> index; // lattice point (in 1/n units) → vertex
  auto vertex = [&](const std::array<int, DIM>& q) {
    auto found = index.find(q);
    if (found != index.end())
    {
      return found->second;
    }
    Vec<DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = origin[k] + size * q[k] / static_cast<double>(n);
    }
    const std::int64_t id = static_cast<std::int64_t>(mesh.Vertices.size());
    mesh.Vertices.push_back(p);
    index.emplace(q, id);
    return id;
  };
  for (const Cell<DIM>& c : filled)
  {
    for (int axis = 0; axis < DIM; ++axis)
    {
      for (int sign : { -1, 1 })
      {
        Cell<DIM> neighbour = c;
        neighbour[axis] += sign;
        if (filled.count(neighbour))
        {
          continue;
        }
        std::array<int, DIM> base;
        for (int k = 0; k < DIM; ++k)
        {
          base[k] = c[k] * n;
        }
        base[axis] += sign > 0 ? n : 0;
        if constexpr (DIM == 2)
        {
          // Counter-clockwise around the cell: +x side runs +y, −x side −y,
          // +y side runs −x, −y side +x.
          const int t = 1 - axis;
          const int direction = (axis == 0) == (sign > 0) ? 1 : -1;
          for (int i = 0; i < n; ++i)
          {
            std::array<int, DIM> a = base, b = base;
            a[t] += direction > 0 ? i : n - i;
            b[t] += direction > 0 ? i + 1 : n - i - 1;
            mesh.Simplices.push_back({ vertex(a), vertex(b) });
          }
        }
        else
        {
          // e_u × e_w = e_axis for (u, w) cyclic after axis.
          const int u = (axis + 1) % 3, w = (axis + 2) % 3;
          for (int i = 0; i < n; ++i)
          {
            for (int j = 0; j < n; ++j)
            {
              auto at = [&](int di, int dj) {
                std::array<int, DIM> q = base;
                q[u] += i + di;
                q[w] += j + dj;
                return vertex(q);
              };
              const std::int64_t p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
              if (sign > 0)
              {
                mesh.Simplices.push_back({ p00, p10, p11 });
                mesh.Simplices.push_back({ p00, p11, p01 });
              }
              else
              {
                mesh.Simplices.push_back({ p00, p11, p10 });
                mesh.Simplices.push_back({ p00, p01, p11 });
              }
            }
          }
        }
      }
    }
  }
  return mesh;
}
} // namespace testing
} // namespace gridfree

#endif
