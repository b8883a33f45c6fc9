#include "GridFreeSourceConversion.h"

#include "GridFreeParsedExpression.h"

#include <gridfree/sources/ImageSource.h>

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkGenericCell.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace gridfree
{
namespace
{
// The source's values as floats, `components` per point (a one-component
// array is broadcast), so every thread reads them without VTK calls.
std::vector<float> CopyValues(vtkDataArray* array, int components)
{
  const vtkIdType tuples = array->GetNumberOfTuples();
  const int nc = array->GetNumberOfComponents();
  std::vector<float> values(static_cast<std::size_t>(tuples) * components);
  for (vtkIdType t = 0; t < tuples; ++t)
  {
    for (int c = 0; c < components; ++c)
    {
      values[static_cast<std::size_t>(t) * components + c] =
        static_cast<float>(array->GetComponent(t, nc == 1 ? 0 : c));
    }
  }
  return values;
}


// Any other dataset: the cell containing y and its interpolation weights.
// EvaluateGradient uses the located cell's own derivative of its
// interpolation functions (vtkCell::Derivatives), the exact gradient of the
// interpolant inside that cell; it jumps across cell faces (the cell the
// locator returns wins) and is zero outside every cell.
template <int DIM>
class DataSetSource : public VolumeSource<DIM>
{
public:
  struct Shared
  {
    vtkSmartPointer<vtkDataSet> Data;
    vtkSmartPointer<vtkStaticCellLocator> Locator;
    int Components = 1;
    double PlaneZ = 0.0;
    std::vector<float> Values;
    Vec<DIM> Min, Max;
    // Every cell interpolates linearly (non-negative weights): the values'
    // range bounds f (ValueBounds).
    bool LinearCells = false;
  };

  explicit DataSetSource(std::shared_ptr<const Shared> shared)
    : Data(std::move(shared))
    , Weights(static_cast<std::size_t>(std::max(1, this->Data->Data->GetMaxCellSize())))
    , PointValues(this->Weights.size())
  {
  }

  void Evaluate(const Vec<DIM>& y, double* f) override { this->Locate(y, f); }

  void EvaluateGradient(const Vec<DIM>& y, int, double* f, double* gradient) override
  {
    const Shared& s = *this->Data;
    std::fill(gradient, gradient + s.Components * DIM, 0.0);
    if (!this->Locate(y, f))
    {
      return;
    }
    const vtkIdType n = this->Cell->GetNumberOfPoints();
    if (static_cast<std::size_t>(n) > this->PointValues.size())
    {
      return; // cannot happen: GetMaxCellSize bounds every cell
    }
    for (int c = 0; c < s.Components; ++c)
    {
      for (vtkIdType k = 0; k < n; ++k)
      {
        this->PointValues[k] = s.Values[static_cast<std::size_t>(this->Cell->GetPointId(k)) *
            static_cast<std::size_t>(s.Components) +
          static_cast<std::size_t>(c)];
      }
      double derivs[3] = { 0.0, 0.0, 0.0 };
      this->Cell->Derivatives(this->SubId, this->PCoords, this->PointValues.data(), 1, derivs);
      for (int i = 0; i < DIM; ++i)
      {
        gradient[c * DIM + i] = derivs[i];
      }
    }
  }

  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    boxMin = this->Data->Min;
    boxMax = this->Data->Max;
    return true;
  }

  // Higher-order cells' interpolation may overshoot the point values, so
  // only linear cells give a range.
  bool ValueBounds(int c, double& lowest, double& highest) const override
  {
    const Shared& s = *this->Data;
    if (!s.LinearCells || c < 0 || c >= s.Components)
    {
      return false;
    }
    StoredValueRange(s.Values, s.Components, c, lowest, highest);
    return std::isfinite(lowest) && std::isfinite(highest);
  }

private:
  // Finds the cell containing y (kept in Cell, SubId and PCoords) and writes
  // f(y); false (and f = 0) outside every cell.
  bool Locate(const Vec<DIM>& y, double* f)
  {
    const Shared& s = *this->Data;
    std::array<double, 3> p = ToXYZ<DIM>(y, s.PlaneZ);
    std::fill(f, f + s.Components, 0.0);
    const vtkIdType cell = s.Locator->FindCell(
      p.data(), 0.0, this->Cell, this->SubId, this->PCoords, this->Weights.data());
    if (cell < 0)
    {
      return false;
    }
    const vtkIdType n = this->Cell->GetNumberOfPoints();
    for (vtkIdType k = 0; k < n; ++k)
    {
      const float* v = &s.Values[static_cast<std::size_t>(this->Cell->GetPointId(k)) *
        static_cast<std::size_t>(s.Components)];
      for (int c = 0; c < s.Components; ++c)
      {
        f[c] += this->Weights[k] * v[c];
      }
    }
    return true;
  }

  std::shared_ptr<const Shared> Data;
  vtkNew<vtkGenericCell> Cell;
  std::vector<double> Weights;
  std::vector<double> PointValues; // one component's values at the cell's points
  int SubId = 0;
  double PCoords[3] = { 0.0, 0.0, 0.0 };
};

// An expression in x, y, z; one parser per block of probe points a thread
// solves. A scalar expression applies to every component; a vector
// expression gives its first `components` (at most 3) components. Its
// gradient is the base class's central differences, with the step the
// factory sets from the problem's length scale (see VolumeSourceFactory).
template <int DIM>
class ExpressionSource : public VolumeSource<DIM>
{
public:
  // `constant`: the expression reads none of x, y, z (ExpressionReadsPosition).
  ExpressionSource(const std::string& expression, int components, double planeZ, bool constant)
    : Expression(expression)
    , Components(components)
    , PlaneZ(planeZ)
    , Constant(constant)
  {
    if (this->Constant)
    {
      this->Expression.Evaluate({ 0.0, 0.0, 0.0 }, this->ConstantValue);
    }
  }

  void Evaluate(const Vec<DIM>& y, double* f) override
  {
    double v[3];
    this->Expression.Evaluate(ToXYZ<DIM>(y, this->PlaneZ), v);
    if (this->Expression.Components() == 1)
    {
      std::fill(f, f + this->Components, v[0]);
      return;
    }
    std::copy(v, v + this->Components, f);
  }

  bool SupportBounds(Vec<DIM>&, Vec<DIM>&) const override { return false; }

  // Known only for an expression that does not read x, y or z: a constant.
  bool ValueBounds(int c, double& lowest, double& highest) const override
  {
    if (!this->Constant || c < 0 || c >= this->Components)
    {
      return false;
    }
    lowest = highest = this->ConstantValue[this->Expression.Components() == 1 ? 0 : c];
    return std::isfinite(lowest);
  }

private:
  ParsedExpression Expression;
  int Components;
  double PlaneZ;
  bool Constant = false;
  double ConstantValue[3] = { 0.0, 0.0, 0.0 };
};

// Several expressions in x, y, z, one per component: boundary values g (and
// the biharmonic h) of boundaries without a value table, evaluated at the
// boundary point.
template <int DIM>
class ExpressionListSource : public VolumeSource<DIM>
{
public:
  ExpressionListSource(const std::vector<std::string>& expressions, double planeZ)
    : PlaneZ(planeZ)
  {
    for (const std::string& e : expressions)
    {
      this->Expressions.push_back(std::make_unique<ParsedExpression>(e));
    }
  }

  void Evaluate(const Vec<DIM>& y, double* f) override
  {
    const std::array<double, 3> p = ToXYZ<DIM>(y, this->PlaneZ);
    for (std::size_t c = 0; c < this->Expressions.size(); ++c)
    {
      f[c] = (*this->Expressions[c])(p);
    }
  }

  bool SupportBounds(Vec<DIM>&, Vec<DIM>&) const override { return false; }

private:
  std::vector<std::unique_ptr<ParsedExpression>> Expressions;
  double PlaneZ;
};

// The sum of two volume sources (a dataset plus an expression).
template <int DIM>
class SumSource : public VolumeSource<DIM>
{
public:
  SumSource(std::unique_ptr<VolumeSource<DIM>> a, std::unique_ptr<VolumeSource<DIM>> b,
    int components)
    : A(std::move(a))
    , B(std::move(b))
    , Scratch(components)
    , GradientScratch(static_cast<std::size_t>(components) * DIM)
  {
  }

  void Evaluate(const Vec<DIM>& y, double* f) override
  {
    this->A->Evaluate(y, f);
    this->B->Evaluate(y, this->Scratch.data());
    for (std::size_t c = 0; c < this->Scratch.size(); ++c)
    {
      f[c] += this->Scratch[c];
    }
  }

  // The sum of the parts' values and gradients.
  void EvaluateGradient(const Vec<DIM>& y, int components, double* f, double* gradient) override
  {
    this->A->EvaluateGradient(y, components, f, gradient);
    this->B->EvaluateGradient(y, components, this->Scratch.data(), this->GradientScratch.data());
    for (std::size_t c = 0; c < this->Scratch.size(); ++c)
    {
      f[c] += this->Scratch[c];
    }
    for (std::size_t k = 0; k < this->GradientScratch.size(); ++k)
    {
      gradient[k] += this->GradientScratch[k];
    }
  }

  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    Vec<DIM> lo, hi;
    if (!this->A->SupportBounds(boxMin, boxMax) || !this->B->SupportBounds(lo, hi))
    {
      return false;
    }
    boxMin = boxMin.cwiseMin(lo);
    boxMax = boxMax.cwiseMax(hi);
    return true;
  }

  bool ValueBounds(int c, double& lowest, double& highest) const override
  {
    double lowB = 0.0, highB = 0.0;
    if (!this->A->ValueBounds(c, lowest, highest) || !this->B->ValueBounds(c, lowB, highB))
    {
      return false;
    }
    lowest += lowB;
    highest += highB;
    return true;
  }

private:
  std::unique_ptr<VolumeSource<DIM>> A, B;
  std::vector<double> Scratch, GradientScratch;
};

