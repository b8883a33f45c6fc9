#include "vtkWalkOnSpheresDenoiser.h"

#include "GridFreeArrays.h"

#include <gridfree/applications/JointBilateralDenoising.h>
#include <gridfree/execution/ParallelExecution.h>

#include "vtkAbstractArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStaticPointLocator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresDenoiser);

namespace
{
constexpr int ValueIndex = 0;
constexpr int VarianceIndex = 1;
constexpr int GuideIndex = 2;

// The typical spacing is the median over this many points at most: enough
// for a stable median, negligible next to the filter itself.
constexpr vtkIdType kSpacingSamples = 1000;
// Coincident points (duplicates) are skipped when looking for a point's
// nearest distinct neighbour among this many closest points.
constexpr int kSpacingCandidates = 8;

// Largest (max - min) over the components of a row-major array, ignoring
// non-finite numbers; 0 when there are none.
double LargestRange(const std::vector<double>& values, int components)
{
  double largest = 0.0;
  for (int c = 0; c < components; ++c)
  {
    double low = std::numeric_limits<double>::infinity();
    double high = -low;
    for (std::size_t i = static_cast<std::size_t>(c); i < values.size(); i += components)
    {
      if (std::isfinite(values[i]))
      {
        low = std::min(low, values[i]);
        high = std::max(high, values[i]);
      }
    }
    if (low <= high)
    {
      largest = std::max(largest, high - low);
    }
  }
  return largest;
}

double SquaredDistance(const double* a, const double* b)
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]);
}

// Median distance from a point to its nearest distinct neighbour, over up
// to kSpacingSamples points evenly strided through the ids; 0 when no
// sampled point has one (a single point, or all points coincide).
double TypicalSpacing(
  vtkStaticPointLocator* locator, const double* xyz, const std::vector<char>& finite)
{
  const vtkIdType n = static_cast<vtkIdType>(finite.size());
  const vtkIdType samples = std::min(n, kSpacingSamples);
  vtkNew<vtkIdList> closest;
  std::vector<double> distances;
  for (vtkIdType s = 0; s < samples; ++s)
  {
    const vtkIdType i = s * n / samples;
    if (!finite[static_cast<std::size_t>(i)])
    {
      continue;
    }
    const double* x = xyz + 3 * static_cast<std::size_t>(i);
    locator->FindClosestNPoints(kSpacingCandidates, x, closest);
    double nearest = std::numeric_limits<double>::infinity();
    for (vtkIdType j : *closest)
    {
      const double d2 = SquaredDistance(x, xyz + 3 * static_cast<std::size_t>(j));
      if (finite[static_cast<std::size_t>(j)] && d2 > 0.0)
      {
        nearest = std::min(nearest, d2);
      }
    }
    if (std::isfinite(nearest))
    {
      distances.push_back(std::sqrt(nearest));
    }
  }
  if (distances.empty())
  {
    return 0.0;
  }
  auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  return *middle;
}

// A copy of `array` under another name that shares its memory where the
// array type allows it: the input's array itself must keep its name.
vtkSmartPointer<vtkDataArray> Renamed(vtkDataArray* array, const std::string& name)
{
  vtkSmartPointer<vtkDataArray> copy;
  copy.TakeReference(array->NewInstance());
  copy->ShallowCopy(array);
  copy->SetName(name.c_str());
  return copy;
}
} // namespace

//------------------------------------------------------------------------------
vtkWalkOnSpheresDenoiser::vtkWalkOnSpheresDenoiser() = default;
vtkWalkOnSpheresDenoiser::~vtkWalkOnSpheresDenoiser() = default;

