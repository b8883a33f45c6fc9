// Distance lower bounds cached on a coarse grid, so that walk steps far from
// the boundary skip the hierarchy (issue: "a conservative distance lower bound
// cached on a coarse grid, so deep interior steps skip the BVH").
//
// Each grid vertex v stores l_v, a lower bound of the distance d(v) to the
// boundary that is within a known factor of it: d(v) / (1 + r) <= l_v <= d(v).
// The distance is 1-Lipschitz, so for any x in a cell with corners v
//
//   L(x) = max_v (l_v − |x − v|)  <=  d(x)  <=  min_v ((1 + r) l_v + |x − v|) = U(x).
//
// L(x) is a radius of an empty ball around x whatever the cell size: walk on
// spheres keeps its expectation on any ball inside the domain (paper Sec. 2.2),
// so a step may use it. It is used only when it is not much smaller than the
// distance, L(x) >= U(x) / (1 + accept), because smaller balls mean more
// steps; nearer the boundary the test fails and the walk asks the hierarchy.
// A grid step costs a few dozen nanoseconds (one cell's corners, which a walk
// keeps touching), against about a microsecond for a query of a large mesh.
//
// The values are a pure function of the geometry, filled once when the
// boundary is set: which steps use the grid, and so every walk, is the same
// whatever the number of threads.
#ifndef GRIDFREE_GEOMETRY_DISTANCE_BOUND_GRID_H
#define GRIDFREE_GEOMETRY_DISTANCE_BOUND_GRID_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/math/Vector.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
template <int DIM>
class DistanceBoundGrid
{
public:
  /// Fills the grid over `box` (grown by one cell on each side), with about
  /// `vertices` vertices in cubic cells (at least 2 cells per side, at most
  /// 512 along the longest). `lowerBound(x, hint)` returns l with
  /// d(x) / (1 + relaxation) <= l <= d(x); it is called once per vertex, row
  /// by row (a row's calls in order, so it may carry state along the row in
  /// `hint`; rows may run in parallel). An empty or non-finite box gives an
  /// empty grid, which answers no query.
  ///
  /// With `signedValues`, lowerBound returns a signed distance s instead,
  /// |s| within the same factor of the distance and of the side's sign
  /// (negative inside), and Range() can tell the side of nearby points.
  template <typename Hint, typename LowerBound>
  void Build(const BoundingBox<DIM>& box, std::size_t vertices, double relaxation,
    LowerBound&& lowerBound, bool signedValues = false)
  {
    *this = DistanceBoundGrid();
    const Vec<DIM> extent = box.Extent();
    const double longest = extent.maxCoeff();
    if (box.IsEmpty() || !box.Min.allFinite() || !box.Max.allFinite() || !(longest > 0.0) ||
      !std::isfinite(longest) || vertices == 0 || !(relaxation >= 0.0))
    {
      return;
    }
    // Cells along the longest side so that the whole grid holds about the
    // requested number of vertices (thin boxes get more along their length).
    double volume = 1.0;
    for (int k = 0; k < DIM; ++k)
    {
      volume *= std::max(extent[k], 1e-3 * longest) / longest;
    }
    const double perSide = std::pow(static_cast<double>(vertices) / volume, 1.0 / DIM);
    const int cellsLongest = std::max(2, std::min(512, static_cast<int>(perSide)));
    this->Cell = longest / cellsLongest;
    for (int k = 0; k < DIM; ++k)
    {
      const int cells = std::max(1, static_cast<int>(std::ceil(extent[k] / this->Cell))) + 2;
      this->Cells[k] = cells;
      // The grid is centred on the box, one cell or more beyond it each side.
      this->Origin[k] = box.Center()[k] - 0.5 * cells * this->Cell;
    }
    this->InverseCell = 1.0 / this->Cell;
    this->UpperFactor = (1.0 + relaxation) * (1.0 + 1e-6);

    std::size_t rowLength = static_cast<std::size_t>(this->Cells[0] + 1);
    std::size_t rows = 1;
    for (int k = 1; k < DIM; ++k)
    {
      rows *= static_cast<std::size_t>(this->Cells[k] + 1);
    }
    this->Bounds.assign(rows * rowLength, 0.0f);
    auto fillRows = [&](const tbb::blocked_range<std::size_t>& range)
      {
        for (std::size_t row = range.begin(); row != range.end(); ++row)
        {
          std::array<int, DIM> index{};
          std::size_t rest = row;
          for (int k = 1; k < DIM; ++k)
          {
            index[k] = static_cast<int>(rest % static_cast<std::size_t>(this->Cells[k] + 1));
            rest /= static_cast<std::size_t>(this->Cells[k] + 1);
          }
          Hint hint{};
          for (std::size_t i = 0; i < rowLength; ++i)
          {
            index[0] = static_cast<int>(i);
            const double l = lowerBound(this->VertexPosition(index), hint);
            this->Bounds[row * rowLength + i] = StoredBound(l, signedValues);
          }
        }
      };
#if defined(__SANITIZE_THREAD__)
    // Debian's libtbb is not built with ThreadSanitizer, which then reports
    // false races inside TBB's own scheduling; the rows are independent, so
    // filling them in order gives the same values.
    fillRows(tbb::blocked_range<std::size_t>(0, rows));
#else
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows), fillRows);
#endif
  }

  bool Empty() const { return this->Bounds.empty(); }
  double CellSize() const { return this->Cell; }
  std::size_t NumberOfVertices() const { return this->Bounds.size(); }
  std::size_t MemoryBytes() const { return this->Bounds.capacity() * sizeof(float); }

  /// A radius L <= d(x) when x lies in the grid and L >= U(x) / (1 + accept)
  /// (so L >= d(x) / (1 + accept)); 0 otherwise, when the caller must query
  /// the boundary itself.
  double StepBound(const Vec<DIM>& x, double accept) const
  {
    double lower = -std::numeric_limits<double>::infinity();
    double upper = std::numeric_limits<double>::infinity();
    const bool inside = this->ForEachCorner(x,
      [&](double stored, double distance)
      {
        const double l = std::abs(stored);
        lower = std::max(lower, l - distance);
        upper = std::min(upper, this->UpperFactor * l + distance);
      });
    if (!inside)
    {
      return 0.0;
    }
    // A relative margin far above the rounding of the norms and differences.
    lower -= 1e-12 * (upper + lower);
    return lower > 0.0 && lower * (1.0 + accept) >= upper ? lower : 0.0;
  }

  /// An interval [Low, High] that holds the signed distance ψ(x), from a
  /// grid built with signed values; (−∞, ∞) where the grid cannot tell (x
  /// beyond it, or NaN). ψ is 1-Lipschitz, so for every corner v with
  /// stored s_v (|s_v| ≤ |ψ(v)| ≤ (1 + r)|s_v|):
  /// * |ψ(x)| ≤ (1 + r)|s_v| + |x − v|, on either side;
  /// * when |x − v| < |s_v|, x lies in a ball around v that the zero set
  ///   does not reach, so ψ(x) has the sign of s_v and
  ///   |ψ(x)| ≥ |s_v| − |x − v|. Two such balls both hold x, so they lie in
  ///   one region and agree on the sign.
  /// No search, one cell's corners: a few dozen nanoseconds.
  struct Interval
  {
    double Low = -std::numeric_limits<double>::infinity();
    double High = std::numeric_limits<double>::infinity();
  };
  Interval Range(const Vec<DIM>& x) const
  {
    Interval range;
    double lower = -std::numeric_limits<double>::infinity();
    double upper = std::numeric_limits<double>::infinity();
    double sign = 0.0;
    const bool inside = this->ForEachCorner(x,
      [&](double stored, double distance)
      {
        const double l = std::abs(stored);
        if (l - distance > lower)
        {
          lower = l - distance;
          sign = stored < 0.0 ? -1.0 : 1.0;
        }
        upper = std::min(upper, this->UpperFactor * l + distance);
      });
    if (!inside)
    {
      return range;
    }
    // Margins far above the rounding of the norms and differences.
    const double margin = 1e-12 * (std::abs(upper) + std::abs(lower));
    upper += margin;
    lower -= margin;
    if (lower > 0.0)
    {
      range.Low = sign > 0.0 ? lower : -upper;
      range.High = sign > 0.0 ? upper : -lower;
    }
    else
    {
      range.Low = -upper;
      range.High = upper;
    }
    return range;
  }