template <int DIM>
void BoundsOf(vtkDataSet* data, Vec<DIM>& lo, Vec<DIM>& hi)
{
  double b[6];
  data->GetBounds(b);
  for (int i = 0; i < DIM; ++i)
  {
    lo[i] = b[2 * i];
    hi[i] = b[2 * i + 1];
  }
}

template <int DIM>
VolumeSourceFactory<DIM> MakeImageSource(
  vtkImageData* image, vtkDataArray* array, int components, double planeZ)
{
  auto shared = std::make_shared<typename ImageSource<DIM>::Shared>();
  image->GetOrigin(shared->Origin.data());
  image->GetSpacing(shared->Spacing.data());
  image->GetDimensions(shared->Dims.data());
  vtkNew<vtkMatrix3x3> inverse;
  vtkMatrix3x3::Invert(image->GetDirectionMatrix(), inverse);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      shared->PhysicalToIndex[3 * r + c] = inverse->GetElement(r, c);
    }
  }
  // Origin is the physical position of the image's first point (its extent
  // may not start at 0): shift it to index 0 of the value array.
  int extent[6];
  image->GetExtent(extent);
  double first[3];
  image->TransformIndexToPhysicalPoint(extent[0], extent[2], extent[4], first);
  shared->Origin = { first[0], first[1], first[2] };
  shared->Components = components;
  shared->PlaneZ = planeZ;
  shared->Values = CopyValues(array, components);
  BoundsOf<DIM>(image, shared->Min, shared->Max);
  for (int i = 0; i < DIM; ++i)
  {
    shared->Bounded = shared->Bounded && shared->Dims[i] > 1;
  }
  std::shared_ptr<const typename ImageSource<DIM>::Shared> constShared = shared;
  return [constShared](double) -> std::unique_ptr<VolumeSource<DIM>> {
    return std::make_unique<ImageSource<DIM>>(constShared);
  };
}

