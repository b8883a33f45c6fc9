// Turns the solver's source inputs into the estimator core's source terms:
// - a vtkImageData point array: trilinear interpolation straight from the
//   voxels (no locator), zero outside the image;
// - any other vtkDataSet point array: the cell containing y (a static cell
//   locator) and its interpolation weights, zero outside every cell;
// - a vtkPolyData with vertices and/or lines: point and curve sources with
//   the point array as strength;
// - an expression in x, y, z (vtkExprTkFunctionParser; each block of probe
//   points a thread solves gets its own parser).
// The volume sources also give their gradients (EvaluateGradient): exact for
// the image and dataset interpolants, central differences for expressions.
// Private to the GridFree::Filters module.
#ifndef GridFreeSourceConversion_h
#define GridFreeSourceConversion_h

#include <gridfree/sources/DifferentialOperatorSource.h>
#include <gridfree/sources/SourceSet.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkDataArray;
class vtkDataSet;

namespace gridfree
{
// SourceOperator (DifferentialOperatorSource.h): the data themselves, or the
// divergence or curl of the vector field they give. Its values match
// vtkWalkOnSpheresSolver's SourceOperator.

// "value", "divergence" or "curl", for messages.
const char* SourceOperatorName(SourceOperator op);

// Builds the source terms from an optional dataset with its point array and
// an optional expression, for a solution with `components` components (a
// one-component source applies to every component). Expressions may be
// scalars or vectors (iHat, jHat, kHat). With an operator, the array (DIM or
// 3 components) or the vector expression is a field X and f is its
// divergence or curl. In 2D, datasets and expressions are sampled in the
// plane z = planeZ. Returns false with a reason when the inputs cannot be
// used.
template <int DIM>
bool ConvertSource(vtkDataSet* source, vtkDataArray* array, const std::string& expression,
  int components, double planeZ, SourceSet<DIM>& out, std::string& reason,
  SourceOperator op = SourceOperator::Value);

extern template bool ConvertSource<2>(vtkDataSet*, vtkDataArray*, const std::string&, int,
  double, SourceSet<2>&, std::string&, SourceOperator);
extern template bool ConvertSource<3>(vtkDataSet*, vtkDataArray*, const std::string&, int,
  double, SourceSet<3>&, std::string&, SourceOperator);

// Makes one thread's source of len(expressions) components, component c
// being expressions[c] in x, y, z (in 2D sampled in the plane z = planeZ).
// The expressions must have passed CheckSourceExpression.
template <int DIM>
std::function<std::unique_ptr<VolumeSource<DIM>>()> MakeExpressionListFactory(
  const std::vector<std::string>& expressions, double planeZ);

extern template std::function<std::unique_ptr<VolumeSource<2>>()> MakeExpressionListFactory<2>(
  const std::vector<std::string>&, double);
extern template std::function<std::unique_ptr<VolumeSource<3>>()> MakeExpressionListFactory<3>(
  const std::vector<std::string>&, double);

// Checks that an expression in x, y, z parses to a scalar; returns false
// with the parser's message (or the reason a vector is refused) otherwise.
bool CheckSourceExpression(const std::string& expression, std::string& reason);
} // namespace gridfree

#endif
