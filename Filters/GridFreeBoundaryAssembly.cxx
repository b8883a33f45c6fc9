#include "GridFreeBoundaryAssembly.h"

#include "GridFreeBoundaryConversion.h"
#include "GridFreeCsgBoundary.h"
#include "GridFreeImplicitBoundary.h"
#include "GridFreeMixedBoundaryConversion.h"
#include "GridFreeProblemInputs.h"
#include "GridFreeSourceConversion.h"

#include "vtkAlgorithm.h"
#include "vtkDataSet.h"
#include "vtkImplicitFunction.h"
#include "vtkObject.h"
#include "vtkPolyData.h"
#include "vtkSetGet.h"

#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/SignedDistance.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

namespace gridfree
{
namespace
{
// While the hierarchy of a large mesh is built (seconds for a million
// triangles), progress creeps up to 2% so that the filter's progress
// reports, and with them a GUI's window, go on (ParaView 5.11 processes
// window events only in them: Plugin/Client/pqGridFreeResponsiveSolves).
std::function<void(double)> BuildingProgress(vtkObject* self)
{
  vtkAlgorithm* algorithm = vtkAlgorithm::SafeDownCast(self);
  if (!algorithm)
  {
    return nullptr;
  }
  return [algorithm](double seconds) {
    algorithm->UpdateProgress(0.02 * (1.0 - std::exp(-seconds / 4.0)));
  };
}

// The boundary of one dimension from the resolved inputs; messages go to
// `self`, the filter that asked.
template <int DIM>
class BoundaryAssembly
{
public:
  // The plane of a 2D problem (the boundary's z); 0 for a 3D one.
  static double PlaneZ(const gridfree::ProblemInputs& in)
  {
    double bounds[6] = { 0, 0, 0, 0, 0, 0 };
    if (DIM == 2 && in.Boundary)
    {
      in.Boundary->GetBounds(bounds);
    }
    else if (DIM == 2 && !in.CsgOperands.empty() && in.CsgOperands.front().Mesh)
    {
      in.CsgOperands.front().Mesh->GetBounds(bounds);
    }
    return bounds[4];
  }

  // Warnings for the cells a conversion dropped.
  static void ReportDroppedCells(vtkObject* self, long long lowerDimensional,
    long long skipped, long long degenerate)
  {
    if (lowerDimensional > 0)
    {
      vtkWarningWithObjectMacro(self, << "Ignored " << lowerDimensional
                                      << " boundary cells of lower dimension than the " << DIM
                                      << "D problem (vertices" << (DIM == 3 ? " and lines" : "")
                                      << ").");
    }
    if (skipped > 0)
    {
      vtkWarningWithObjectMacro(
        self, << "Skipped " << skipped << " boundary cells with too few points.");
    }
    if (degenerate > 0)
    {
      vtkWarningWithObjectMacro(self, << "Ignored " << degenerate << " degenerate boundary "
                                      << (DIM == 3 ? "triangles of zero area (repeated or "
                                                     "collinear points)."
                                                   : "segments or Bézier curves of zero length "
                                                     "(repeated points)."));
    }
  }

  // The box of the probe's points (and `extra`), enlarged by half: the
  // problem's region where the boundary is not known to be bounded.
  static gridfree::BoundingBox<DIM> ProbeRegion(
    const gridfree::ProblemInputs& in, const gridfree::BoundingBox<DIM>& extra)
  {
    gridfree::BoundingBox<DIM> region;
    double b[6];
    in.Region->GetBounds(b);
    gridfree::Vec<DIM> lo, hi;
    for (int k = 0; k < DIM; ++k)
    {
      lo[k] = b[2 * k];
      hi[k] = b[2 * k + 1];
    }
    region.Expand(lo);
    region.Expand(hi);
    if (!extra.IsEmpty())
    {
      region.Expand(extra);
    }
    const gridfree::Vec<DIM> centre = region.Center();
    const gridfree::Vec<DIM> half = 0.75 * region.Extent() +
      gridfree::Vec<DIM>::Constant(1e-3 * std::max(region.Diagonal(), 1e-12));
    return gridfree::BoundingBox<DIM>(centre - half, centre + half);
  }

