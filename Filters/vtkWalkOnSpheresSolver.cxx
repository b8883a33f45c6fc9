#include "vtkWalkOnSpheresSolver.h"

#include "GridFreeBoundaryConversion.h"
#include "ParallelExecution.h"
#include "RunningStatistics.h"
#include "WalkOnSpheres.h"

#include "vtkAbstractArray.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <array>
#include <chrono>
#include <limits>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresSolver);

namespace
{
constexpr int BoundaryPort = 0;
constexpr int ProbePort = 1;

vtkSmartPointer<vtkDoubleArray> MakeArray(const std::string& name, int components, vtkIdType tuples)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  // Points not reached (abort) stay NaN, never a plausible-looking zero.
  array->Fill(std::numeric_limits<double>::quiet_NaN());
  return array;
}

void AddFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}
} // namespace

// Runs the estimator of one dimension over the probe points and fills the
// output arrays. Lives here, not in the core, because it moves data between
// VTK arrays and the core's plain types.
template <int DIM>
class vtkWalkOnSpheresSolverRunner
{
public:
  static bool Run(vtkWalkOnSpheresSolver* self, vtkPolyData* boundary, vtkDataArray* values,
    bool cellData, vtkDataSet* probe, vtkDataSet* output, const std::string& name)
  {
    gridfree::Boundary<DIM> geometry;
    gridfree::BoundaryConversionReport report;
    std::string reason;
    if (!gridfree::ConvertBoundary<DIM>(boundary, values, cellData, geometry, report, reason))
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the Boundary input: " << reason << ".");
      return false;
    }
    if (report.IgnoredLowerDimensionalCells > 0)
    {
      vtkWarningWithObjectMacro(self, << "Ignored " << report.IgnoredLowerDimensionalCells
                                      << " boundary cells of lower dimension than the "
                                      << DIM << "D problem (vertices"
                                      << (DIM == 3 ? " and lines" : "") << ").");
    }
    if (report.SkippedCells > 0)
    {
      vtkWarningWithObjectMacro(
        self, << "Skipped " << report.SkippedCells << " boundary cells with too few points.");
    }

    gridfree::WalkSettings settings;
    const double diagonal = geometry.Diagonal();
    settings.Epsilon = self->EpsilonIsRelative ? self->Epsilon * diagonal : self->Epsilon;
    if (!(settings.Epsilon > 0.0))
    {
      vtkErrorWithObjectMacro(self, << "Epsilon must be positive (got " << settings.Epsilon
                                    << " in world units; boundary diagonal " << diagonal << ").");
      return false;
    }
    settings.MaxSteps = self->MaxSteps;

    const vtkIdType numPoints = probe->GetNumberOfPoints();
    const int nc = geometry.Components();
    std::vector<std::array<double, 3>> points(static_cast<std::size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      probe->GetPoint(i, points[i].data());
    }

    auto mean = MakeArray(name, nc, numPoints);
    auto variance = MakeArray(name + "_Variance", nc, numPoints);
    auto steps = MakeArray("WalkSteps", 1, numPoints);
    auto escaped = MakeArray("EscapedFraction", 1, numPoints);
    auto truncated = MakeArray("TruncatedFraction", 1, numPoints);
    double* meanPtr = mean->GetPointer(0);
    double* variancePtr = variance->GetPointer(0);
    double* stepsPtr = steps->GetPointer(0);
    double* escapedPtr = escaped->GetPointer(0);
    double* truncatedPtr = truncated->GetPointer(0);

