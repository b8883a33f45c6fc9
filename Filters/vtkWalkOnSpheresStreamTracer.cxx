#include "vtkWalkOnSpheresStreamTracer.h"

#include "GridFreeArrays.h"
#include "GridFreePointNumbers.h"

#include <gridfree/applications/GradientStreamlines.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresStreamTracer);

namespace
{
constexpr int SeedsPort = 1;

static_assert(vtkWalkOnSpheresStreamTracer::OUT_OF_DOMAIN ==
    static_cast<int>(gridfree::StreamEnd::OutOfDomain) &&
  vtkWalkOnSpheresStreamTracer::OUT_OF_LENGTH == static_cast<int>(gridfree::StreamEnd::OutOfLength) &&
  vtkWalkOnSpheresStreamTracer::OUT_OF_STEPS == static_cast<int>(gridfree::StreamEnd::OutOfSteps) &&
  vtkWalkOnSpheresStreamTracer::STAGNATION == static_cast<int>(gridfree::StreamEnd::Stagnation) &&
  vtkWalkOnSpheresStreamTracer::CLOSE_TO_BOUNDARY ==
    static_cast<int>(gridfree::StreamEnd::CloseToBoundary));
} // namespace

//------------------------------------------------------------------------------
vtkWalkOnSpheresStreamTracer::vtkWalkOnSpheresStreamTracer()
{
  // A line's noise does not average out along it: many walks by default.
  this->SetWalksPerPoint(1024);
}