  // φ of the implicit boundary: the module's exact distances (and boolean
  // trees of them) run in the core, with exact gradients and L = 1 (`exact`);
  // anything else is called through VTK. A known bound (1, or a linear
  // Transform's factor) is never lowered by LipschitzBound; a larger
  // LipschitzBound only shortens the steps. Null, with an error, for invalid
  // parameters.
  static std::shared_ptr<const gridfree::SignedDistanceFunction<3>> MakeImplicitFunction(
    vtkObject* self, const gridfree::ProblemInputs& in, bool& exact,
    double& lipschitz)
  {
    const std::string invalid = gridfree::InvalidPrimitiveError(in.Implicit);
    if (!invalid.empty())
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the implicit boundary: " << invalid << ".");
      return nullptr;
    }
    std::shared_ptr<const gridfree::SignedDistanceFunction<3>> phi =
      gridfree::MakeExactImplicitDistance(in.Implicit);
    exact = phi != nullptr;
    lipschitz = std::max(in.LipschitzBound, gridfree::KnownLipschitzBound(in.Implicit));
    if (!exact)
    {
      phi = std::make_shared<gridfree::VtkImplicitFunctionDistance>(in.Implicit, lipschitz);
    }
    return phi;
  }

  // Never trust a function's scale: look for a steeper slope than L in
  // `checked`, on the sides of the surface the probe is on (where walks go).
  static void CheckLipschitz(vtkObject* self, const gridfree::ProblemInputs& in,
    const gridfree::SignedDistanceFunction<3>& phi, double lipschitz,
    const gridfree::BoundingBox<3>& checked)
  {
    bool inside = false, outside = false;
    const vtkIdType n = in.Region->GetNumberOfPoints();
    const vtkIdType stride = std::max<vtkIdType>(1, n / 1000);
    for (vtkIdType i = 0; i < n; i += stride)
    {
      double p[3];
      in.Region->GetPoint(i, p);
      const double value = phi.Value(gridfree::Vec3(p[0], p[1], p[2]));
      inside = inside || value < 0.0;
      outside = outside || value > 0.0;
    }
    const int side = inside == outside ? 0 : (inside ? -1 : 1);
    const double observed = gridfree::ObservedLipschitz(phi, checked, 4096, side);
    if (observed > lipschitz * (1.0 + 1e-6))
    {
      vtkWarningWithObjectMacro(self, << "The implicit boundary's function changes faster than "
                                         "LipschitzBound = "
                                      << lipschitz << " (slope " << observed
                                      << " seen near the boundary): walks may step across the "
                                         "boundary. Set LipschitzBound to at least "
                                      << observed << " or use a signed distance function.");
    }
  }

  // The CSG of the Boundary's blocks and the implicit boundary (paper Sec.
  // 5.1.4), with values from the expressions or each block's own array.
  static bool BuildCsg(vtkObject* self, const gridfree::ProblemInputs& in,
    std::shared_ptr<const gridfree::BoundaryValueFunction<DIM>> valueFunction,
    gridfree::Boundary<DIM>& geometry)
  {
    std::shared_ptr<const gridfree::SignedDistanceFunction<DIM>> implicitOperand;
    bool exact = true;
    double lipschitz = 1.0;
    if (in.Implicit)
    {
      if constexpr (DIM == 3)
      {
        implicitOperand = MakeImplicitFunction(self, in, exact, lipschitz);
        if (!implicitOperand)
        {
          return false;
        }
      }
      else
      {
        vtkErrorWithObjectMacro(self, << "An implicit boundary makes a 3D problem: it cannot be "
                                         "combined with a 2D boundary of lines.");
        return false;
      }
    }
    const gridfree::CsgOperation operation = *in.CsgOperation;
    gridfree::CsgBoundaryReport report;
    std::string reason;
    const gridfree::BoundingBox<DIM> probeBox = ProbeRegion(in, gridfree::BoundingBox<DIM>());
    if (!gridfree::BuildCsgBoundary<DIM>(in.CsgOperands, implicitOperand, operation,
          in.CsgBlendRadius, valueFunction, probeBox, geometry, report, reason))
    {
      vtkErrorWithObjectMacro(self, << "Cannot combine the boundary operands: " << reason << ".");
      return false;
    }
    ReportDroppedCells(
      self, report.IgnoredLowerDimensionalCells, report.SkippedCells, report.DegenerateCells);
    if constexpr (DIM == 3)
    {
      if (implicitOperand && !exact)
      {
        gridfree::BoundingBox<3> checked = implicitOperand->Bounds();
        CheckLipschitz(self, in, *implicitOperand, lipschitz,
          checked.IsEmpty() ? ProbeRegion(in, gridfree::BoundingBox<3>()) : checked);
      }
    }
    return true;
  }

