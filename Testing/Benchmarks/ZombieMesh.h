// Conversions between the benchmarks' plain types and zombie's float
// vectors, and the split of a triangle list into compact parts, shared by
// the two files that include the authors' headers (ZombieStarsRows.cxx,
// ZombieCacheRows.cxx). Include it only after zombie's headers.
#ifndef GRIDFREE_BENCHMARKS_ZOMBIEMESH_H
#define GRIDFREE_BENCHMARKS_ZOMBIEMESH_H

#include <array>
#include <chrono>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
namespace bench
{
namespace zombie_mesh
{
using Point = std::array<double, 3>;

inline zombie::Vector3 ToFloat(const Point& p)
{
  return zombie::Vector3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
}

inline Point ToDouble(const zombie::Vector3& p)
{
  return Point{ p[0], p[1], p[2] };
}

inline double SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The primitives of one part with their own compact vertex list.
struct Part
{
  std::vector<zombie::Vector3> Positions;
  std::vector<zombie::Vector3i> Indices;
};

// Appends a triangle of the full mesh to `part`; `map` takes a full-mesh
// vertex to the part's (−1: not yet in it).
inline void Add(Part& part, std::vector<int>& map, const std::vector<Point>& vertices,
  const std::array<std::int64_t, 3>& triangle)
{
  zombie::Vector3i indices;
  for (int k = 0; k < 3; ++k)
  {
    int& m = map[static_cast<std::size_t>(triangle[k])];
    if (m < 0)
    {
      m = static_cast<int>(part.Positions.size());
      part.Positions.push_back(ToFloat(vertices[static_cast<std::size_t>(triangle[k])]));
    }
    indices[k] = m;
  }
  part.Indices.push_back(indices);
}

// The bounding box of the vertices, in float.
inline void Bounds(const std::vector<Point>& vertices, zombie::Vector3& lo, zombie::Vector3& hi)
{
  lo = zombie::Vector3::Constant(std::numeric_limits<float>::max());
  hi = -lo;
  for (const Point& v : vertices)
  {
    lo = lo.cwiseMin(ToFloat(v));
    hi = hi.cwiseMax(ToFloat(v));
  }
}
// The absorbing part's hierarchy (fcpw) in `handler`, and the queries
// that use it (the handler must outlive them).
inline void UseDirichletPart(zombie::FcpwDirichletBoundaryHandler<3>& handler, const Part& part,
  zombie::GeometricQueries<3>& queries)
{
  handler.buildAccelerationStructure(part.Positions, part.Indices, true, false, false);
  zombie::populateGeometricQueriesForDirichletBoundary<3>(handler, queries);
}
} // namespace zombie_mesh
} // namespace bench
} // namespace gridfree

#endif
