#include "vtkWalkOnSpheresAdaptiveSampler.h"

#include "GridFreeArrays.h"
#include "GridFreeEstimateArrays.h"

#include "GridFreeVisibleNeighbours.h"

#include <gridfree/applications/AdaptiveSamplingRounds.h>

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresAdaptiveSampler);

namespace
{
constexpr int DomainPort = 1;

double Component(vtkDataArray* array, vtkIdType i, int c)
{
  return array ? array->GetComponent(i, c) : 0.0;
}

// The core's neighbour search (SampleAdaptively) through VisibleNeighbours:
// the k nearest samples a candidate sees.
struct SampleNeighbours
{
  gridfree::VisibleNeighbours Finder;
  vtkNew<vtkPoints> Points;

  struct Scratch
  {
    gridfree::VisibleNeighbours::Scratch Search;
    std::vector<vtkIdType> Ids;
  };

  SampleNeighbours() { this->Points->SetDataTypeToDouble(); }

  void SetSamples(const std::vector<gridfree::Point3>& positions)
  {
    this->Points->SetNumberOfPoints(static_cast<vtkIdType>(positions.size()));
    for (std::size_t i = 0; i < positions.size(); ++i)
    {
      this->Points->SetPoint(static_cast<vtkIdType>(i), positions[i].data());
    }
    this->Points->Modified();
    this->Finder.SetSamples(this->Points);
  }

  void Find(const gridfree::Point3& x, int k, Scratch& scratch, std::vector<std::size_t>& ids) const
  {
    this->Finder.Find(x.data(), k, scratch.Search, scratch.Ids);
    ids.assign(scratch.Ids.begin(), scratch.Ids.end());
  }
};
} // namespace

//------------------------------------------------------------------------------
vtkWalkOnSpheresAdaptiveSampler::vtkWalkOnSpheresAdaptiveSampler() = default;