//------------------------------------------------------------------------------
vtkDataArray* vtkWalkOnSpheresDenoiser::FindPointArray(
  int index, vtkDataSet* input, const std::string& fallback, std::string& problem)
{
  problem.clear();
  vtkPointData* pd = input->GetPointData();
  vtkInformation* selection = this->GetInputArrayInformation(index);
  const char* selectedName = selection && selection->Has(vtkDataObject::FIELD_NAME())
    ? selection->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  const bool byName = selectedName && *selectedName;
  const bool byAttribute = selection && selection->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE());

  vtkDataArray* array = nullptr;
  std::string name = byName ? selectedName : fallback;
  if (byName || byAttribute)
  {
    int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    array = this->GetInputArrayToProcess(index, input, association);
    if (array && association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      problem = "the array '" + std::string(array->GetName() ? array->GetName() : "") +
        "' is not point data";
      return nullptr;
    }
  }
  else if (fallback.empty())
  {
    array = pd->GetScalars();
    if (!array)
    {
      problem = "no array is selected and the input has no active point scalars";
      return nullptr;
    }
  }
  else
  {
    array = pd->GetArray(fallback.c_str());
  }

  if (!array)
  {
    if (name.empty())
    {
      problem = "the input has no point array of the selected attribute";
    }
    else if (vtkAbstractArray* other = pd->GetAbstractArray(name.c_str()))
    {
      problem = "the array '" + name + "' is a " + other->GetClassName() + ", not a numeric array";
    }
    else if (input->GetCellData()->GetAbstractArray(name.c_str()))
    {
      problem = "the array '" + name + "' is cell data, not point data";
    }
    else
    {
      problem = "there is no point array named '" + name + "'";
    }
    return nullptr;
  }
  // Point data accepts arrays of any length: reading one tuple per point of
  // a shorter one would read past its end.
  if (array->GetNumberOfTuples() != input->GetNumberOfPoints())
  {
    problem = "the array '" + std::string(array->GetName() ? array->GetName() : "") + "' has " +
      std::to_string(array->GetNumberOfTuples()) + " tuples, but the input has " +
      std::to_string(input->GetNumberOfPoints()) + " points";
    return nullptr;
  }
  return array;
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresDenoiser::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastSpatialSigma = 0.0;
  this->LastGuideSigma = 0.0;
  this->LastDenoiseSeconds = 0.0;
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro(<< "No input: connect a dataset with walk-on-spheres estimates.");
    return 0;
  }

  // The input passes through; the denoised arrays are added at the end, so
  // on any error or abort the output is the input unchanged.
  output->CopyStructure(input);
  output->GetPointData()->PassData(input->GetPointData());
  output->GetCellData()->PassData(input->GetCellData());
  output->GetFieldData()->PassData(input->GetFieldData());

  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints == 0)
  {
    vtkWarningMacro(<< "The input has no points: there is nothing to denoise.");
    return 1;
  }

  std::string problem;
  vtkDataArray* values = this->FindPointArray(ValueIndex, input, "", problem);
  if (!values)
  {
    vtkErrorMacro(<< "No values to denoise: " << problem << ".");
    return 0;
  }
  const std::string name = values->GetName() ? values->GetName() : "";
  if (name.empty())
  {
    vtkErrorMacro(<< "The array to denoise has no name: its output arrays could not be named.");
    return 0;
  }
  const int nc = values->GetNumberOfComponents();
  vtkDataArray* variances = this->FindPointArray(VarianceIndex, input, name + "_Variance", problem);
  if (!variances)
  {
    vtkErrorMacro(<< "No variance for '" << name << "': " << problem
                  << ". Every estimate is weighed by its variance, which the solver outputs as '"
                  << name << "_Variance'.");
    return 0;
  }
  if (variances->GetNumberOfComponents() != nc)
  {
    vtkErrorMacro(<< "The variance array '" << (variances->GetName() ? variances->GetName() : "")
                  << "' has " << variances->GetNumberOfComponents() << " components, but '" << name
                  << "' has " << nc << ": one variance per component is needed.");
    return 0;
  }
  vtkDataArray* guide = nullptr;
  if (this->UseGuide)
  {
    guide = this->FindPointArray(GuideIndex, input, name + "_ClosestBoundaryValue", problem);
    if (!guide)
    {
      vtkWarningMacro(<< "Denoising without a guide: " << problem
                      << ". Select one (the solver outputs '" << name
                      << "_ClosestBoundaryValue') or turn UseGuide off.");
    }
  }
  const auto start = std::chrono::steady_clock::now();

  // Plain copies for the core: values, variances, guide, and the points.
  // Points with non-finite coordinates take part in nothing (they keep their
  // values); the locator sees them at the first finite point (or the origin),
  // so that its bins stay finite.
  const std::size_t n = static_cast<std::size_t>(numPoints);
  const std::vector<double> u = gridfree::ToDoubles(values);
  const std::vector<double> v = gridfree::ToDoubles(variances);
  const std::vector<double> a = guide ? gridfree::ToDoubles(guide) : std::vector<double>();
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(numPoints);
  double* xyz = coordinates->GetPointer(0);
  std::vector<char> finite(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    double* x = xyz + 3 * i;
    input->GetPoint(static_cast<vtkIdType>(i), x);
    finite[i] = std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]) ? 1 : 0;
  }
  const auto firstFinite = std::find(finite.begin(), finite.end(), 1);
  if (firstFinite != finite.end())
  {
    const double* anchor = xyz + 3 * static_cast<std::size_t>(firstFinite - finite.begin());
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!finite[i])
      {
        std::copy_n(anchor, 3, xyz + 3 * i);
      }
    }
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(points);
  // Queries are thread safe once the locator is built on this thread.
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(cloud);
  locator->BuildLocator();

  // The filter's scales in world and guide units.
  const double spacing = this->SpatialSigmaIsRelative ? TypicalSpacing(locator, xyz, finite) : 1.0;
  gridfree::DenoiseSettings settings;
  settings.SpatialSigma = this->SpatialSigma * spacing;
  settings.NeighbourRadius = gridfree::kDenoiseRadiusInSigmas * settings.SpatialSigma;
  settings.VarianceScale = this->VarianceScale;
  if (guide)
  {
    const double scale =
      this->GuideSigmaIsRelative ? LargestRange(a, guide->GetNumberOfComponents()) : 1.0;
    settings.GuideSigma = this->GuideSigma * scale;
  }
  this->LastSpatialSigma = settings.SpatialSigma;
  this->LastGuideSigma = settings.GuideSigma;

  gridfree::DenoiseInput in;
  in.Count = n;
  in.Components = nc;
  in.Values = u.data();
  in.Variances = v.data();
  in.GuideComponents = guide ? guide->GetNumberOfComponents() : 0;
  in.Guide = guide ? a.data() : nullptr;
  const gridfree::JointBilateralDenoiser denoiser(in, settings);
  std::size_t invalid = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    invalid += denoiser.IsValid(i) ? 0 : 1;
  }
  if (invalid > 0)
  {
    vtkWarningMacro(<< invalid << " of " << n << " points have a NaN or infinite value or a NaN, "
                    << "infinite or negative variance: they are left as they are.");
  }

  auto denoised = gridfree::MakeArray(name, nc, numPoints);
  denoised->CopyComponentNames(values);
  auto denoisedVariance = gridfree::MakeArray(name + "_Variance", nc, numPoints);
  double* outValues = denoised->GetPointer(0);
  double* outVariances = denoisedVariance->GetPointer(0);
  const double radius = settings.NeighbourRadius;

  // Each task has its own id list; ids are sorted so that a point's sums do
  // not depend on the locator's bin order.
  auto body = [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
    vtkNew<vtkIdList> found;
    std::vector<vtkIdType> ids;
    auto forEachNeighbour = [&](std::size_t i, const auto& visit) {
      if (!finite[i])
      {
        return;
      }
      const double* x = xyz + 3 * i;
      locator->FindPointsWithinRadius(radius, x, found);
      ids.assign(found->begin(), found->end());
      std::sort(ids.begin(), ids.end());
      for (vtkIdType id : ids)
      {
        const std::size_t j = static_cast<std::size_t>(id);
        if (finite[j])
        {
          visit(j, SquaredDistance(x, xyz + 3 * j));
        }
      }
    };
    for (std::size_t i = begin; i < end && !cancel.load(std::memory_order_relaxed); ++i)
    {
      denoiser.DenoisePoint(i, forEachNeighbour, outValues + i * nc, outVariances + i * nc);
    }
  };
  // Progress and abort live on this thread (ParallelExecution.h).
  auto progress = [this](double fraction) {
    this->UpdateProgress(fraction);
    return !this->GetAbortExecute();
  };
  bool completed = false;
  try
  {
    completed = gridfree::ParallelForWithProgress(n, this->NumberOfThreads, body, progress);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Denoising failed: " << e.what());
    return 0;
  }
  if (!completed)
  {
    vtkWarningMacro(<< "Denoising aborted: the output is the input unchanged.");
    return 1;
  }
  this->LastDenoiseSeconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  vtkPointData* pd = output->GetPointData();
  const bool wasActive = input->GetPointData()->GetScalars() == values;
  // AddArray replaces arrays by name: `name` and `name`_Variance take the
  // place of the input's, which are kept under the _Noisy names.
  pd->AddArray(Renamed(values, name + "_Noisy"));
  pd->AddArray(Renamed(variances, name + "_Noisy_Variance"));
  pd->AddArray(denoised);
  pd->AddArray(denoisedVariance);
  if (wasActive)
  {
    pd->SetActiveScalars(name.c_str());
  }
  gridfree::AddFieldValue(output->GetFieldData(), "DenoiseSeconds", this->LastDenoiseSeconds);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresDenoiser::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SpatialSigma: " << this->SpatialSigma << "\n";
  os << indent << "SpatialSigmaIsRelative: " << (this->SpatialSigmaIsRelative ? "On" : "Off")
     << "\n";
  os << indent << "VarianceScale: " << this->VarianceScale << "\n";
  os << indent << "GuideSigma: " << this->GuideSigma << "\n";
  os << indent << "GuideSigmaIsRelative: " << (this->GuideSigmaIsRelative ? "On" : "Off") << "\n";
  os << indent << "UseGuide: " << (this->UseGuide ? "On" : "Off") << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastSpatialSigma: " << this->LastSpatialSigma << "\n";
  os << indent << "LastGuideSigma: " << this->LastGuideSigma << "\n";
  os << indent << "LastDenoiseSeconds: " << this->LastDenoiseSeconds << "\n";
}
