#include "vtkWalkOnSpheresStreamTracer.h"

#include "GridFreeArrays.h"
#include "GridFreeEstimateArrays.h"

#include <gridfree/applications/LockstepStreamlines.h>

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

using Point = std::array<double, 3>;

// What the solver estimated at one point: u, ∇u (of the first component)
// and their variances, and whether the point is closer than epsilon.
struct Estimate
{
  double Value = 0.0;
  double ValueVariance = 0.0;
  Point Gradient = { 0.0, 0.0, 0.0 };
  Point GradientVariance = { 0.0, 0.0, 0.0 };
  double Distance = 0.0; // to the boundary
  bool NearBoundary = false;
  bool Valid = false;
};

// One streamline: its points, the estimates there, and how it ended.
struct Line
{
  vtkIdType Seed = 0;
  double Sign = 1.0; // +1 up the gradient, -1 down
  std::vector<Point> Points;
  std::vector<Estimate> Estimates;
  double Length = 0.0;
  int Reason = 0; // 0 while running
};

// Unit direction s·g/|g|; false where |g| is at most `terminal` or not finite.
bool UnitDirection(const Estimate& e, double sign, double terminal, Point& d)
{
  const double norm = std::sqrt(e.Gradient[0] * e.Gradient[0] + e.Gradient[1] * e.Gradient[1] +
    e.Gradient[2] * e.Gradient[2]);
  if (!(norm > terminal) || !std::isfinite(norm))
  {
    return false;
  }
  for (int k = 0; k < 3; ++k)
  {
    d[k] = sign * e.Gradient[k] / norm;
  }
  return true;
}