void vtkWalkOnSpheresStreamTracer::SetSeedsConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(SeedsPort, output);
}
void vtkWalkOnSpheresStreamTracer::SetSeedsData(vtkDataObject* data)
{
  this->SetInputData(SeedsPort, data);
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresStreamTracer::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfEstimates = 0;
  vtkDataObject* boundary = vtkDataObject::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* seeds = vtkDataSet::GetData(inputVector[SeedsPort], 0);
  vtkDataSet* source = vtkDataSet::GetData(inputVector[SourcePort], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!seeds || !output)
  {
    vtkErrorMacro(<< "No Seeds input: connect a dataset whose points start the lines to port 1.");
    return 0;
  }
  if (seeds->GetNumberOfPoints() == 0)
  {
    vtkWarningMacro(<< "The Seeds input has no points: no lines.");
    return 1;
  }

  // The box lines must stay in (the boundary's, enlarged by a step), and
  // the length scale of relative steps.
  gridfree::StreamlineSettings lineSettings;
  double bounds[6] = { 0, -1, 0, -1, 0, -1 };
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(boundary))
  {
    composite->GetBounds(bounds);
  }
  else if (auto* poly = vtkPolyData::SafeDownCast(boundary))
  {
    poly->GetBounds(bounds);
  }
  lineSettings.HaveBox = bounds[0] <= bounds[1];
  if (!lineSettings.HaveBox)
  {
    seeds->GetBounds(bounds);
  }
  std::copy_n(bounds, 6, lineSettings.Box.begin());
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const double scale = this->StepLengthIsRelative ? (diagonal > 0.0 ? diagonal : 1.0) : 1.0;
  lineSettings.StepLength = this->StepLength * scale;
  lineSettings.MaximumLength = this->MaximumPropagation * scale;
  lineSettings.MaximumSteps = this->MaximumNumberOfSteps;
  lineSettings.TerminalSpeed = this->TerminalSpeed;
  lineSettings.Integrator = this->IntegratorType == RUNGE_KUTTA_4
    ? gridfree::StreamIntegrator::RungeKutta4
    : gridfree::StreamIntegrator::Heun;
  lineSettings.Forward = this->IntegrationDirection != BACKWARD;
  lineSettings.Backward = this->IntegrationDirection != FORWARD;

  // The problem, built once for all the lines (an implicit boundary lives
  // around the seeds).
  if (!this->BuildProblem(boundary, source, seeds))
  {
    // An Abort while the coefficients were prepared was reported as a
    // warning: an empty output, not a failed pipeline.
    return this->GetAbortExecute() ? 1 : 0;
  }
  const std::string valueName = this->GetSolutionName();
  double progress = 0.0;
  double seconds = 0.0;
  vtkIdType walks = 0;

  // Estimates at `points`, one batch for all of them, as numbers (the
  // core's): the first component's value and gradient with their
  // variances, whether the gradient is the interior one, the distance to
  // the boundary. False when aborted or when the batch failed (reported).
  auto estimate = [&](const std::vector<gridfree::StreamPoint>& points,
                    std::vector<gridfree::StreamEstimate>& out) {
    gridfree::PointNumbers found;
    const bool completed = this->EstimateNumbersAt(points, found, progress, seconds, walks);
    this->LastNumberOfEstimates += static_cast<vtkIdType>(points.size());
    if (found.Size() != points.size() || !found.HasGradient())
    {
      return false; // the batch failed (reported)
    }
    out.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      gridfree::StreamEstimate& e = out[i];
      e.Value = found.Value(i);
      e.ValueVariance = found.ValueVariance(i);
      for (int k = 0; k < 3; ++k)
      {
        e.Gradient[k] = found.Gradient(i, 0, k);
        e.GradientVariance[k] = found.GradientVariance(i, 0, k);
      }
      e.NearBoundary = found.Status(i) != gridfree::DerivativeStatus::Interior;
      e.Distance = found.Distance[i];
      e.Valid = std::isfinite(e.Value);
    }
    return completed;
  };
  auto reportProgress = [&](double fraction) {
    progress = fraction;
    this->UpdateProgress(progress);
    return !this->GetAbortExecute();
  };

  // The lines (the core's lockstep tracing), one per seed and direction.
  std::vector<gridfree::StreamPoint> seedPoints(
    static_cast<std::size_t>(seeds->GetNumberOfPoints()));
  for (vtkIdType s = 0; s < seeds->GetNumberOfPoints(); ++s)
  {
    seeds->GetPoint(s, seedPoints[static_cast<std::size_t>(s)].data());
  }
  std::vector<gridfree::Streamline> lines;
  const bool completed =
    gridfree::TraceGradientStreamlines(seedPoints, lineSettings, estimate, reportProgress, lines);
  if (this->GetEstimateFailed())
  {
    return 0;
  }
  if (!completed)
  {
    vtkWarningMacro(<< "Tracing aborted: the lines end where they were.");
  }
  // Each distinct warning once (every stage repeats the same ones).
  this->ReportWarnings();
  gridfree::AddFieldValue(output->GetFieldData(), "TotalWalks", static_cast<double>(walks));
  gridfree::AddFieldValue(output->GetFieldData(), "SolveSeconds", seconds);

  // Polylines with the estimates along them, as vtkStreamTracer's output.
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polylines;
  auto makeArray = [](const std::string& name, int components) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfComponents(components);
    return vtkSmartPointer<vtkDoubleArray>(a);
  };
  auto value = makeArray(valueName, 1);
  auto valueVariance = makeArray(valueName + "_Variance", 1);
  auto gradient = makeArray(valueName + "_Gradient", 3);
  auto gradientVariance = makeArray(valueName + "_Gradient_Variance", 3);
  auto time = makeArray("IntegrationTime", 1);
  vtkNew<vtkIntArray> seedIds, reasons;
  seedIds->SetName("SeedIds");
  reasons->SetName("ReasonForTermination");
  for (const gridfree::Streamline& line : lines)
  {
    if (line.Points.size() < 2)
    {
      continue; // vtkStreamTracer drops lines that never left their seed
    }
    polylines->InsertNextCell(static_cast<vtkIdType>(line.Points.size()));
    double arc = 0.0;
    for (std::size_t i = 0; i < line.Points.size(); ++i)
    {
      if (i > 0)
      {
        const gridfree::StreamPoint& a = line.Points[i - 1];
        const gridfree::StreamPoint& b = line.Points[i];
        arc += std::sqrt(
          (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
      }
      polylines->InsertCellPoint(points->InsertNextPoint(line.Points[i].data()));
      const gridfree::StreamEstimate& e = line.Estimates[i];
      value->InsertNextValue(e.Value);
      valueVariance->InsertNextValue(e.ValueVariance);
      gradient->InsertNextTuple(e.Gradient.data());
      gradientVariance->InsertNextTuple(e.GradientVariance.data());
      time->InsertNextValue(line.Sign * arc);
    }
    seedIds->InsertNextValue(static_cast<int>(line.Seed));
    reasons->InsertNextValue(static_cast<int>(line.Reason));
  }
  output->SetPoints(points);
  output->SetLines(polylines);
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(value);
  pd->AddArray(valueVariance);
  pd->AddArray(gradient);
  pd->AddArray(gradientVariance);
  pd->AddArray(time);
  pd->SetActiveScalars(value->GetName());
  pd->SetActiveVectors(gradient->GetName());
  output->GetCellData()->AddArray(seedIds);
  output->GetCellData()->AddArray(reasons);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresStreamTracer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "StepLength: " << this->StepLength << "\n";
  os << indent << "StepLengthIsRelative: " << (this->StepLengthIsRelative ? "On" : "Off")
     << "\n";
  os << indent << "MaximumNumberOfSteps: " << this->MaximumNumberOfSteps << "\n";
  os << indent << "MaximumPropagation: " << this->MaximumPropagation << "\n";
  os << indent << "TerminalSpeed: " << this->TerminalSpeed << "\n";
  os << indent << "IntegrationDirection: " << this->IntegrationDirection << "\n";
  os << indent << "IntegratorType: " << this->IntegratorType << "\n";
  os << indent << "LastNumberOfEstimates: " << this->LastNumberOfEstimates << "\n";
}