  // The core boundary: the mesh with its value table, a mesh with values from
  // expressions, an implicit surface with values from expressions or
  // sampled from the Boundary input's mesh, or a CSG of blocks and the
  // implicit surface.
  static bool BuildBoundary(vtkObject* self, const gridfree::ProblemInputs& in,
    gridfree::Boundary<DIM>& geometry)
  {
    std::shared_ptr<const gridfree::BoundaryValueFunction<DIM>> valueFunction;
    if (!in.ValueExpressions.empty())
    {
      valueFunction = std::make_shared<gridfree::VolumeBoundaryValues<DIM>>(
        gridfree::MakeExpressionListFactory<DIM>(in.ValueExpressions, PlaneZ(in)),
        static_cast<int>(in.ValueExpressions.size()));
    }
    if (in.CsgOperation)
    {
      return BuildCsg(self, in, valueFunction, geometry);
    }
    auto mesh = std::make_shared<gridfree::Boundary<DIM>>();
    if (in.Boundary && !(in.Implicit && valueFunction))
    {
      gridfree::BoundaryConversionReport report;
      std::string reason;
      if (!gridfree::ConvertBoundary<DIM>(in.Boundary, in.Values, in.CellData, *mesh, report,
            reason, in.Implicit ? nullptr : valueFunction, BuildingProgress(self)))
      {
        vtkErrorWithObjectMacro(self, << "Cannot use the Boundary input: " << reason << ".");
        return false;
      }
      ReportDroppedCells(
        self, report.IgnoredLowerDimensionalCells, report.SkippedCells, report.DegenerateCells);
    }
    if (!in.Implicit)
    {
      geometry = std::move(*mesh);
      return true;
    }
    if constexpr (DIM == 3)
    {
      bool exact = false;
      double lipschitz = 1.0;
      const auto phi = MakeImplicitFunction(self, in, exact, lipschitz);
      if (!phi)
      {
        return false;
      }
      auto shape = std::make_shared<gridfree::ImplicitBoundaryGeometry<3>>(phi, lipschitz);
      if (!valueFunction)
      {
        valueFunction = std::make_shared<gridfree::SampledBoundaryValues<3>>(mesh);
      }
      // Where the function's zero set is not known to be bounded, the problem
      // lives in the box of the probe (and of the value mesh), enlarged.
      gridfree::BoundingBox<3> meshBox;
      if (!mesh->Empty())
      {
        meshBox.Expand(mesh->BoundsMin());
        meshBox.Expand(mesh->BoundsMax());
      }
      const gridfree::BoundingBox<3> region = ProbeRegion(in, meshBox);
      geometry.SetGeometry(shape, valueFunction, region);

      // Exact distances need no check: their slope is 1 by construction.
      if (!exact)
      {
        gridfree::BoundingBox<3> checked = shape->Bounds();
        CheckLipschitz(self, in, *phi, lipschitz, checked.IsEmpty() ? region : checked);
      }
      return true;
    }
    vtkErrorWithObjectMacro(self, << "An implicit boundary makes a 3D problem.");
    return false;
  }
};
} // namespace

template <int DIM>
double ProblemPlaneZ(const gridfree::ProblemInputs& in)
{
  return BoundaryAssembly<DIM>::PlaneZ(in);
}

