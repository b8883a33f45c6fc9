#include "vtkMovingLeastSquaresInterpolator.h"

#include "GridFreeArrays.h"

#include "GridFreeWholeInputRequest.h"

#include "GridFreeVisibleNeighbours.h"
#include <gridfree/applications/MovingLeastSquares.h>
#include <gridfree/execution/ParallelExecution.h>

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMovingLeastSquaresInterpolator);

namespace
{
constexpr int TargetPort = 0;
constexpr int SourcePort = 1;
constexpr int BoundaryPort = 2;

// The samples' arrays as flat double tables in the core's layout.
struct SampleTable
{
  int Components = 0;
  std::vector<double> Values, ValueVariances, Gradients, GradientVariances;
  bool HasVariances = false;
  bool HasGradients = false;
  bool HasGradientVariances = false;
};

// Copies `array` (n tuples of `components`) into `out`; false if it does not
// have that shape.
bool Flatten(vtkDataArray* array, vtkIdType n, int components, std::vector<double>& out)
{
  if (!array || array->GetNumberOfTuples() != n || array->GetNumberOfComponents() != components)
  {
    return false;
  }
  out = gridfree::ToDoubles(array);
  return true;
}

} // namespace

//------------------------------------------------------------------------------
vtkMovingLeastSquaresInterpolator::vtkMovingLeastSquaresInterpolator()
{
  this->SetNumberOfInputPorts(3);
  this->SetInputArrayToProcess(0, SourcePort, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
    vtkDataSetAttributes::SCALARS);
}

void vtkMovingLeastSquaresInterpolator::SetSourceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(SourcePort, output);
}
void vtkMovingLeastSquaresInterpolator::SetSourceData(vtkDataObject* data)
{
  this->SetInputData(SourcePort, data);
}
void vtkMovingLeastSquaresInterpolator::SetBoundaryConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(BoundaryPort, output);
}
void vtkMovingLeastSquaresInterpolator::SetBoundaryData(vtkDataObject* data)
{
  this->SetInputData(BoundaryPort, data);
}

int vtkMovingLeastSquaresInterpolator::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == BoundaryPort)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  }
  return 1;
}

