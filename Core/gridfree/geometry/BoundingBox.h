// Axis-aligned bounding box in DIM dimensions (double precision).
//
// Used by the BVH builder (surface area heuristic, centroid binning) and to
// report the extent of a boundary. The empty box is [+inf, -inf] so that
// expanding it by any point yields that point, without special cases.
#ifndef GRIDFREE_GEOMETRY_BOUNDING_BOX_H
#define GRIDFREE_GEOMETRY_BOUNDING_BOX_H

#include <gridfree/math/Vector.h>

#include <limits>

namespace gridfree
{
template <int DIM>
struct BoundingBox
{
  Vec<DIM> Min = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
  Vec<DIM> Max = Vec<DIM>::Constant(-std::numeric_limits<double>::infinity());

  BoundingBox() = default;
  BoundingBox(const Vec<DIM>& lo, const Vec<DIM>& hi)
    : Min(lo)
    , Max(hi)
  {
  }

  /// True until at least one point was added (NaN-free inputs assumed).
  bool IsEmpty() const { return (this->Min.array() > this->Max.array()).any(); }

  void Expand(const Vec<DIM>& p)
  {
    this->Min = this->Min.cwiseMin(p);
    this->Max = this->Max.cwiseMax(p);
  }

  void Expand(const BoundingBox& other)
  {
    this->Min = this->Min.cwiseMin(other.Min);
    this->Max = this->Max.cwiseMax(other.Max);
  }

  /// Side lengths; zero for an empty box so that callers never see -inf.
  Vec<DIM> Extent() const
  {
    return this->IsEmpty() ? Vec<DIM>::Zero() : Vec<DIM>(this->Max - this->Min);
  }

  Vec<DIM> Center() const { return 0.5 * (this->Min + this->Max); }

  double Diagonal() const { return this->Extent().norm(); }

  /// Index of the longest side (first one on ties).
  int LongestAxis() const
  {
    int axis = 0;
    this->Extent().maxCoeff(&axis);
    return axis;
  }

  /// Half the surface area in 3D, half the perimeter in 2D. The surface area
  /// heuristic only compares ratios, so the constant factor is irrelevant.
  double HalfArea() const
  {
    const Vec<DIM> e = this->Extent();
    if constexpr (DIM == 2)
    {
      return e[0] + e[1];
    }
    else
    {
      return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
  }

  bool Contains(const Vec<DIM>& p) const
  {
    return (p.array() >= this->Min.array()).all() && (p.array() <= this->Max.array()).all();
  }

  /// Squared distance from p to the box (0 inside), inf for an empty box.
  double SquaredDistance(const Vec<DIM>& p) const
  {
    if (this->IsEmpty())
    {
      return std::numeric_limits<double>::infinity();
    }
    const Vec<DIM> gap = (this->Min - p).cwiseMax(p - this->Max).cwiseMax(Vec<DIM>::Zero());
    return gap.squaredNorm();
  }
};
} // namespace gridfree

#endif