template <int DIM>
bool AssembleBoundary(vtkObject* reporter, const gridfree::ProblemInputs& in,
  Boundary<DIM>& geometry)
{
  if (!BoundaryAssembly<DIM>::BuildBoundary(reporter, in, geometry))
  {
    return false;
  }
  geometry.SetTwoSided(in.TwoSided);
  return true;
}

template <int DIM>
bool AssembleMixedBoundary(vtkObject* reporter, const gridfree::ProblemInputs& in,
  MixedBoundary<DIM>& mixed)
{
  vtkObject* self = reporter;
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction;
  if (!in.ValueExpressions.empty())
  {
    valueFunction = std::make_shared<VolumeBoundaryValues<DIM>>(
      MakeExpressionListFactory<DIM>(in.ValueExpressions, ProblemPlaneZ<DIM>(in)),
      static_cast<int>(in.ValueExpressions.size()));
  }
  MixedBoundaryArrays arrays;
  arrays.Values = in.Values;
  arrays.ValuesOnCells = in.CellData;
  arrays.Conditions = in.Conditions;
  arrays.ConditionsOnCells = in.ConditionsOnCells;
  arrays.Flux = in.Flux;
  arrays.FluxOnCells = in.FluxOnCells;
  arrays.Robin = in.Robin;
  arrays.RobinOnCells = in.RobinOnCells;
  BoundaryConversionReport report;
  MixedBoundaryCounts counts;
  std::string reason;
  if (!ConvertMixedBoundary<DIM>(in.Boundary, arrays, valueFunction, mixed, report, counts, reason,
        BuildingProgress(self)))
  {
    vtkErrorWithObjectMacro(self, << "Cannot use the Boundary input with mixed boundary "
                                     "conditions: "
                                  << reason << ".");
    return false;
  }
  BoundaryAssembly<DIM>::ReportDroppedCells(
    self, report.IgnoredLowerDimensionalCells, report.SkippedCells, report.DegenerateCells);
  if (counts.Neumann + counts.Robin + counts.Sheets == 0)
  {
    vtkWarningWithObjectMacro(self, << "Mixed Boundary Conditions is on, but the boundary "
                                       "condition array marks no cell Neumann (1), Robin (2) "
                                       "or insulating sheet (3): every cell is Dirichlet.");
  }
  // A flux out of all proportion: across the boundary's size it would
  // change u by far more than the boundary values are (1e8 times), or by
  // so much that the walks' sums of squares overflow (1e100).
  const double swing = counts.LargestFlux * counts.Size;
  if (swing > 1e100 || (counts.LargestValue > 0.0 && swing > 1e8 * counts.LargestValue))
  {
    vtkWarningWithObjectMacro(self, << "The Neumann flux reaches " << counts.LargestFlux
                                    << " on the Neumann and Robin cells: across the boundary's "
                                       "size ("
                                    << counts.Size << ") that changes the solution by about "
                                    << swing << ", against boundary values of at most "
                                    << counts.LargestValue
                                    << ". Check the flux array's values and units (a fill "
                                       "value for missing data?).");
  }
  vtkDebugWithObjectMacro(self, << "Mixed boundary: " << counts.Dirichlet << " Dirichlet, "
                                << counts.Neumann << " Neumann, " << counts.Robin
                                << " Robin and " << counts.Sheets
                                << " insulating sheet primitives.");
  return true;
}

template double ProblemPlaneZ<2>(const gridfree::ProblemInputs&);
template double ProblemPlaneZ<3>(const gridfree::ProblemInputs&);
template bool AssembleBoundary<2>(vtkObject*, const gridfree::ProblemInputs&, Boundary<2>&);
template bool AssembleBoundary<3>(vtkObject*, const gridfree::ProblemInputs&, Boundary<3>&);
template bool AssembleMixedBoundary<2>(
  vtkObject*, const gridfree::ProblemInputs&, MixedBoundary<2>&);
template bool AssembleMixedBoundary<3>(
  vtkObject*, const gridfree::ProblemInputs&, MixedBoundary<3>&);
} // namespace gridfree
