// Boundary values g on a BezierBoundaryGeometry (2D diffusion curves), given
// per curve: either at the curve's two end points, interpolated along it, or
// one constant tuple per curve.
//
// Why only the end points carry values: the inner control points P1 and P2
// of a cubic Bézier curve are handles that shape the curve but do not lie on
// it, so a value attached to them would describe no boundary point. The value
// at parameter t is (1 − t)·g(P0) + t·g(P3), with the weights (1 − t, t) that
// BezierBoundaryGeometry returns as the closest point's barycentric
// coordinates. For a straight curve with control points at 1/3 and 2/3 of
// the chord, t is proportional to arc length, so this is exactly the linear
// interpolation of a line segment; on a curved one, t is not proportional to
// arc length, so the interpolation is linear in t, not in arc length.
#ifndef GRIDFREE_BOUNDARY_BEZIER_BOUNDARY_VALUES_H
#define GRIDFREE_BOUNDARY_BEZIER_BOUNDARY_VALUES_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/geometry/ClosestPointResult.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
class BezierBoundaryValues final : public BoundaryValueFunction<2>
{
public:
  // `values` holds, for each of `curves` curves in the geometry's order,
  // 2 × `components` numbers (the tuple at P0, then the tuple at P3) for
  // ValueAssociation::Points, or `components` numbers for
  // ValueAssociation::Cells.
  BezierBoundaryValues(std::size_t curves, ValueAssociation association, int components,
    std::vector<double> values)
    : Association(association)
    , NumberOfComponents(components)
    , NumberOfCurves(curves)
    , Values(std::move(values))
  {
    const std::size_t perCurve =
      static_cast<std::size_t>(components) * (association == ValueAssociation::Points ? 2 : 1);
    if (components < 1 || this->Values.size() != curves * perCurve)
    {
      throw std::invalid_argument("Bézier boundary values: expected " + std::to_string(curves) +
        " x " + std::to_string(perCurve) + " numbers, got " + std::to_string(this->Values.size()));
    }
  }

  int Components() const override { return this->NumberOfComponents; }

  // NaN for a hit on no curve (an empty geometry has no closest point), so a
  // missing value can never pass for a real one.
  void Evaluate(const ClosestPointResult<2>& hit, double* out) const override
  {
    const int nc = this->NumberOfComponents;
    if (hit.primitive < 0 || static_cast<std::size_t>(hit.primitive) >= this->NumberOfCurves)
    {
      for (int c = 0; c < nc; ++c)
      {
        out[c] = std::numeric_limits<double>::quiet_NaN();
      }
      return;
    }
    const std::size_t curve = static_cast<std::size_t>(hit.primitive);
    if (this->Association == ValueAssociation::Cells)
    {
      const double* v = &this->Values[curve * nc];
      for (int c = 0; c < nc; ++c)
      {
        out[c] = v[c];
      }
      return;
    }
    const double* v0 = &this->Values[2 * curve * nc];
    const double* v1 = v0 + nc;
    const double w0 = hit.barycentric[0];
    const double w1 = hit.barycentric[1];
    for (int c = 0; c < nc; ++c)
    {
      out[c] = w0 * v0[c] + w1 * v1[c];
    }
  }

private:
  ValueAssociation Association;
  int NumberOfComponents;
  std::size_t NumberOfCurves;
  std::vector<double> Values;
};
} // namespace gridfree

#endif
