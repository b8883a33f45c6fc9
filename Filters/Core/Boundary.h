// A Dirichlet boundary: simplices (segments in 2D, triangles in 3D) with the
// values prescribed on them, plus the BVH that answers distance and closest
// point queries. This is the only thing a walk needs to know about geometry.
#ifndef GRIDFREE_CORE_BOUNDARY_H
#define GRIDFREE_CORE_BOUNDARY_H

#include "Geometry/Bvh.h"
#include "Vector.h"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace gridfree
{
// Where boundary values live: on vertices (interpolated with the closest
// point's barycentric weights) or on primitives (constant per primitive).
enum class ValueAssociation
{
  Points,
  Cells
};

template <int DIM>
class Boundary
{
public:
  using Primitive = typename Bvh<DIM>::Primitive;

  // vertices and primitives describe the geometry. values holds
  // `components` numbers per vertex (Points) or per primitive (Cells).
  void Set(std::vector<Vec<DIM>> vertices, std::vector<Primitive> primitives,
    ValueAssociation association, int components, std::vector<double> values)
  {
    const std::size_t tuples =
      association == ValueAssociation::Points ? vertices.size() : primitives.size();
    if (components < 1 || values.size() != tuples * static_cast<std::size_t>(components))
    {
      throw std::invalid_argument("boundary values: expected " + std::to_string(tuples) + " x " +
        std::to_string(components) + " numbers, got " + std::to_string(values.size()));
    }
    for (const Primitive& p : primitives)
    {
      for (int k = 0; k < DIM; ++k)
      {
        if (p[k] < 0 || static_cast<std::size_t>(p[k]) >= vertices.size())
        {
          throw std::invalid_argument("boundary primitive refers to a missing vertex");
        }
      }
    }
    this->Vertices = std::move(vertices);
    this->Primitives = std::move(primitives);
    this->Association = association;
    this->NumberOfComponents = components;
    this->Values = std::move(values);
    this->ComputeBounds();
    this->Tree.Build(this->Vertices, this->Primitives);
  }

  bool Empty() const { return this->Primitives.empty(); }
  int Components() const { return this->NumberOfComponents; }
  std::size_t NumberOfPrimitives() const { return this->Primitives.size(); }
  const Vec<DIM>& BoundsMin() const { return this->Min; }
  const Vec<DIM>& BoundsMax() const { return this->Max; }
  Vec<DIM> Center() const { return 0.5 * (this->Min + this->Max); }
  double Diagonal() const { return (this->Max - this->Min).norm(); }

  // Radius of the largest empty ball around x (paper Sec. 5.1).
  double Distance(const Vec<DIM>& x) const { return this->Tree.Distance(x); }

  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const
  {
    return this->Tree.ClosestPoint(x);
  }

  // Unit normal of a primitive (segment: its left normal; triangle: the
  // right-handed normal of its vertex order); zero for a degenerate one.
  // Only used to pick a side for points exactly on the boundary.
  Vec<DIM> PrimitiveNormal(std::int64_t primitive) const
  {
    const Primitive& p = this->Primitives[static_cast<std::size_t>(primitive)];
    Vec<DIM> n = Vec<DIM>::Zero();
    if constexpr (DIM == 2)
    {
      const Vec<DIM> e = this->Vertices[p[1]] - this->Vertices[p[0]];
      n << -e[1], e[0];
    }
    else
    {
      n = (this->Vertices[p[1]] - this->Vertices[p[0]])
            .cross(this->Vertices[p[2]] - this->Vertices[p[0]]);
    }
    const double length = n.norm();
    return length > 0.0 ? Vec<DIM>(n / length) : Vec<DIM>::Zero();
  }

  // Boundary value g at a closest point: barycentric interpolation of point
  // data, or the primitive's own value for cell data. Writes Components().
  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const
  {
    const int nc = this->NumberOfComponents;
    if (this->Association == ValueAssociation::Cells)
    {
      const double* v = &this->Values[static_cast<std::size_t>(hit.primitive) * nc];
      for (int c = 0; c < nc; ++c)
      {
        out[c] = v[c];
      }
      return;
    }
    const Primitive& p = this->Primitives[static_cast<std::size_t>(hit.primitive)];
    for (int c = 0; c < nc; ++c)
    {
      out[c] = 0.0;
    }
    for (int k = 0; k < DIM; ++k)
    {
      const double w = hit.barycentric[k];
      const double* v = &this->Values[static_cast<std::size_t>(p[k]) * nc];
      for (int c = 0; c < nc; ++c)
      {
        out[c] += w * v[c];
      }
    }
  }

private:
  void ComputeBounds()
  {
    const double inf = std::numeric_limits<double>::infinity();
    this->Min.setConstant(inf);
    this->Max.setConstant(-inf);
    for (const Primitive& p : this->Primitives)
    {
      for (int k = 0; k < DIM; ++k)
      {
        this->Min = this->Min.cwiseMin(this->Vertices[p[k]]);
        this->Max = this->Max.cwiseMax(this->Vertices[p[k]]);
      }
    }
    if (this->Primitives.empty())
    {
      this->Min.setZero();
      this->Max.setZero();
    }
  }

  std::vector<Vec<DIM>> Vertices;
  std::vector<Primitive> Primitives;
  ValueAssociation Association = ValueAssociation::Points;
  int NumberOfComponents = 1;
  std::vector<double> Values;
  Vec<DIM> Min = Vec<DIM>::Zero();
  Vec<DIM> Max = Vec<DIM>::Zero();
  Bvh<DIM> Tree;
};
} // namespace gridfree

#endif