Point Advance(const Point& x, double h, const Point& d)
{
  return { x[0] + h * d[0], x[1] + h * d[1], x[2] + h * d[2] };
}
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
  double bounds[6] = { 0, -1, 0, -1, 0, -1 };
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(boundary))
  {
    composite->GetBounds(bounds);
  }
  else if (auto* poly = vtkPolyData::SafeDownCast(boundary))
  {
    poly->GetBounds(bounds);
  }
  const bool haveBox = bounds[0] <= bounds[1];
  if (!haveBox)
  {
    seeds->GetBounds(bounds);
  }
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const double scale = this->StepLengthIsRelative ? (diagonal > 0.0 ? diagonal : 1.0) : 1.0;
  const double h = this->StepLength * scale;
  const double maximumLength = this->MaximumPropagation * scale;
  auto inBox = [&](const Point& p) {
    if (!haveBox)
    {
      return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    }
    for (int k = 0; k < 3; ++k)
    {
      if (!(p[k] >= bounds[2 * k] - h && p[k] <= bounds[2 * k + 1] + h))
      {
        return false;
      }
    }
    return true;
  };

  // The problem, built once for all the lines (an implicit boundary lives
  // around the seeds).
  if (!this->BuildProblem(boundary, source, seeds))
  {
    return 0;
  }
  const std::string valueName = this->GetSolutionName();
  double progress = 0.0;
  double seconds = 0.0;
  vtkIdType walks = 0;

  // Estimates at `points` (one batch for all of them), taken as numbers from
  // the batch: the first component's value and gradient with their
  // variances, the derivative status and the distance to the boundary.
  // False when aborted or when the batch failed (reported).
  auto estimate = [&](const std::vector<Point>& points, std::vector<Estimate>& out) {
    gridfree::EstimateArrays found;
    const bool completed = this->EstimateNumbersAt(points, found, progress, seconds, walks);
    this->LastNumberOfEstimates += static_cast<vtkIdType>(points.size());
    const gridfree::DerivativeArrays& derivatives = found.Derivatives;
    if (!found.Mean || !derivatives.Gradient || !derivatives.GradientVariance ||
      !derivatives.Status)
    {
      return false; // the batch failed (reported)
    }
    const int nc = found.Components;
    out.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const auto id = static_cast<vtkIdType>(i);
      Estimate& e = out[i];
      e.Value = found.Mean->GetValue(id * nc);
      e.ValueVariance = found.Variance->GetValue(id * nc);
      for (int k = 0; k < 3; ++k)
      {
        e.Gradient[k] = derivatives.Gradient->GetTypedComponent(id, k);
        e.GradientVariance[k] = derivatives.GradientVariance->GetTypedComponent(id, k);
      }
      e.NearBoundary = derivatives.Status->GetValue(id) != 0;
      e.Distance = found.Distance->GetValue(id);
      e.Valid = std::isfinite(e.Value);
    }
    return completed;
  };

  // The lines: one per seed and direction, started at the seeds.
  std::vector<Line> lines;
  std::vector<Point> seedPoints(static_cast<std::size_t>(seeds->GetNumberOfPoints()));
  for (vtkIdType s = 0; s < seeds->GetNumberOfPoints(); ++s)
  {
    seeds->GetPoint(s, seedPoints[static_cast<std::size_t>(s)].data());
  }
  std::vector<Estimate> seedEstimates;
  bool aborted = !estimate(seedPoints, seedEstimates);
  for (vtkIdType s = 0; s < seeds->GetNumberOfPoints(); ++s)
  {
    for (double sign : { 1.0, -1.0 })
    {
      if ((sign > 0 && this->IntegrationDirection == BACKWARD) ||
        (sign < 0 && this->IntegrationDirection == FORWARD))
      {
        continue;
      }
      Line line;
      line.Seed = s;
      line.Sign = sign;
      line.Points.push_back(seedPoints[static_cast<std::size_t>(s)]);
      line.Estimates.push_back(seedEstimates[static_cast<std::size_t>(s)]);
      lines.push_back(std::move(line));
    }
  }

  // Checks whether a line can take a step from its last point; sets its
  // direction there, or ends it with the reason.
  auto startStep = [&](Line& line, Point& d) {
    const Estimate& e = line.Estimates.back();
    if (!e.Valid || !inBox(line.Points.back()))
    {
      line.Reason = OUT_OF_DOMAIN;
    }
    else if (e.NearBoundary)
    {
      line.Reason = CLOSE_TO_BOUNDARY;
    }
    else if (!UnitDirection(e, line.Sign, this->TerminalSpeed, d))
    {
      line.Reason = STAGNATION;
    }
    else if (static_cast<int>(line.Points.size()) > this->MaximumNumberOfSteps)
    {
      line.Reason = OUT_OF_STEPS;
    }
    else if (line.Length + h > maximumLength * (1.0 + 1e-12))
    {
      line.Reason = OUT_OF_LENGTH;
    }
    return line.Reason == 0;
  };

  // A step never leaves the empty ball around the line's point (half its
  // radius), so no stage crosses the boundary: near it, steps shrink and the
  // line ends within epsilon of it (CLOSE_TO_BOUNDARY).
  auto stepOf = [&](const Line& line) {
    return std::min(h, 0.5 * line.Estimates.back().Distance);
  };

  // Lockstep integration (the core's LockstepStreamlines.h): each stage
  // estimates at all running lines' stage points in one batch. A stage whose
  // direction is undefined reuses the previous one.
  const gridfree::StreamIntegrator method = this->IntegratorType == RUNGE_KUTTA_4
    ? gridfree::StreamIntegrator::RungeKutta4
    : gridfree::StreamIntegrator::Heun;
  for (int step = 0; step < this->MaximumNumberOfSteps && !aborted; ++step)
  {
    std::vector<std::size_t> running;
    std::vector<Point> from, first;
    std::vector<double> steps;
    for (std::size_t l = 0; l < lines.size(); ++l)
    {
      Point d;
      if (lines[l].Reason == 0 && startStep(lines[l], d))
      {
        running.push_back(l);
        from.push_back(lines[l].Points.back());
        first.push_back(d);
        steps.push_back(stepOf(lines[l]));
      }
    }
    if (running.empty())
    {
      break;
    }
    progress = static_cast<double>(step) / this->MaximumNumberOfSteps;
    this->UpdateProgress(progress);
    if (this->GetAbortExecute())
    {
      aborted = true;
      break;
    }
    auto gradientDirections = [&](int, const std::vector<Point>& at, const std::vector<Point>&,
                                std::vector<Point>& directions, std::vector<char>& defined) {
      std::vector<Estimate> estimates;
      if (!estimate(at, estimates))
      {
        return false;
      }
      for (std::size_t r = 0; r < running.size(); ++r)
      {
        defined[r] = UnitDirection(estimates[r], lines[running[r]].Sign, 0.0, directions[r]);
      }
      return true;
    };
    std::vector<Point> combined;
    if (!gridfree::LockstepStepDirections<Point, 3>(
          method, from, steps, first, gradientDirections, combined))
    {
      aborted = true;
      break;
    }
    std::vector<Point> next(running.size());
    for (std::size_t r = 0; r < running.size(); ++r)
    {
      next[r] = Advance(from[r], steps[r], combined[r]);
    }
    std::vector<Estimate> atNext;
    if (!estimate(next, atNext))
    {
      aborted = true;
      break; // an aborted batch's points are NaN: the lines end before them
    }
    for (std::size_t r = 0; r < running.size(); ++r)
    {
      Line& line = lines[running[r]];
      const Point& from = line.Points.back();
      const Point& to = next[r];
      line.Length += std::sqrt((to[0] - from[0]) * (to[0] - from[0]) +
        (to[1] - from[1]) * (to[1] - from[1]) + (to[2] - from[2]) * (to[2] - from[2]));
      line.Points.push_back(to);
      line.Estimates.push_back(atNext[r]);
    }
  }
  for (Line& line : lines)
  {
    if (line.Reason == 0)
    {
      Point unused;
      if (startStep(line, unused))
      {
        line.Reason = OUT_OF_STEPS;
      }
    }
  }
  if (this->GetEstimateFailed())
  {
    return 0;
  }
  if (aborted)
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
  for (const Line& line : lines)
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
        const Point& a = line.Points[i - 1];
        const Point& b = line.Points[i];
        arc += std::sqrt(
          (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
      }
      polylines->InsertCellPoint(points->InsertNextPoint(line.Points[i].data()));
      const Estimate& e = line.Estimates[i];
      value->InsertNextValue(e.Value);
      valueVariance->InsertNextValue(e.ValueVariance);
      gradient->InsertNextTuple(e.Gradient.data());
      gradientVariance->InsertNextTuple(e.GradientVariance.data());
      time->InsertNextValue(line.Sign * arc);
    }
    seedIds->InsertNextValue(static_cast<int>(line.Seed));
    reasons->InsertNextValue(line.Reason);
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