    const int walks = self->WalksPerPoint;
    const std::uint64_t seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(self->Seed));
    std::atomic<std::uint64_t> totalSteps{ 0 }, totalEscaped{ 0 }, totalTruncated{ 0 },
      totalWalks{ 0 };

    const auto start = std::chrono::steady_clock::now();
    const bool completed = gridfree::ParallelForWithProgress(
      static_cast<std::size_t>(numPoints), self->NumberOfThreads,
      [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
        gridfree::LaplaceWalkOnSpheres<DIM> estimator(geometry, settings);
        gridfree::RunningStatistics stats(nc);
        gridfree::WalkCounters sum;
        for (std::size_t i = begin; i < end && !cancel.load(std::memory_order_relaxed); ++i)
        {
          stats.Reset();
          gridfree::WalkCounters counters;
          estimator.EstimatePoint(points[i].data(), seed, 0, walks, stats, counters);
          for (int c = 0; c < nc; ++c)
          {
            meanPtr[i * nc + c] = stats.GetMean(c);
            variancePtr[i * nc + c] = stats.VarianceOfMean(c);
          }
          stepsPtr[i] = counters.MeanSteps();
          escapedPtr[i] = counters.EscapedFraction();
          truncatedPtr[i] = counters.TruncatedFraction();
          sum.Walks += counters.Walks;
          sum.Steps += counters.Steps;
          sum.Escaped += counters.Escaped;
          sum.Truncated += counters.Truncated;
        }
        totalWalks += sum.Walks;
        totalSteps += sum.Steps;
        totalEscaped += sum.Escaped;
        totalTruncated += sum.Truncated;
      },
      [self](double fraction) {
        self->UpdateProgress(fraction);
        return !self->GetAbortExecute();
      });
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    self->LastNumberOfWalks = static_cast<vtkIdType>(totalWalks.load());
    self->LastSolveSeconds = seconds;
    self->LastDimension = DIM;

    vtkPointData* pd = output->GetPointData();
    pd->AddArray(mean);
    pd->AddArray(variance);
    pd->AddArray(steps);
    pd->AddArray(escaped);
    pd->AddArray(truncated);
    pd->SetActiveScalars(mean->GetName());

    vtkFieldData* fd = output->GetFieldData();
    AddFieldValue(fd, "TotalWalks", static_cast<double>(totalWalks.load()));
    AddFieldValue(fd, "TotalSteps", static_cast<double>(totalSteps.load()));
    AddFieldValue(fd, "EscapedWalks", static_cast<double>(totalEscaped.load()));
    AddFieldValue(fd, "TruncatedWalks", static_cast<double>(totalTruncated.load()));
    AddFieldValue(fd, "SolveSeconds", seconds);

    if (!completed)
    {
      vtkWarningWithObjectMacro(self, << "Solve aborted: points not reached are NaN.");
      return true;
    }
    if (totalEscaped > 0)
    {
      vtkWarningWithObjectMacro(self, << totalEscaped.load() << " of " << totalWalks.load()
                                      << " walks left the region enclosed by the boundary and "
                                         "were counted as 0 (see EscapedFraction).");
    }
    if (totalTruncated > 0)
    {
      vtkWarningWithObjectMacro(self, << totalTruncated.load() << " of " << totalWalks.load()
                                      << " walks reached MaxSteps = " << self->MaxSteps
                                      << " and were stopped (see TruncatedFraction).");
    }
    return true;
  }
};

//------------------------------------------------------------------------------
vtkWalkOnSpheresSolver::vtkWalkOnSpheresSolver()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

vtkWalkOnSpheresSolver::~vtkWalkOnSpheresSolver() = default;

void vtkWalkOnSpheresSolver::SetBoundaryConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(BoundaryPort, output);
}

void vtkWalkOnSpheresSolver::SetBoundaryData(vtkDataObject* data)
{
  this->SetInputData(BoundaryPort, data);
}

void vtkWalkOnSpheresSolver::SetProbeConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(ProbePort, output);
}

void vtkWalkOnSpheresSolver::SetProbeData(vtkDataObject* data)
{
  this->SetInputData(ProbePort, data);
}

double vtkWalkOnSpheresSolver::GetLastWalksPerSecond() const
{
  return this->LastSolveSeconds > 0.0
    ? static_cast<double>(this->LastNumberOfWalks) / this->LastSolveSeconds
    : 0.0;
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresSolver::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == BoundaryPort)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  }
  return 1;
}

//------------------------------------------------------------------------------
// The output is a copy of the probe's structure: make it the probe's type.
int vtkWalkOnSpheresSolver::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  if (!probe)
  {
    return 1; // reported in RequestData
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataSet* output = vtkDataSet::GetData(outInfo);
  if (!output || !output->IsA(probe->GetClassName()))
  {
    vtkDataSet* fresh = probe->NewInstance();
    outInfo->Set(vtkDataObject::DATA_OBJECT(), fresh);
    fresh->FastDelete();
  }
  return 1;
}