// The samples and the boundary are needed whole; the target may stream.
int vtkMovingLeastSquaresInterpolator::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  for (int port : { SourcePort, BoundaryPort })
  {
    gridfree::RequestWholeInput(inputVector[port]->GetInformationObject(0));
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMovingLeastSquaresInterpolator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  const auto start = std::chrono::steady_clock::now();
  this->LastNumberOfUnreachedPoints = 0;
  vtkDataSet* target = vtkDataSet::GetData(inputVector[TargetPort], 0);
  vtkDataSet* samples = vtkDataSet::GetData(inputVector[SourcePort], 0);
  vtkPolyData* boundary = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!target || !output)
  {
    vtkErrorMacro(<< "No target: connect the dataset to interpolate onto to input 0.");
    return 0;
  }
  output->CopyStructure(target);
  output->GetPointData()->PassData(target->GetPointData());
  output->GetCellData()->PassData(target->GetCellData());
  output->GetFieldData()->PassData(target->GetFieldData());
  if (!samples)
  {
    vtkErrorMacro(<< "No samples: connect a dataset with the sampled values to the Source "
                     "input (port 1).");
    return 0;
  }
  const vtkIdType numSamples = samples->GetNumberOfPoints();
  if (numSamples == 0)
  {
    vtkErrorMacro(<< "The Source input has no points: nothing to interpolate from.");
    return 0;
  }
  vtkDataArray* values = this->GetInputArrayToProcess(0, samples);
  bool onPoints = false;
  for (int i = 0; values && i < samples->GetPointData()->GetNumberOfArrays(); ++i)
  {
    onPoints = onPoints || samples->GetPointData()->GetAbstractArray(i) == values;
  }
  if (!values || !onPoints)
  {
    vtkErrorMacro(<< "No value array selected on the Source input's points: select one with "
                     "SetInputArrayToProcess(0, 1, 0, POINTS, name).");
    return 0;
  }
  if (values->GetNumberOfTuples() != numSamples)
  {
    vtkErrorMacro(<< "The value array has " << values->GetNumberOfTuples() << " tuples for "
                  << numSamples << " sample points.");
    return 0;
  }
  const std::string name = values->GetName() ? values->GetName() : "Solution";
  const int nc = values->GetNumberOfComponents();

  // The samples in the core's layout. Gradients have 3 numbers per
  // component, as the solver writes them (zero z in 2D).
  SampleTable table;
  table.Components = nc;
  Flatten(values, numSamples, nc, table.Values);
  vtkPointData* spd = samples->GetPointData();
  table.HasVariances =
    Flatten(spd->GetArray((name + "_Variance").c_str()), numSamples, nc, table.ValueVariances);
  if (this->UseGradients && this->PolynomialDegree > 0)
  {
    table.HasGradients =
      Flatten(spd->GetArray((name + "_Gradient").c_str()), numSamples, 3 * nc, table.Gradients);
    table.HasGradientVariances = table.HasGradients &&
      Flatten(spd->GetArray((name + "_Gradient_Variance").c_str()), numSamples, 3 * nc,
        table.GradientVariances);
  }
  std::vector<gridfree::Vec<3>> positions(static_cast<std::size_t>(numSamples));
  auto samplePoints = vtkSmartPointer<vtkPoints>::New();
  samplePoints->SetDataTypeToDouble();
  samplePoints->SetNumberOfPoints(numSamples);
  for (vtkIdType i = 0; i < numSamples; ++i)
  {
    double p[3];
    samples->GetPoint(i, p);
    samplePoints->SetPoint(i, p);
    positions[static_cast<std::size_t>(i)] = gridfree::Vec<3>(p[0], p[1], p[2]);
  }

  gridfree::VisibleNeighbours neighbours;
  neighbours.SetSamples(samplePoints);
  if (this->UseVisibility && boundary)
  {
    std::string reason;
    if (!neighbours.SetBoundary(boundary, reason))
    {
      vtkErrorMacro(<< "The Boundary input cannot block visibility: " << reason << ".");
      return 0;
    }
  }

  const vtkIdType n = target->GetNumberOfPoints();
  auto value = gridfree::MakeArray(name, nc, n);
  auto gradient = gridfree::MakeArray(name + "_Gradient", 3 * nc, n);
  auto variance = table.HasVariances ? gridfree::MakeArray(name + "_Variance", nc, n) : nullptr;
  auto used = vtkSmartPointer<vtkIntArray>::New();
  used->SetName("MLSNeighbors");
  used->SetNumberOfTuples(n);
  std::vector<std::array<double, 3>> targetPoints(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    target->GetPoint(i, targetPoints[static_cast<std::size_t>(i)].data());
  }

  gridfree::MlsSettings settings;
  settings.Degree = this->PolynomialDegree;
  settings.GradientWeight = table.HasGradients ? this->GradientWeight : 0.0;
  const int k = this->NumberOfNeighbors;
  std::atomic<vtkIdType> unreached{ 0 };
  auto body = [&](std::size_t from, std::size_t to, const std::atomic<bool>& cancel) {
    gridfree::MovingLeastSquares<3> mls(settings, nc);
    gridfree::VisibleNeighbours::Scratch scratch;
    std::vector<vtkIdType> ids;
    std::vector<gridfree::Vec<3>> p;
    std::vector<double> u, uVar, g, gVar;
    std::vector<double> outValue(nc), outGradient(3 * nc), outVariance(nc);
    for (std::size_t i = from; i < to && !cancel.load(std::memory_order_relaxed); ++i)
    {
      const auto& x = targetPoints[i];
      neighbours.Find(x.data(), k, scratch, ids);
      p.clear();
      u.clear();
      uVar.clear();
      g.clear();
      gVar.clear();
      for (vtkIdType id : ids)
      {
        const auto s = static_cast<std::size_t>(id);
        p.push_back(positions[s]);
        for (int c = 0; c < nc; ++c)
        {
          u.push_back(table.Values[s * nc + c]);
          if (table.HasVariances)
          {
            uVar.push_back(table.ValueVariances[s * nc + c]);
          }
          for (int a = 0; a < 3 && table.HasGradients; ++a)
          {
            g.push_back(table.Gradients[(s * nc + c) * 3 + a]);
            if (table.HasGradientVariances)
            {
              gVar.push_back(table.GradientVariances[(s * nc + c) * 3 + a]);
            }
          }
        }
      }
      gridfree::MlsNeighbours<3> data;
      data.Count = static_cast<int>(ids.size());
      data.Positions = p.data();
      data.Values = u.data();
      data.ValueVariances = table.HasVariances ? uVar.data() : nullptr;
      data.Gradients = table.HasGradients ? g.data() : nullptr;
      data.GradientVariances = table.HasGradientVariances ? gVar.data() : nullptr;
      const bool fitted = mls.Fit(gridfree::Vec<3>(x[0], x[1], x[2]), data, outValue.data(),
        outGradient.data(), table.HasVariances ? outVariance.data() : nullptr);
      if (!fitted)
      {
        unreached.fetch_add(1, std::memory_order_relaxed);
      }
      const auto id = static_cast<vtkIdType>(i);
      used->SetValue(id, data.Count);
      for (int c = 0; c < nc; ++c)
      {
        value->SetTypedComponent(id, c, outValue[c]);
        if (variance)
        {
          variance->SetTypedComponent(id, c, outVariance[c]);
        }
        for (int a = 0; a < 3; ++a)
        {
          gradient->SetTypedComponent(id, 3 * c + a, outGradient[3 * c + a]);
        }
      }
    }
  };
  const bool completed = gridfree::ParallelForWithProgress(
    static_cast<std::size_t>(n), this->NumberOfThreads, body,
    [this](double fraction) {
      this->UpdateProgress(fraction);
      return !this->CheckAbort();
    },
    0.1, 64);
  if (!completed)
  {
    vtkWarningMacro(<< "Interpolation aborted: points not reached are NaN.");
  }
  this->LastNumberOfUnreachedPoints = unreached.load();
  if (this->LastNumberOfUnreachedPoints > 0)
  {
    vtkWarningMacro(<< this->LastNumberOfUnreachedPoints << " of " << n
                    << " target points see no sample (walled off by the boundary): their "
                       "values are NaN. Add samples on their side of the boundary.");
  }

  vtkPointData* pd = output->GetPointData();
  pd->AddArray(value);
  pd->AddArray(gradient);
  if (variance)
  {
    pd->AddArray(variance);
  }
  pd->AddArray(used);
  pd->SetActiveScalars(value->GetName());
  if (nc == 1)
  {
    pd->SetActiveVectors(gradient->GetName());
  }
  gridfree::AddFieldValue(output->GetFieldData(), "InterpolationSeconds",
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMovingLeastSquaresInterpolator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfNeighbors: " << this->NumberOfNeighbors << "\n";
  os << indent << "PolynomialDegree: " << this->PolynomialDegree << "\n";
  os << indent << "UseGradients: " << this->UseGradients << "\n";
  os << indent << "GradientWeight: " << this->GradientWeight << "\n";
  os << indent << "UseVisibility: " << this->UseVisibility << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