private:
  /// Calls visit(stored value, |x − corner|) for each corner of the cell
  /// holding x; false (and no call) when x is beyond the grid or NaN.
  template <typename Visit>
  bool ForEachCorner(const Vec<DIM>& x, Visit&& visit) const
  {
    if (this->Bounds.empty())
    {
      return false;
    }
    std::array<int, DIM> cell;
    std::size_t base = 0;
    std::size_t stride = 1;
    std::array<std::size_t, DIM> strides;
    for (int k = 0; k < DIM; ++k)
    {
      const double u = (x[k] - this->Origin[k]) * this->InverseCell;
      // The comparisons also reject NaN.
      if (!(u >= 0.0 && u < static_cast<double>(this->Cells[k])))
      {
        return false;
      }
      cell[k] = static_cast<int>(u);
      strides[k] = stride;
      base += static_cast<std::size_t>(cell[k]) * stride;
      stride *= static_cast<std::size_t>(this->Cells[k] + 1);
    }
    for (int corner = 0; corner < (1 << DIM); ++corner)
    {
      std::array<int, DIM> index;
      std::size_t at = base;
      for (int k = 0; k < DIM; ++k)
      {
        const int bit = corner >> k & 1;
        index[k] = cell[k] + bit;
        at += bit ? strides[k] : 0;
      }
      visit(static_cast<double>(this->Bounds[at]), (x - this->VertexPosition(index)).norm());
    }
    return true;
  }

  /// A bound rounded towards zero into float, so that it stays a bound;
  /// NaN (a failed query) stores 0, which no step accepts and which tells
  /// no side. Unsigned grids store negatives as 0 too.
  static float StoredBound(double l, bool signedValues)
  {
    if (!(l > 0.0) && !(signedValues && l < 0.0))
    {
      return 0.0f;
    }
    float f = static_cast<float>(l);
    if (std::abs(static_cast<double>(f)) > std::abs(l))
    {
      f = std::nextafter(f, 0.0f);
    }
    return f;
  }

  /// The same arithmetic at build and at query time, so both see one point.
  Vec<DIM> VertexPosition(const std::array<int, DIM>& index) const
  {
    Vec<DIM> v;
    for (int k = 0; k < DIM; ++k)
    {
      v[k] = this->Origin[k] + index[k] * this->Cell;
    }
    return v;
  }

  std::vector<float> Bounds; // x fastest, then y, then z
  std::array<int, DIM> Cells{};
  Vec<DIM> Origin = Vec<DIM>::Zero();
  double Cell = 0.0;
  double InverseCell = 0.0;
  double UpperFactor = 1.0;
};
} // namespace gridfree

#endif