void vtkWalkOnSpheresAdaptiveSampler::SetDomainConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(DomainPort, output);
}
void vtkWalkOnSpheresAdaptiveSampler::SetDomainData(vtkDataObject* data)
{
  this->SetInputData(DomainPort, data);
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresAdaptiveSampler::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  const auto start = std::chrono::steady_clock::now();
  this->LastNumberOfWalks = 0;
  this->LastNumberOfSamples = 0;
  this->LastNumberOfRounds = 0;
  this->LastSeconds = 0.0;
  vtkDataObject* boundary = vtkDataObject::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* domain = vtkDataSet::GetData(inputVector[DomainPort], 0);
  vtkDataSet* source = vtkDataSet::GetData(inputVector[SourcePort], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!domain || !output)
  {
    vtkErrorMacro(<< "No Domain input: connect a dataset whose points are the candidate "
                     "sample locations to port 1.");
    return 0;
  }
  const vtkIdType numCandidates = domain->GetNumberOfPoints();
  if (numCandidates == 0)
  {
    vtkWarningMacro(<< "The Domain input has no points: no samples.");
    return 1;
  }
  std::vector<gridfree::Point3> candidates(static_cast<std::size_t>(numCandidates));
  for (vtkIdType i = 0; i < numCandidates; ++i)
  {
    domain->GetPoint(i, candidates[static_cast<std::size_t>(i)].data());
  }

  // The problem, built once for all the rounds.
  if (!this->BuildProblem(boundary, source, domain))
  {
    // An Abort while the coefficients were prepared was reported as a
    // warning: an empty output, not a failed pipeline.
    return this->GetAbortExecute() ? 1 : 0;
  }

  // The batches of the rounds: each estimates at the candidates `ids`, keeps
  // the solver's arrays of those points as rows of the output, and hands the
  // refinement its numbers (read from the same arrays, by member).
  vtkNew<vtkPointData> sampleData;
  std::string name;
  double solveSeconds = 0.0;
  auto estimate = [&](const std::vector<std::size_t>& ids, gridfree::SampleBatch& batch) {
    std::vector<std::array<double, 3>> points(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      points[i] = candidates[ids[i]];
    }
    vtkNew<vtkPointData> pd;
    gridfree::EstimateArrays found;
    double seconds = 0.0;
    const bool completed = this->EstimateAt(
      points, pd, this->GetProgress(), seconds, this->LastNumberOfWalks, &found);
    solveSeconds += seconds;
    if (!completed)
    {
      return false;
    }
    const int nc = found.Mean->GetNumberOfComponents();
    if (sampleData->GetNumberOfArrays() == 0)
    {
      name = this->GetSolutionName();
      sampleData->CopyAllocate(pd);
    }
    batch.Components = nc;
    batch.Values.clear();
    batch.ValueVariances.clear();
    batch.Gradients.clear();
    batch.GradientVariances.clear();
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      const auto j = static_cast<vtkIdType>(i);
      sampleData->CopyData(pd, j, sampleData->GetNumberOfTuples());
      for (int c = 0; c < nc; ++c)
      {
        batch.Values.push_back(found.Mean->GetComponent(j, c));
        batch.ValueVariances.push_back(Component(found.Variance, j, c));
        for (int a = 0; a < 3; ++a)
        {
          batch.Gradients.push_back(Component(found.Derivatives.Gradient, j, 3 * c + a));
          batch.GradientVariances.push_back(
            Component(found.Derivatives.GradientVariance, j, 3 * c + a));
        }
      }
    }
    return true;
  };

  // Visibility through the boundary, when it can block it.
  SampleNeighbours neighbours;
  auto* mesh = vtkPolyData::SafeDownCast(boundary);
  if (this->UseVisibility && mesh && mesh->GetNumberOfCells() > 0)
  {
    std::string reason;
    if (!neighbours.Finder.SetBoundary(mesh, reason))
    {
      vtkWarningMacro(<< "Visibility is off: the boundary cannot block it (" << reason << ").");
    }
  }
  auto reportProgress = [this](double fraction) {
    this->UpdateProgress(fraction);
    return !this->CheckAbort();
  };

  // The rounds (the core's).
  gridfree::AdaptiveSamplingSettings settings;
  settings.InitialSamples = static_cast<std::size_t>(this->InitialSamples);
  settings.MaximumSamples = static_cast<std::size_t>(this->MaximumSamples);
  settings.Threshold = this->Threshold;
  settings.ThresholdIsRelative = this->ThresholdIsRelative;
  settings.Neighbours = this->NumberOfNeighbors;
  settings.MaximumRounds = this->MaximumRounds;
  settings.Threads = this->GetNumberOfThreads();
  gridfree::AdaptiveSamples samples;
  const gridfree::AdaptiveSamplingEnd end = gridfree::SampleAdaptively(
    candidates, settings, estimate, neighbours, reportProgress, samples);
  if (end == gridfree::AdaptiveSamplingEnd::NoFiniteCandidate)
  {
    vtkErrorMacro(<< "The Domain input has no finite point to sample.");
    return 0;
  }
  if (end == gridfree::AdaptiveSamplingEnd::StoppedAtFirst)
  {
    if (this->GetEstimateFailed())
    {
      return 0;
    }
    vtkWarningMacro(<< "Adaptive sampling aborted before the first samples were estimated.");
    return 1;
  }
  this->LastNumberOfRounds = samples.RoundsDone;
  // Each distinct warning of the rounds once.
  this->ReportWarnings();
  if (this->GetEstimateFailed())
  {
    return 0;
  }
  if (end == gridfree::AdaptiveSamplingEnd::Stopped)
  {
    vtkWarningMacro(<< "Adaptive sampling aborted after " << samples.Size() << " samples.");
  }
  const int nc = samples.Components;

  // The sample cloud.
  const auto count = static_cast<vtkIdType>(samples.Size());
  vtkNew<vtkPoints> samplePoints;
  samplePoints->SetDataTypeToDouble();
  samplePoints->SetNumberOfPoints(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    samplePoints->SetPoint(i, samples.Positions[static_cast<std::size_t>(i)].data());
  }
  output->SetPoints(samplePoints);
  vtkNew<vtkCellArray> vertices;
  for (vtkIdType i = 0; i < count; ++i)
  {
    vertices->InsertNextCell(1, &i);
  }
  output->SetVerts(vertices);
  vtkPointData* pd = output->GetPointData();
  pd->ShallowCopy(sampleData);
  vtkNew<vtkIntArray> rounds;
  rounds->SetName("RefinementRound");
  vtkNew<vtkIdTypeArray> domainIds;
  domainIds->SetName("DomainPointId");
  vtkNew<vtkDoubleArray> scores;
  scores->SetName("TaylorDisagreement");
  for (vtkIdType i = 0; i < count; ++i)
  {
    const auto s = static_cast<std::size_t>(i);
    rounds->InsertNextValue(samples.Rounds[s]);
    domainIds->InsertNextValue(static_cast<vtkIdType>(samples.CandidateIds[s]));
    scores->InsertNextValue(samples.Scores[s]);
  }
  pd->AddArray(rounds);
  pd->AddArray(domainIds);
  pd->AddArray(scores);
  pd->SetActiveScalars(name.c_str());
  if (nc == 1)
  {
    pd->SetActiveVectors((name + "_Gradient").c_str());
  }

  this->LastNumberOfSamples = count;
  this->LastSeconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  vtkFieldData* fd = output->GetFieldData();
  gridfree::AddFieldValue(fd, "TotalWalks", static_cast<double>(this->LastNumberOfWalks));
  gridfree::AddFieldValue(fd, "SolveSeconds", solveSeconds);
  gridfree::AddFieldValue(fd, "SamplingSeconds", this->LastSeconds);
  gridfree::AddFieldValue(fd, "RefinementRounds", this->LastNumberOfRounds);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresAdaptiveSampler::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "InitialSamples: " << this->InitialSamples << "\n";
  os << indent << "MaximumSamples: " << this->MaximumSamples << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "ThresholdIsRelative: " << (this->ThresholdIsRelative ? "On" : "Off") << "\n";
  os << indent << "NumberOfNeighbors: " << this->NumberOfNeighbors << "\n";
  os << indent << "MaximumRounds: " << this->MaximumRounds << "\n";
  os << indent << "UseVisibility: " << (this->UseVisibility ? "On" : "Off") << "\n";
}
