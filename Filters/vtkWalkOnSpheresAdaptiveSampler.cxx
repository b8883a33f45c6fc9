#include "vtkWalkOnSpheresAdaptiveSampler.h"

#include "GridFreeArrays.h"
#include "GridFreeEstimateArrays.h"

#include <gridfree/applications/AdaptiveSampling.h>
#include "GridFreeVisibleNeighbours.h"
#include <gridfree/execution/ParallelExecution.h>

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
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
#include "vtkStaticPointLocator.h"

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

// The samples so far: what the refinement test reads (first component's
// value and gradient are enough per component, kept for all components),
// and the solver's point data for the output.
struct SampleSet
{
  int Components = 0;
  vtkNew<vtkPoints> Points;
  std::vector<gridfree::Point3> Positions;
  std::vector<double> Values, ValueVariances, Gradients, GradientVariances; // nc, nc, 3nc, 3nc
  std::vector<vtkIdType> DomainIds;
  std::vector<int> Rounds;
  std::vector<double> Scores;
  vtkNew<vtkPointData> Data;
  std::string Name;

  vtkIdType Size() const { return static_cast<vtkIdType>(this->Positions.size()); }

  // The refinement test's data of sample s, component c.
  gridfree::TaylorNeighbour Neighbour(std::size_t s, int c) const
  {
    const std::size_t nc = static_cast<std::size_t>(this->Components);
    gridfree::TaylorNeighbour n;
    n.Position = this->Positions[s];
    n.Value = this->Values[s * nc + c];
    n.ValueVariance = this->ValueVariances[s * nc + c];
    for (int a = 0; a < 3; ++a)
    {
      n.Gradient[a] = this->Gradients[(s * nc + c) * 3 + a];
      n.GradientVariance[a] = this->GradientVariances[(s * nc + c) * 3 + a];
    }
    return n;
  }
};

