// The coefficients of the equation with varying coefficients, ∇·(α∇u) −
// σu = f, from a filter's Source input and settings: the arrays chosen as
// input arrays 7 (α), 8 (σ) and 2 (f) on a vtkImageData, or the settings'
// constants, made into the core's CoefficientModel (ImageCoefficients
// smoothed by CoefficientSmoothing and the cubic B-spline, with a bound
// grid of σ′ over the domain). Private to the GridFree::Filters module.
#ifndef GridFreeCoefficientConversion_h
#define GridFreeCoefficientConversion_h

#include "GridFreeArraySelection.h"
#include "GridFreeProblemInputs.h"
#include "GridFreeSolveSettings.h"

#include <gridfree/coefficients/ScreeningMajorant.h>
#include <gridfree/execution/PreparationMonitor.h>
#include <gridfree/geometry/BoundingBox.h>

#include <memory>
#include <string>

class vtkDataSet;
class vtkObject;

namespace gridfree
{
// Finds the coefficient arrays on `source` (null: none connected) and
// checks the constants; false after an error reported as `reporter`'s.
bool ResolveCoefficientArrays(vtkObject* reporter, const SolveSettings& settings,
  const ArraySelections& arrays, vtkDataSet* source, ProblemInputs& inputs);

// The coefficients and their majorant over `domain` (the boundary's box);
// null with `reason` set when the image does not cover the domain or holds
// unusable values. VTK-free once the arrays are copied, so it may run on a
// thread of its own while `monitor` (may be null) reports its progress and
// stops it (it then throws PreparationStopped).
template <int DIM>
std::shared_ptr<const CoefficientModel<DIM>> MakeCoefficientModel(const ProblemInputs& in,
  const SolveSettings& settings, const BoundingBox<DIM>& domain, std::string& reason,
  PreparationMonitor* monitor = nullptr);

extern template std::shared_ptr<const CoefficientModel<2>> MakeCoefficientModel<2>(
  const ProblemInputs&, const SolveSettings&, const BoundingBox<2>&, std::string&,
  PreparationMonitor*);
extern template std::shared_ptr<const CoefficientModel<3>> MakeCoefficientModel<3>(
  const ProblemInputs&, const SolveSettings&, const BoundingBox<3>&, std::string&,
  PreparationMonitor*);
} // namespace gridfree

#endif