// Whether every cell's interpolation weights are non-negative, so that f stays
// within its point values: linear cells, but not polyhedra (their mean value
// coordinates turn negative where a polyhedron is not convex) nor
// higher-order cells (their weights overshoot).
bool InterpolatesWithinPointValues(vtkDataSet* data)
{
  vtkNew<vtkCellTypes> types;
  data->GetCellTypes(types);
  bool linear = types->GetNumberOfTypes() > 0;
  for (vtkIdType t = 0; t < types->GetNumberOfTypes(); ++t)
  {
    const unsigned char type = types->GetCellType(t);
    linear = linear && vtkCellTypes::IsLinear(type) && type != VTK_POLYHEDRON;
  }
  return linear;
}

template <int DIM>
VolumeSourceFactory<DIM> MakeDataSetSource(
  vtkDataSet* data, vtkDataArray* array, int components, double planeZ)
{
  auto shared = std::make_shared<typename DataSetSource<DIM>::Shared>();
  // A private shallow copy: the locator and the cells it builds are ours.
  shared->Data = vtk::TakeSmartPointer(data->NewInstance());
  shared->Data->ShallowCopy(data);
  shared->Locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  shared->Locator->SetDataSet(shared->Data);
  shared->Locator->BuildLocator();
  // Build the dataset's lazy cell structures here, on one thread, so the
  // threads' GetCell calls only read them.
  if (shared->Data->GetNumberOfCells() > 0)
  {
    vtkNew<vtkGenericCell> cell;
    shared->Data->GetCell(0, cell);
  }
  shared->Components = components;
  shared->PlaneZ = planeZ;
  shared->Values = CopyValues(array, components);
  BoundsOf<DIM>(data, shared->Min, shared->Max);
  shared->LinearCells = InterpolatesWithinPointValues(shared->Data);
  std::shared_ptr<const typename DataSetSource<DIM>::Shared> constShared = shared;
  return [constShared](double) -> std::unique_ptr<VolumeSource<DIM>> {
    return std::make_unique<DataSetSource<DIM>>(constShared);
  };
}

