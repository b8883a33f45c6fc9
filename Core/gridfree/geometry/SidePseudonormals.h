// Which side of a mesh a point lies on, from its closest point: the sign of
// (x − y)·N, where y is the closest point and N the pseudonormal of the
// feature y lies on (Bærentzen & Aanæs 2005, "Signed distance computation
// using the angle weighted pseudonormal"):
// - inside a triangle or segment: its normal;
// - on a triangle's edge: the sum of the unit normals of the triangles that
//   share the edge;
// - on a vertex: the angle-weighted sum of the unit normals of the triangles
//   around it (3D), or the sum of the unit normals of its segments (2D).
// The primitive's own normal is not enough where the closest point is an
// edge or a vertex: past a sharp turn of a polyline, or a sharp crease of a
// surface, x − y can make an obtuse angle with it on the side it points to.
// For a consistently oriented closed mesh (or, in 2D, any consistently
// oriented polyline) the pseudonormal's sign is exact.
//
// Two-sided boundary values (diffusion curves and surfaces, paper Sec. 6.4)
// pick their side this way.
#ifndef GRIDFREE_GEOMETRY_SIDE_PSEUDONORMALS_H
#define GRIDFREE_GEOMETRY_SIDE_PSEUDONORMALS_H

#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

namespace gridfree
{
template <int DIM>
class SidePseudonormals
{
public:
  using Primitive = std::array<std::int64_t, DIM>;

  // O(n log n) in the number of primitives (3D edges are matched by sorting).
  void Build(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives)
  {
    this->Built = true;
    this->VertexNormals.assign(vertices.size(), Vec<DIM>::Zero());
    for (const Primitive& p : primitives)
    {
      const Vec<DIM> n = SimplexUnitNormal<DIM>(vertices, p);
      for (int k = 0; k < DIM; ++k)
      {
        this->VertexNormals[static_cast<std::size_t>(p[k])] += AngleAt(vertices, p, k) * n;
      }
    }
    if constexpr (DIM == 3)
    {
      this->BuildEdgeNormals(vertices, primitives);
    }
  }

  bool Empty() const { return !this->Built; }

  // The pseudonormal at the point of `primitive` with barycentric weights
  // `w` (as ClosestPointResult gives them: a weight is exactly 0 when the
  // point lies on the opposite edge, exactly 1 at a vertex), on the mesh it
  // was built from. Not unit length; zero where no side is defined.
  Vec<DIM> At(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives,
    std::int64_t primitive, const Vec<DIM>& w) const
  {
    const Primitive& p = primitives[static_cast<std::size_t>(primitive)];
    int zeros = 0, nonzero = 0, zero = 0;
    for (int k = 0; k < DIM; ++k)
    {
      if (w[k] == 0.0)
      {
        ++zeros;
        zero = k;
      }
      else
      {
        nonzero = k;
      }
    }
    if (zeros == DIM - 1)
    {
      return this->VertexNormals[static_cast<std::size_t>(p[nonzero])];
    }
    if constexpr (DIM == 3)
    {
      if (zeros == 1)
      {
        return this->EdgeNormals[static_cast<std::size_t>(primitive) * 3 + zero];
      }
    }
    return SimplexUnitNormal<DIM>(vertices, p);
  }

private:
  // The weight of a primitive's normal at its vertex k: 1 for a segment, the
  // triangle's angle at the vertex in 3D.
  static double AngleAt(const std::vector<Vec<DIM>>& v, const Primitive& p, int k)
  {
    if constexpr (DIM == 2)
    {
      (void)v;
      (void)p;
      (void)k;
      return 1.0;
    }
    else
    {
      const Vec3& a = v[static_cast<std::size_t>(p[k])];
      const Vec3 e1 = v[static_cast<std::size_t>(p[(k + 1) % 3])] - a;
      const Vec3 e2 = v[static_cast<std::size_t>(p[(k + 2) % 3])] - a;
      // atan2 of |cross| and dot is accurate for tiny and flat angles alike.
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      return std::isfinite(angle) ? angle : 0.0;
    }
  }

  // For each triangle and edge k (the edge opposite vertex k), the sum of the
  // unit normals of all triangles sharing that undirected edge.
  void BuildEdgeNormals(const std::vector<Vec3>& vertices, const std::vector<Primitive>& primitives)
  {
    using Key = std::tuple<std::int64_t, std::int64_t, std::size_t>;
    std::vector<Key> edges;
    edges.reserve(3 * primitives.size());
    for (std::size_t t = 0; t < primitives.size(); ++t)
    {
      const Primitive& p = primitives[t];
      for (int k = 0; k < 3; ++k)
      {
        const std::int64_t a = p[(k + 1) % 3], b = p[(k + 2) % 3];
        edges.emplace_back(std::min(a, b), std::max(a, b), 3 * t + static_cast<std::size_t>(k));
      }
    }
    std::sort(edges.begin(), edges.end());
    this->EdgeNormals.assign(3 * primitives.size(), Vec3::Zero());
    for (std::size_t first = 0; first < edges.size();)
    {
      std::size_t last = first;
      Vec3 sum = Vec3::Zero();
      while (last < edges.size() && std::get<0>(edges[last]) == std::get<0>(edges[first]) &&
        std::get<1>(edges[last]) == std::get<1>(edges[first]))
      {
        sum += SimplexUnitNormal<3>(vertices, primitives[std::get<2>(edges[last]) / 3]);
        ++last;
      }
      for (std::size_t e = first; e < last; ++e)
      {
        this->EdgeNormals[std::get<2>(edges[e])] = sum;
      }
      first = last;
    }
  }

  bool Built = false;
  std::vector<Vec<DIM>> VertexNormals;
  std::vector<Vec<DIM>> EdgeNormals;
};
} // namespace gridfree

#endif