double Component(vtkDataArray* array, vtkIdType i, int c)
{
  return array ? array->GetComponent(i, c) : 0.0;
}
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
    return 0;
  }

  // Solves at the given candidates and appends them to the samples.
  SampleSet samples;
  samples.Points->SetDataTypeToDouble();
  double solveSeconds = 0.0;
  // Estimates at the candidates `ids` and appends them to the samples;
  // false when aborted (the samples stay as they were).
  auto solveAt = [&](const std::vector<vtkIdType>& ids, int round,
                   const std::vector<double>& scores) -> bool {
    std::vector<std::array<double, 3>> points(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      points[i] = candidates[static_cast<std::size_t>(ids[i])];
    }
    // The batch's arrays go to the samples' output as they are; the numbers
    // the refinement needs are read from them by member.
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
    const std::string name = this->GetSolutionName();
    vtkDataArray* value = found.Mean;
    vtkDataArray* gradient = found.Derivatives.Gradient;
    vtkDataArray* variance = found.Variance;
    vtkDataArray* gradientVariance = found.Derivatives.GradientVariance;
    const int nc = value->GetNumberOfComponents();
    if (samples.Size() == 0)
    {
      samples.Components = nc;
      samples.Name = name;
      samples.Data->CopyAllocate(pd);
    }
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      const auto j = static_cast<vtkIdType>(i);
      const vtkIdType to = samples.Size();
      samples.Data->CopyData(pd, j, to);
      const gridfree::Point3& x = candidates[static_cast<std::size_t>(ids[i])];
      samples.Points->InsertNextPoint(x.data());
      samples.Positions.push_back(x);
      samples.DomainIds.push_back(ids[i]);
      samples.Rounds.push_back(round);
      samples.Scores.push_back(scores[i]);
      for (int c = 0; c < nc; ++c)
      {
        samples.Values.push_back(value->GetComponent(j, c));
        samples.ValueVariances.push_back(Component(variance, j, c));
        for (int a = 0; a < 3; ++a)
        {
          samples.Gradients.push_back(gradient->GetComponent(j, 3 * c + a));
          samples.GradientVariances.push_back(Component(gradientVariance, j, 3 * c + a));
        }
      }
    }
    return true;
  };

  // Round 0: well-spread first samples.
  const std::size_t budget = static_cast<std::size_t>(this->MaximumSamples);
  std::vector<std::size_t> spread = gridfree::SpreadSubset(
    candidates, std::min<std::size_t>(static_cast<std::size_t>(this->InitialSamples), budget));
  if (spread.size() > budget)
  {
    spread.resize(budget);
  }
  if (spread.empty())
  {
    vtkErrorMacro(<< "The Domain input has no finite point to sample.");
    return 0;
  }
  std::vector<vtkIdType> firstIds(spread.begin(), spread.end());
  if (!solveAt(firstIds, 0,
        std::vector<double>(firstIds.size(), std::numeric_limits<double>::quiet_NaN())))
  {
    if (this->GetEstimateFailed())
    {
      return 0;
    }
    vtkWarningMacro(<< "Adaptive sampling aborted before the first samples were estimated.");
    return 1;
  }
  const int nc = samples.Components;

  // The scale of the threshold: the first samples' range per component.
  std::vector<double> threshold2(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c)
  {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (vtkIdType s = 0; s < samples.Size(); ++s)
    {
      const double v = samples.Values[static_cast<std::size_t>(s) * nc + c];
      if (std::isfinite(v))
      {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    const double range = hi > lo ? hi - lo : 1.0;
    const double scale = this->ThresholdIsRelative ? range : 1.0;
    threshold2[static_cast<std::size_t>(c)] = (this->Threshold * scale) * (this->Threshold * scale);
  }

  gridfree::VisibleNeighbours neighbours;
  auto* mesh = vtkPolyData::SafeDownCast(boundary);
  if (this->UseVisibility && mesh && mesh->GetNumberOfCells() > 0)
  {
    std::string reason;
    if (!neighbours.SetBoundary(mesh, reason))
    {
      vtkWarningMacro(<< "Visibility is off: the boundary cannot block it (" << reason << ").");
    }
  }
  vtkNew<vtkPolyData> candidateCloud;
  {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(numCandidates);
    for (vtkIdType i = 0; i < numCandidates; ++i)
    {
      points->SetPoint(i, candidates[static_cast<std::size_t>(i)].data());
    }
    candidateCloud->SetPoints(points);
  }
  vtkNew<vtkStaticPointLocator> candidateLocator;
  candidateLocator->SetDataSet(candidateCloud);
  candidateLocator->BuildLocator();

  // Refinement rounds.
  std::vector<char> sampled(static_cast<std::size_t>(numCandidates), 0);
  for (vtkIdType id : samples.DomainIds)
  {
    sampled[static_cast<std::size_t>(id)] = 1;
  }
  const int k = this->NumberOfNeighbors;
  bool aborted = false;
  for (int round = 1; round <= this->MaximumRounds && samples.Positions.size() < budget; ++round)
  {
    this->UpdateProgress(static_cast<double>(samples.Size()) / static_cast<double>(budget));
    if (this->CheckAbort())
    {
      aborted = true;
      break;
    }
    neighbours.SetSamples(samples.Points);
    std::vector<double> score(static_cast<std::size_t>(numCandidates), 0.0);
    std::vector<double> nearest(static_cast<std::size_t>(numCandidates), 0.0);
    auto test = [&](std::size_t from, std::size_t to, const std::atomic<bool>& cancel) {
      gridfree::VisibleNeighbours::Scratch scratch;
      std::vector<vtkIdType> ids;
      std::vector<gridfree::TaylorNeighbour> data;
      for (std::size_t i = from; i < to && !cancel.load(std::memory_order_relaxed); ++i)
      {
        if (sampled[i])
        {
          continue;
        }
        const gridfree::Point3& x = candidates[i];
        neighbours.Find(x.data(), k, scratch, ids);
        double worst = ids.empty() ? std::numeric_limits<double>::infinity() : 0.0;
        for (int c = 0; c < nc && !ids.empty(); ++c)
        {
          data.clear();
          for (vtkIdType id : ids)
          {
            data.push_back(samples.Neighbour(static_cast<std::size_t>(id), c));
          }
          const double excess =
            gridfree::TaylorDisagreement(x, data.data(), static_cast<int>(data.size()));
          const double t2 = threshold2[static_cast<std::size_t>(c)];
          const double ratio =
            t2 > 0.0 ? excess / t2 : (excess > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
          worst = std::max(worst, ratio); // NaN (NaN samples) never refines
        }
        score[i] = worst;
        if (!ids.empty())
        {
          const gridfree::Point3& y = samples.Positions[static_cast<std::size_t>(ids.front())];
          nearest[i] = std::sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
            (x[2] - y[2]) * (x[2] - y[2]));
        }
      }
    };
    if (!gridfree::ParallelForWithProgress(
          static_cast<std::size_t>(numCandidates), this->GetNumberOfThreads(), test,
          [this](double) { return !this->CheckAbort(); }, 0.1, 256))
    {
      aborted = true;
      break;
    }

    // Candidates that need a sample, worst first (ties: lower id).
    std::vector<vtkIdType> needy;
    for (vtkIdType i = 0; i < numCandidates; ++i)
    {
      if (score[static_cast<std::size_t>(i)] > 1.0)
      {
        needy.push_back(i);
      }
    }
    std::stable_sort(needy.begin(), needy.end(), [&](vtkIdType a, vtkIdType b) {
      return score[static_cast<std::size_t>(a)] > score[static_cast<std::size_t>(b)];
    });
    const std::size_t room =
      std::min(budget - samples.Positions.size(), samples.Positions.size());
    std::vector<char> blocked(static_cast<std::size_t>(numCandidates), 0);
    std::vector<vtkIdType> chosen;
    std::vector<double> chosenScores;
    vtkNew<vtkIdList> near;
    for (vtkIdType c : needy)
    {
      if (chosen.size() >= room)
      {
        break;
      }
      const auto ci = static_cast<std::size_t>(c);
      if (blocked[ci])
      {
        continue;
      }
      chosen.push_back(c);
      chosenScores.push_back(score[ci]);
      candidateLocator->FindPointsWithinRadius(0.5 * nearest[ci], candidates[ci].data(), near);
      for (vtkIdType j = 0; j < near->GetNumberOfIds(); ++j)
      {
        blocked[static_cast<std::size_t>(near->GetId(j))] = 1;
      }
    }
    if (chosen.empty())
    {
      break; // every candidate is predicted well enough
    }
    if (!solveAt(chosen, round, chosenScores))
    {
      aborted = true;
      break;
    }
    for (vtkIdType id : chosen)
    {
      sampled[static_cast<std::size_t>(id)] = 1;
    }
    this->LastNumberOfRounds = round;
  }
  // Each distinct warning of the rounds once.
  this->ReportWarnings();
  if (this->GetEstimateFailed())
  {
    return 0;
  }
  if (aborted)
  {
    vtkWarningMacro(<< "Adaptive sampling aborted after " << samples.Size() << " samples.");
  }

  // The sample cloud.
  const vtkIdType count = samples.Size();
  output->SetPoints(samples.Points);
  vtkNew<vtkCellArray> vertices;
  for (vtkIdType i = 0; i < count; ++i)
  {
    vertices->InsertNextCell(1, &i);
  }
  output->SetVerts(vertices);
  vtkPointData* pd = output->GetPointData();
  pd->ShallowCopy(samples.Data);
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
    domainIds->InsertNextValue(samples.DomainIds[s]);
    scores->InsertNextValue(samples.Scores[s]);
  }
  pd->AddArray(rounds);
  pd->AddArray(domainIds);
  pd->AddArray(scores);
  pd->SetActiveScalars(samples.Name.c_str());
  if (nc == 1)
  {
    pd->SetActiveVectors((samples.Name + "_Gradient").c_str());
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