//------------------------------------------------------------------------------
// Structured probes (images) keep their extent.
int vtkWalkOnSpheresSolver::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* probeInfo = inputVector[ProbePort]->GetInformationObject(0);
  if (!probeInfo)
  {
    return 1;
  }
  outInfo->CopyEntry(probeInfo, vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->CopyEntry(probeInfo, vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  if (probeInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(),
      probeInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  else
  {
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  }
  outInfo->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

//------------------------------------------------------------------------------
// Every piece needs the whole boundary; the probe is split as requested.
int vtkWalkOnSpheresSolver::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* boundaryInfo = inputVector[BoundaryPort]->GetInformationObject(0);
  vtkInformation* probeInfo = inputVector[ProbePort]->GetInformationObject(0);
  if (boundaryInfo)
  {
    boundaryInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    boundaryInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    boundaryInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    if (boundaryInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      boundaryInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
        boundaryInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    }
  }
  if (probeInfo)
  {
    probeInfo->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
    probeInfo->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
    probeInfo->CopyEntry(
      outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS());
    probeInfo->CopyEntry(outInfo, vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresSolver::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  this->LastDimension = 0;

  vtkPolyData* boundary = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!boundary)
  {
    vtkErrorMacro(<< "No Boundary input: connect a vtkPolyData with boundary values to port 0.");
    return 0;
  }
  if (!probe || !output)
  {
    vtkErrorMacro(<< "No Probe input: connect the dataset to solve on to port 1.");
    return 0;
  }

  // The output is the probe, with its arrays, plus the solution arrays.
  output->CopyStructure(probe);
  output->GetPointData()->PassData(probe->GetPointData());
  output->GetCellData()->PassData(probe->GetCellData());
  output->GetFieldData()->PassData(probe->GetFieldData());

  std::string reason;
  const int dimension = gridfree::DetectBoundaryDimension(boundary, reason);
  if (dimension == 0)
  {
    vtkErrorMacro(<< "Cannot use the Boundary input: " << reason << ".");
    return 0;
  }

  // The boundary values: the selected array, if one was selected.
  int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  const bool selected = arrayInfo->Has(vtkDataObject::FIELD_NAME()) ||
    arrayInfo->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE());
  vtkDataArray* values =
    selected ? this->GetInputArrayToProcess(0, boundary, association) : nullptr;
  const char* requested =
    arrayInfo->Has(vtkDataObject::FIELD_NAME()) ? arrayInfo->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (!values && requested && *requested)
  {
    vtkAbstractArray* any = boundary->GetPointData()->GetAbstractArray(requested);
    if (!any)
    {
      any = boundary->GetCellData()->GetAbstractArray(requested);
    }
    if (any)
    {
      vtkErrorMacro(<< "The boundary value array '" << requested << "' is a "
                    << any->GetClassName()
                    << ", not a numeric array: choose a numeric point or cell array.");
    }
    else
    {
      vtkErrorMacro(<< "The boundary has no point or cell array named '" << requested << "'.");
    }
    return 0;
  }
  if (!values)
  {
    // No selection: fall back to the active scalars, points first.
    association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    values = boundary->GetPointData()->GetScalars();
    if (!values)
    {
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
      values = boundary->GetCellData()->GetScalars();
    }
  }
  if (!values)
  {
    vtkErrorMacro(<< "No boundary values: select a numeric point or cell array of the "
                     "Boundary input with SetInputArrayToProcess(0, 0, 0, association, name).");
    return 0;
  }
  const bool cellData = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS && !cellData)
  {
    vtkErrorMacro(<< "Boundary values must be point data or cell data.");
    return 0;
  }

  // Non-finite boundary data would silently poison every walk that ends near it.
  vtkIdType nonFinite = 0;
  for (vtkIdType t = 0; t < values->GetNumberOfTuples(); ++t)
  {
    for (int c = 0; c < values->GetNumberOfComponents(); ++c)
    {
      nonFinite += std::isfinite(values->GetComponent(t, c)) ? 0 : 1;
    }
  }
  const std::string name =
    values->GetName() && *values->GetName() ? values->GetName() : std::string("Solution");
  if (nonFinite > 0)
  {
    vtkErrorMacro(<< "The boundary value array '" << name << "' has " << nonFinite
                  << " NaN or infinite values: boundary values must be finite.");
    return 0;
  }

  if (probe->GetNumberOfPoints() == 0)
  {
    vtkWarningMacro(<< "The Probe input has no points: there is nothing to solve.");
    return 1;
  }

  bool ok = false;
  try
  {
    ok = dimension == 2
      ? vtkWalkOnSpheresSolverRunner<2>::Run(this, boundary, values, cellData, probe, output, name)
      : vtkWalkOnSpheresSolverRunner<3>::Run(this, boundary, values, cellData, probe, output, name);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Walk on spheres failed: " << e.what());
    ok = false;
  }
  this->UpdateProgress(1.0);
  return ok ? 1 : 0;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresSolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WalksPerPoint: " << this->WalksPerPoint << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "EpsilonIsRelative: " << (this->EpsilonIsRelative ? "On" : "Off") << "\n";
  os << indent << "MaxSteps: " << this->MaxSteps << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastNumberOfWalks: " << this->LastNumberOfWalks << "\n";
  os << indent << "LastSolveSeconds: " << this->LastSolveSeconds << "\n";
  os << indent << "LastDimension: " << this->LastDimension << "\n";
}