template <int DIM>
Vec<DIM> PointOf(vtkDataSet* data, vtkIdType id)
{
  double p[3];
  data->GetPoint(id, p);
  Vec<DIM> v;
  for (int i = 0; i < DIM; ++i)
  {
    v[i] = p[i];
  }
  return v;
}

// Vertices become point sources, lines curve sources; strengths from the
// point array. Polygons and strips carry no point or curve measure.
template <int DIM>
bool ConvertConcentrated(vtkPolyData* poly, vtkDataArray* array, int components,
  SourceSet<DIM>& out, std::string& reason)
{
  const int nc = array->GetNumberOfComponents();
  auto strength = [&](vtkIdType id, std::vector<double>& dst) {
    for (int c = 0; c < components; ++c)
    {
      dst.push_back(array->GetComponent(id, nc == 1 ? 0 : c));
    }
  };
  try
  {
    if (poly->GetNumberOfVerts() > 0)
    {
      std::vector<Vec<DIM>> positions;
      std::vector<double> strengths;
      auto it = vtk::TakeSmartPointer(poly->GetVerts()->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdType n;
        const vtkIdType* ids;
        it->GetCurrentCell(n, ids);
        for (vtkIdType k = 0; k < n; ++k)
        {
          positions.push_back(PointOf<DIM>(poly, ids[k]));
          strength(ids[k], strengths);
        }
      }
      out.Points = std::make_unique<PointSources<DIM>>();
      out.Points->Set(std::move(positions), components, std::move(strengths));
    }
    if (poly->GetNumberOfLines() > 0)
    {
      std::vector<Vec<DIM>> vertices;
      std::vector<double> strengths;
      for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i)
      {
        vertices.push_back(PointOf<DIM>(poly, i));
        strength(i, strengths);
      }
      std::vector<std::array<std::int64_t, 2>> segments;
      auto it = vtk::TakeSmartPointer(poly->GetLines()->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdType n;
        const vtkIdType* ids;
        it->GetCurrentCell(n, ids);
        for (vtkIdType k = 0; k + 1 < n; ++k)
        {
          segments.push_back({ ids[k], ids[k + 1] });
        }
      }
      out.Curves = std::make_unique<CurveSources<DIM>>();
      out.Curves->Set(std::move(vertices), std::move(segments), components, std::move(strengths));
    }
  }
  catch (const std::exception& e)
  {
    reason = std::string("its point and curve sources are not usable: ") + e.what();
    return false;
  }
  out.IgnoredSurfaceCells = poly->GetNumberOfPolys() + poly->GetNumberOfStrips();
  return true;
}
} // namespace

