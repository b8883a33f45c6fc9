// Random boundary soups for the BVH tests: primitives of widely varying
// sizes, some sharing vertices like a mesh, mixed with degenerate and
// duplicated ones (zero length or area, identical or collinear vertices);
// and the float group of four primitives the leaf filter tests read.
#ifndef GRIDFREE_TESTING_RANDOMSOUPS_H
#define GRIDFREE_TESTING_RANDOMSOUPS_H

#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/BvhLeafFilter.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace gridfree
{
namespace testing
{
template <int DIM>
struct Soup
{
  std::vector<Vec<DIM>> Vertices;
  std::vector<typename Bvh<DIM>::Primitive> Primitives;
};

//------------------------------------------------------------------------------
// The float copies of four primitives (prims[lane][vertex]) relative to a
// hierarchy centre, rounded to nearest as Bvh.h stores a leaf group.
template <int DIM, class Prims>
gridfree::detail::BvhLeafGroup<DIM> LeafGroupOf(const Prims& prims, const Vec<DIM>& center)
{
  gridfree::detail::BvhLeafGroup<DIM> group;
  for (int lane = 0; lane < 4; ++lane)
  {
    for (int v = 0; v < DIM; ++v)
    {
      for (int k = 0; k < DIM; ++k)
      {
        group.V[v][k][lane] = static_cast<float>(prims[lane][v][k] - center[k]);
      }
    }
  }
  return group;
}

//------------------------------------------------------------------------------
// Random soups: mostly regular primitives of widely varying sizes, some
// sharing vertices like a mesh, mixed with degenerate and duplicated ones.
template <int DIM>
Soup<DIM> MakeSoup(int n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto uniformPoint = [&]()
  {
    Vec<DIM> p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = u01(rng);
    }
    return p;
  };
  auto pick = [&](std::size_t count) { return static_cast<std::int64_t>(rng() % count); };

  Soup<DIM> soup;
  auto addVertex = [&](const Vec<DIM>& v)
  {
    soup.Vertices.push_back(v);
    return static_cast<std::int64_t>(soup.Vertices.size() - 1);
  };
  for (int i = 0; i < n; ++i)
  {
    typename Bvh<DIM>::Primitive prim;
    const int kind = (i == 0) ? 9 : static_cast<int>(rng() % 12);
    const Vec<DIM> center = uniformPoint();
    const double size = std::pow(10.0, -3.0 + 2.5 * u01(rng));
    auto nearby = [&]()
    { return Vec<DIM>(center + size * (2.0 * uniformPoint() - Vec<DIM>::Ones())); };
    switch (kind)
    {
      case 0: // repeated vertex index: zero length / zero area
        prim[0] = addVertex(nearby());
        for (int k = 1; k < DIM; ++k)
        {
          prim[k] = (k == DIM - 1 && DIM == 3) ? addVertex(nearby()) : prim[0];
        }
        break;
      case 1: // all vertices identical (distinct indices, same coordinates)
      {
        const Vec<DIM> v = nearby();
        for (int k = 0; k < DIM; ++k)
        {
          prim[k] = addVertex(v);
        }
        break;
      }
      case 2: // collinear: exactly (axis-aligned grid) or up to rounding
      {
        const Vec<DIM> a = nearby();
        Vec<DIM> d = nearby() - a;
        if (rng() % 2)
        {
          d = Vec<DIM>::Zero();
          d[rng() % DIM] = 0.25 * size;
        }
        const double t = (rng() % 2) ? 2.0 : 0.3; // third vertex outside or inside
        prim[0] = addVertex(a);
        prim[1] = addVertex(a + d);
        if constexpr (DIM == 3)
        {
          prim[2] = addVertex(a + t * d);
        }
        break;
      }
      case 3: // duplicate of an earlier primitive, possibly reordered
        prim = soup.Primitives[pick(soup.Primitives.size())];
        if (rng() % 2)
        {
          std::reverse(prim.begin(), prim.end());
        }
        break;
      case 4: // duplicate coordinates under new vertex indices
      {
        const auto& other = soup.Primitives[pick(soup.Primitives.size())];
        for (int k = 0; k < DIM; ++k)
        {
          prim[k] = addVertex(Vec<DIM>(soup.Vertices[other[k]]));
        }
        break;
      }
      case 5: // shares vertices with the mesh so far
        for (int k = 0; k < DIM; ++k)
        {
          prim[k] = (rng() % 2) ? pick(soup.Vertices.size()) : addVertex(nearby());
        }
        break;
      default: // regular primitive
        for (int k = 0; k < DIM; ++k)
        {
          prim[k] = addVertex(nearby());
        }
        break;
    }
    soup.Primitives.push_back(prim);
  }
  return soup;
}
//------------------------------------------------------------------------------
// Brute-force reference: the same kernels, minimized over every primitive.
template <int DIM>
PrimitiveClosestPoint<DIM, DIM> KernelClosest(
  const Soup<DIM>& soup, std::size_t p, const Vec<DIM>& x)
{
  const auto& prim = soup.Primitives[p];
  if constexpr (DIM == 2)
  {
    return ClosestPointOnSegment<2>(x, soup.Vertices[prim[0]], soup.Vertices[prim[1]]);
  }
  else
  {
    return ClosestPointOnTriangle(
      x, soup.Vertices[prim[0]], soup.Vertices[prim[1]], soup.Vertices[prim[2]]);
  }
}

template <int DIM>
double BruteForceSquaredDistance(const Soup<DIM>& soup, const Vec<DIM>& x)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < soup.Primitives.size(); ++p)
  {
    best = std::min(best, KernelClosest(soup, p, x).squaredDistance);
  }
  return best;
}
} // namespace testing
} // namespace gridfree

#endif
