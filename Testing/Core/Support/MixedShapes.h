// Mixed-boundary problems on block shapes (BlockShapes.h) for the walk-on-
// stars tests and benchmark: the shapes, points inside them, and a
// MixedBoundary whose primitives take Dirichlet, Neumann or Robin conditions
// by a rule on their centroids, with data from a closed-form solution.
#ifndef GRIDFREE_TESTING_MIXEDSHAPES_H
#define GRIDFREE_TESTING_MIXEDSHAPES_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/stars/MixedBoundary.h>

#include "BlockShapes.h"

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <set>
#include <vector>

namespace gridfree
{
namespace testing
{
template <int DIM>
using Gradient = std::function<Vec<DIM>(const Vec<DIM>&)>;

// A block shape, its cells (to place points inside) and cell size.
template <int DIM>
struct Shape
{
  std::vector<Cell<DIM>> Cells;
  int Pieces;
  double Size;
  SimplexMesh<DIM> Mesh;
};

template <int DIM>
Shape<DIM> MakeShape(std::vector<Cell<DIM>> cells, int pieces, double size)
{
  Shape<DIM> s{ std::move(cells), pieces, size, {} };
  s.Mesh = MakeBlockShape<DIM>(s.Cells, pieces, size);
  return s;
}

// U in 2D (three cells wide, two high, the middle top cell missing): two
// reflex corners, at (1, 1) and (2, 1) times the cell size.
inline Shape<2> UShape() { return MakeShape<2>({ { 0, 0 }, { 1, 0 }, { 2, 0 }, { 0, 1 }, { 2, 1 } }, 24, 0.5); }

// L prism in 3D: the reflex edge along z at x = y = 1 (cell units).
inline Shape<3> LPrism()
{
  return MakeShape<3>({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, 8, 0.6);
}

// The L prism's closed-form solution u = e^{x/2} cos(0.3 y) sin(0.4 z) +
// x y − z, its gradient, and the faces the tests make Dirichlet (bottom,
// z = 0, and back, x = 0).
inline double LPrismSolution(const Vec3& x)
{
  return std::exp(0.5 * x[0]) * std::cos(0.3 * x[1]) * std::sin(0.4 * x[2]) + x[0] * x[1] - x[2];
}
inline Vec3 LPrismGradient(const Vec3& x)
{
  const double e = std::exp(0.5 * x[0]);
  return Vec3(0.5 * e * std::cos(0.3 * x[1]) * std::sin(0.4 * x[2]) + x[1],
    -0.3 * e * std::sin(0.3 * x[1]) * std::sin(0.4 * x[2]) + x[0],
    0.4 * e * std::cos(0.3 * x[1]) * std::cos(0.4 * x[2]) - 1.0);
}
inline bool LPrismDirichlet(const Vec3& c)
{
  return c[2] < 1e-9 || c[0] < 1e-9;
}

// Random points inside the shape's cells, at least a tenth of a cell from
// its boundary. Nearer the Dirichlet part, most walks end at once and a rare
// one that wanders off gathers many flux terms: the walks' values are so
// skewed that 1,024 walks can underestimate the standard error fivefold (a
// point 0.015 from the U's bottom side: 0.007 from 1,024 walks, 0.0088·4
// from 16,384, |z| = 7.5 with the former, 1.1 with the latter).
template <int DIM>
std::vector<Vec<DIM>> PointsInside(const Shape<DIM>& shape, int count, std::uint32_t seed)
{
  const std::set<Cell<DIM>> cells(shape.Cells.begin(), shape.Cells.end());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<DIM>> points;
  while (static_cast<int>(points.size()) < count)
  {
    const Cell<DIM>& c = shape.Cells[rng() % shape.Cells.size()];
    Vec<DIM> p;
    bool inside = true;
    for (int k = 0; k < DIM; ++k)
    {
      const double t = u(rng);
      p[k] = (c[k] + t) * shape.Size;
      // Near a cell side that is on the boundary: keep 0.1 cells away.
      for (int side : { -1, 1 })
      {
        Cell<DIM> n = c;
        n[k] += side;
        const double gap = side < 0 ? t : 1.0 - t;
        if (!cells.count(n) && gap < 0.1)
        {
          inside = false;
        }
      }
    }
    if (inside)
    {
      points.push_back(p);
    }
  }
  return points;
}

// The Robin coefficient μ of a primitive from its centroid (0: Neumann).
template <int DIM>
using RobinRule = std::function<double(const Vec<DIM>&)>;

// The mixed boundary of a shape: primitives for which `isDirichlet(centroid)`
// holds take g = u, the others h = ∂u/∂n + μu with μ = robin(centroid) (n
// the shape's outward normal); `exterior` solves outside the shape, where
// the Robin primitives take ∂u/∂n along the opposite normal (out of the
// exterior domain) and the Neumann ones keep the shape's.
template <int DIM>
MixedBoundary<DIM> MakeMixed(const SimplexMesh<DIM>& mesh,
  const std::function<bool(const Vec<DIM>&)>& isDirichlet, const Field<DIM>& u,
  const Gradient<DIM>& grad, bool silhouettes = true, double fluxScale = 1.0,
  const RobinRule<DIM>& robin = nullptr, bool exterior = false)
{
  std::vector<BoundaryCondition> conditions;
  std::vector<double> mu;
  for (const auto& p : mesh.Simplices)
  {
    Vec<DIM> c = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      c += mesh.Vertices[p[k]] / DIM;
    }
    mu.push_back(robin ? robin(c) : 0.0);
    conditions.push_back(isDirichlet(c) ? BoundaryCondition::Dirichlet
        : mu.back() > 0.0               ? BoundaryCondition::Robin
                                        : BoundaryCondition::Neumann);
  }
  const std::vector<std::array<std::int64_t, DIM>> prims(mesh.Simplices.begin(), mesh.Simplices.end());
  MeshPart<DIM> d, r;
  SplitByCondition<DIM>(mesh.Vertices, prims, conditions, d, r);
  std::shared_ptr<Boundary<DIM>> dirichlet, reflecting;
  if (!d.Primitives.empty())
  {
    dirichlet = std::make_shared<Boundary<DIM>>();
    dirichlet->SetMesh(d.Vertices, d.Primitives,
      std::make_shared<CallableBoundaryValues<DIM>>(
        [u](const Vec<DIM>& z, std::int64_t, double* out) { out[0] = u(z); }, 1));
  }
  std::vector<double> partMu;
  if (!r.Primitives.empty())
  {
    std::vector<Vec<DIM>> normals;
    for (std::size_t i = 0; i < r.Primitives.size(); ++i)
    {
      normals.push_back(OutwardUnitNormal<DIM>(r.Vertices, r.Primitives[i]));
      partMu.push_back(mu[static_cast<std::size_t>(r.Original[i])]);
    }
    reflecting = std::make_shared<Boundary<DIM>>();
    reflecting->SetMesh(r.Vertices, r.Primitives,
      std::make_shared<CallableBoundaryValues<DIM>>(
        [u, grad, normals, partMu, fluxScale, exterior](const Vec<DIM>& z, std::int64_t prim, double* out) {
          const std::size_t i = static_cast<std::size_t>(prim);
          // Outside, a Robin condition holds along the exterior domain's
          // own normal (MixedBoundary::Set), a Neumann flux along the mesh's.
          const double along = exterior && partMu[i] > 0.0 ? -1.0 : 1.0;
          out[0] = fluxScale * (along * grad(z).dot(normals[i]) + partMu[i] * u(z));
        },
        1));
  }
  MixedBoundary<DIM> mixed;
  mixed.Set(dirichlet, reflecting, robin ? partMu : std::vector<double>(), silhouettes, {},
    exterior);
  return mixed;
}

} // namespace testing
} // namespace gridfree

#endif