bool CheckSourceExpression(const std::string& expression, std::string& reason)
{
  const int components = ExpressionComponents(expression, reason);
  if (components == 3)
  {
    reason = "it evaluates to a vector, not a number";
  }
  return components == 1;
}

const char* SourceOperatorName(SourceOperator op)
{
  switch (op)
  {
    case SourceOperator::Divergence:
      return "divergence";
    case SourceOperator::Curl:
      return "curl";
    default:
      return "value";
  }
}

template <int DIM>
bool ConvertSource(vtkDataSet* source, vtkDataArray* array, const std::string& expression,
  int components, double planeZ, SourceSet<DIM>& out, std::string& reason,
  SourceOperator op)
{
  const bool differentiate = op != SourceOperator::Value;
  const int resultComponents =
    differentiate ? DifferentialOperatorSource<DIM>::ResultComponents(op) : components;
  if (differentiate && resultComponents != 1 && resultComponents != components)
  {
    reason = std::string("the ") + SourceOperatorName(op) + " of the source field has " +
      std::to_string(resultComponents) + " components; the boundary values have " +
      std::to_string(components) + " (it needs 1 or as many)";
    return false;
  }
  // Components of the data the source is made from: the solution's, or the
  // vector field an operator differentiates (taken as it is).
  int fieldComponents = components;
  const std::string arrayName = array && array->GetName() ? array->GetName() : "";

  VolumeSourceFactory<DIM> dataset;
  if (source && source->GetNumberOfPoints() > 0)
  {
    if (!array)
    {
      reason = "the Source input has no point array to use as the source term";
      return false;
    }
    const int arrayComponents = array->GetNumberOfComponents();
    if (differentiate)
    {
      if (arrayComponents < DIM || arrayComponents > 3)
      {
        reason = "the source array '" + arrayName + "' has " + std::to_string(arrayComponents) +
          " components; its " + SourceOperatorName(op) + " needs a vector field (" +
          (DIM == 2 ? "2 or 3" : "3") + " components)";
        return false;
      }
      fieldComponents = arrayComponents;
    }
    else if (arrayComponents != 1 && arrayComponents != components)
    {
      reason = "the source array '" + arrayName + "' has " + std::to_string(arrayComponents) +
        " components; it needs 1 or as many as the boundary values (" +
        std::to_string(components) + ")";
      return false;
    }
    if (array->GetNumberOfTuples() != source->GetNumberOfPoints())
    {
      // Values are read one tuple per point: a shorter array would be read
      // past its end.
      reason = "the source array '" + arrayName + "' has " +
        std::to_string(array->GetNumberOfTuples()) + " tuples, but the Source input has " +
        std::to_string(source->GetNumberOfPoints()) + " points";
      return false;
    }
    for (vtkIdType t = 0; t < array->GetNumberOfTuples(); ++t)
    {
      for (int c = 0; c < array->GetNumberOfComponents(); ++c)
      {
        if (!std::isfinite(array->GetComponent(t, c)))
        {
          reason = "the source array has NaN or infinite values";
          return false;
        }
      }
    }
    if (auto* poly = vtkPolyData::SafeDownCast(source))
    {
      if (differentiate && poly->GetNumberOfCells() > 0)
      {
        reason = std::string("point and curve sources (a vtkPolyData Source) have no ") +
          SourceOperatorName(op) + "; give the vector field on an image or another dataset";
        return false;
      }
      if (!ConvertConcentrated<DIM>(poly, array, components, out, reason))
      {
        return false;
      }
    }
    else if (auto* image = vtkImageData::SafeDownCast(source))
    {
      dataset = MakeImageSource<DIM>(image, array, fieldComponents, planeZ);
    }
    else
    {
      dataset = MakeDataSetSource<DIM>(source, array, fieldComponents, planeZ);
    }
  }

  VolumeSourceFactory<DIM> parsed;
  if (!expression.empty())
  {
    const int expressionComponents = ExpressionComponents(expression, reason);
    if (expressionComponents == 0)
    {
      reason = "the SourceExpression '" + expression + "' does not parse: " + reason;
      return false;
    }
    if (differentiate && expressionComponents != 3)
    {
      reason = "the SourceExpression '" + expression + "' is a number; its " +
        SourceOperatorName(op) + " needs a vector field, written with iHat, jHat and kHat " +
        "(e.g. 'y*iHat - x*jHat')";
      return false;
    }
    if (!differentiate && expressionComponents == 3 && components != 3)
    {
      reason = "the SourceExpression '" + expression + "' is a vector; the boundary values have " +
        std::to_string(components) + " components (a vector source needs 3)";
      return false;
    }
    if (!dataset)
    {
      fieldComponents = differentiate ? 3 : components;
    }
    // Parsed once here: every thread's block makes its own source.
    const bool constant = !ExpressionReadsPosition(expression);
    parsed = [expression, fieldComponents, planeZ, constant](
               double lengthScale) -> std::unique_ptr<VolumeSource<DIM>> {
      auto volume =
        std::make_unique<ExpressionSource<DIM>>(expression, fieldComponents, planeZ, constant);
      // Central differences with a step of 1e-5 of the problem's size:
      // small against the domain, large against rounding for points within
      // a few diagonals of it. Without a length scale the base class's step,
      // 1e-5·max(1, |y|∞) (relative to the point's distance from the
      // origin), stays.
      if (lengthScale > 0.0 && std::isfinite(lengthScale))
      {
        volume->SetDifferenceStep(1e-5 * lengthScale);
      }
      return volume;
    };
  }

  VolumeSourceFactory<DIM> field;
  if (dataset && parsed)
  {
    field = [dataset, parsed, fieldComponents](
              double lengthScale) -> std::unique_ptr<VolumeSource<DIM>> {
      return std::make_unique<SumSource<DIM>>(
        dataset(lengthScale), parsed(lengthScale), fieldComponents);
    };
  }
  else
  {
    field = dataset ? dataset : parsed;
  }
  if (field && differentiate)
  {
    out.MakeVolume = [field, fieldComponents, op](
                       double lengthScale) -> std::unique_ptr<VolumeSource<DIM>> {
      return std::make_unique<DifferentialOperatorSource<DIM>>(
        field(lengthScale), fieldComponents, op);
    };
  }
  else
  {
    out.MakeVolume = field;
  }
  return true;
}

template <int DIM>
std::function<std::unique_ptr<VolumeSource<DIM>>()> MakeExpressionListFactory(
  const std::vector<std::string>& expressions, double planeZ)
{
  return [expressions, planeZ]() -> std::unique_ptr<VolumeSource<DIM>> {
    return std::make_unique<ExpressionListSource<DIM>>(expressions, planeZ);
  };
}

template std::function<std::unique_ptr<VolumeSource<2>>()> MakeExpressionListFactory<2>(
  const std::vector<std::string>&, double);
template std::function<std::unique_ptr<VolumeSource<3>>()> MakeExpressionListFactory<3>(
  const std::vector<std::string>&, double);

template bool ConvertSource<2>(vtkDataSet*, vtkDataArray*, const std::string&, int, double,
  SourceSet<2>&, std::string&, SourceOperator);
template bool ConvertSource<3>(vtkDataSet*, vtkDataArray*, const std::string&, int, double,
  SourceSet<3>&, std::string&, SourceOperator);
} // namespace gridfree
