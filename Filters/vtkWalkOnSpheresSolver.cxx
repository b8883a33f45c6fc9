#include "vtkWalkOnSpheresSolver.h"

#include "GridFreeArrays.h"
#include "GridFreeBoundaryAssembly.h"
#include "GridFreeBoundaryValueArrays.h"
#include "GridFreeDerivativeArrays.h"
#include "GridFreeInputFingerprint.h"
#include "GridFreePieceGather.h"
#include "GridFreeSolverCache.h"
#include "GridFreeSolverInputs.h"
#include "GridFreeSourceConversion.h"
#include "GridFreeWholeInputRequest.h"

#include <gridfree/problem/Problem.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "vtkAbstractArray.h"
#include "vtkAlgorithmOutput.h"
#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresSolver);

namespace
{
using gridfree::AddFieldValue;
using gridfree::MakeArray;

constexpr int BoundaryPort = 0;
constexpr int ProbePort = 1;
constexpr int SourcePort = 2;

// A solve projected (after kRateSeconds of measuring) to take longer than
// kLongSolveSeconds is announced with a warning.
constexpr double kRateSeconds = 1.0;
constexpr double kLongSolveSeconds = 120.0;

// "3 minutes", "5 hours", "2 days": a projected solve time for a message.
std::string DescribeDuration(double seconds)
{
  struct Unit
  {
    double Seconds;
    const char* Name;
  };
  const Unit units[] = { { 86400.0 * 365.0, "years" }, { 86400.0, "days" }, { 3600.0, "hours" },
    { 60.0, "minutes" } };
  for (const Unit& u : units)
  {
    if (seconds >= 2.0 * u.Seconds)
    {
      std::ostringstream text;
      text << static_cast<long long>(std::min(seconds / u.Seconds, 1e15) + 0.5) << " " << u.Name;
      return text.str();
    }
  }
  return std::to_string(static_cast<long long>(seconds + 0.5)) + " seconds";
}

} // namespace

// Runs the estimator of one dimension over the probe points and fills the
// output arrays. Lives here, not in the core, because it moves data between
// VTK arrays and the core's plain types.
template <int DIM>
class vtkWalkOnSpheresSolverRunner
{
public:
  static bool Run(vtkWalkOnSpheresSolver* self, const vtkWalkOnSpheresSolverInputs& in)
  {
    std::shared_ptr<const gridfree::Boundary<DIM>>& cached =
      self->Cache->template CachedBoundary<DIM>();
    if (!cached || self->Cache->BoundaryKey != in.BoundaryKey)
    {
      self->Cache->ForgetBoundary(); // frees the old hierarchy before building
      auto built = std::make_shared<gridfree::Boundary<DIM>>();
      if (!gridfree::AssembleBoundary<DIM>(self, in, *built))
      {
        return false;
      }
      cached = built;
      self->Cache->BoundaryKey = in.BoundaryKey;
      self->LastBoundaryBuilt = true;
    }
    const std::shared_ptr<const gridfree::Boundary<DIM>> shared = cached;
    const gridfree::Boundary<DIM>& geometry = *shared;
    std::string reason;

    gridfree::WalkSettings settings;
    const double diagonal = geometry.Diagonal();
    settings.Epsilon = self->EpsilonIsRelative ? self->Epsilon * diagonal : self->Epsilon;
    if (!(settings.Epsilon > 0.0))
    {
      vtkErrorWithObjectMacro(self, << "Epsilon must be positive (got " << settings.Epsilon
                                    << " in world units; boundary diagonal " << diagonal << ").");
      return false;
    }
    if (settings.Epsilon >= 0.1 * diagonal)
    {
      // Walks stop within ε of the boundary: at this size the result is
      // little more than the boundary value nearest to each probe point.
      vtkWarningWithObjectMacro(self, << "Epsilon is " << settings.Epsilon
                                      << " in world units, at least a tenth of the boundary's "
                                         "diagonal ("
                                      << diagonal
                                      << "): walks stop that far from the boundary, so the "
                                         "result is mostly the nearest boundary value, not the "
                                         "solution. Typical values are 1e-4 to 1e-2 of the "
                                         "diagonal (EpsilonIsRelative).");
    }
    settings.MaxSteps = self->MaxSteps;
    settings.Problem = static_cast<gridfree::Equation>(self->Equation);
    settings.ScreeningCoefficient = self->ScreeningCoefficient;
    settings.Sampling = static_cast<gridfree::SourceSampling>(self->SourceSampling);
    settings.Biharmonic = static_cast<gridfree::BiharmonicStrategy>(self->BiharmonicStrategy);
    settings.NestedWalks = self->NestedWalks;

    const bool biharmonic = settings.Problem == gridfree::Equation::Biharmonic;
    const int nc = biharmonic ? geometry.Components() / 2 : geometry.Components();

    // Sources (only for the equations that have them; RequestData warned otherwise).
    auto sourceSet = std::make_shared<gridfree::SourceSet<DIM>>();
    gridfree::SourceSet<DIM>& sources = *sourceSet;
    if (gridfree::WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem))
    {
      if (!gridfree::ConvertSource<DIM>(in.Source, in.SourceArray, in.Expression, nc,
            gridfree::ProblemPlaneZ<DIM>(in), sources, reason,
            static_cast<gridfree::SourceOperator>(self->SourceOperator)))
      {
        vtkErrorWithObjectMacro(self, << "Cannot use the source term: " << reason << ".");
        return false;
      }
      if (sources.IgnoredSurfaceCells > 0)
      {
        vtkWarningWithObjectMacro(self, << "Ignored " << sources.IgnoredSurfaceCells
                                        << " polygons of the Source input: a vtkPolyData source "
                                           "gives point sources (vertices) and curve sources "
                                           "(lines) only.");
      }
    }
    // The problem: boundary, equation and sources, answered in one batch.
    const gridfree::Problem<DIM> problem(shared, settings, sourceSet);

    const vtkIdType numPoints = in.Probe->GetNumberOfPoints();
    std::vector<std::array<double, 3>> points(static_cast<std::size_t>(numPoints));
    vtkIdType nonFinitePoints = 0;
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      in.Probe->GetPoint(i, points[i].data());
      bool finite = true;
      for (int k = 0; k < DIM; ++k)
      {
        finite = finite && std::isfinite(points[i][k]);
      }
      nonFinitePoints += finite ? 0 : 1;
    }
    if (nonFinitePoints > 0)
    {
      vtkWarningWithObjectMacro(self, << nonFinitePoints << " of " << numPoints
                                      << " probe points have NaN or infinite coordinates: their "
                                         "results are NaN.");
    }

    auto mean = MakeArray(in.Name, nc, numPoints);
    auto variance = MakeArray(in.Name + "_Variance", nc, numPoints);
    vtkSmartPointer<vtkDoubleArray> laplacian, laplacianVariance;
    if (biharmonic)
    {
      laplacian = MakeArray(in.Name + "_Laplacian", nc, numPoints);
      laplacianVariance = MakeArray(in.Name + "_Laplacian_Variance", nc, numPoints);
    }
    auto steps = MakeArray("WalkSteps", 1, numPoints);
    auto escaped = MakeArray("EscapedFraction", 1, numPoints);
    auto truncated = MakeArray("TruncatedFraction", 1, numPoints);
    // The distance from each point to the boundary (a lower bound for an
    // implicit boundary): where a walk starts, and how far a streamline may
    // step without crossing the boundary.
    auto distance = MakeArray("BoundaryDistance", 1, numPoints);
    // The boundary value at the closest boundary point: what a walk started
    // here would return if it ended at once. It is the "albedo" a denoiser is
    // guided by (paper Sec. 5.2.4): the solution's sharp features follow its
    // jumps, where the closest point switches between distant boundary parts.
    auto closestValue = MakeArray(in.Name + "_ClosestBoundaryValue", nc, numPoints);
    tbb::parallel_for(tbb::blocked_range<vtkIdType>(0, numPoints, 256),
      [&](const tbb::blocked_range<vtkIdType>& range) {
        std::vector<double> g(static_cast<std::size_t>(geometry.Components()));
        for (vtkIdType i = range.begin(); i < range.end(); ++i)
        {
          gridfree::Vec<DIM> x;
          if (gridfree::ProbeStartPoint<DIM>(points[static_cast<std::size_t>(i)].data(), x))
          {
            distance->SetValue(i, geometry.Distance(x));
            geometry.Evaluate(x, geometry.ClosestPoint(x), g.data());
            for (int c = 0; c < nc; ++c)
            {
              closestValue->SetTypedComponent(i, c, g[static_cast<std::size_t>(c)]);
            }
          }
        }
      });

    // Derivatives: the derivative estimator runs whenever a derivative or a
    // control variate is asked for (the value's control needs the gradient).
    gridfree::DerivativeRequest request;
    request.Gradient = self->ComputeGradient;
    request.Hessian = self->ComputeHessian;
    request.ControlVariates = self->ControlVariates;
    request.Directional = self->ComputeDirectionalDerivative;
    request.Direction = { self->DerivativeDirection[0], self->DerivativeDirection[1],
      self->DerivativeDirection[2] };
    request.DivergenceCurl = self->ComputeGradient && nc == 3;
    const bool anyDerivative = request.Gradient || request.Hessian || request.Directional;
    gridfree::DerivativeArrays derivatives;
    if (anyDerivative)
    {
      derivatives.Allocate(in.Name, nc, numPoints, request);
    }

    gridfree::BatchRequest batch;
    batch.WalksPerPoint = self->WalksPerPoint;
    batch.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(self->Seed));
    batch.Threads = self->NumberOfThreads;
    batch.Derivatives = request;
    const int walks = batch.WalksPerPoint;

    // Progressive refinement: the batch continues from the running sums the
    // last solve kept (RequestData forgot them if anything but
    // WalksPerPoint changed) and keeps its own.
    gridfree::RunningSumsCache& kept = self->Cache->Sums;
    if (!self->KeepRunningSums)
    {
      kept.Clear();
    }

    // Progress counts walks, so that a few points with very many walks each
    // still report it; once the rate is known, a solve projected to take
    // long is announced (abort stays possible: walks run in chunks that
    // check for it).
    bool announced = false;
    auto reportProgress = [&](const gridfree::BatchProgress& p) {
      if (!announced && p.WalksRun > 0 && p.Seconds >= kRateSeconds)
      {
        announced = true;
        const double projected = p.Seconds * p.WalksToRun / static_cast<double>(p.WalksRun);
        if (projected >= kLongSolveSeconds)
        {
          vtkWarningWithObjectMacro(self, << "This solve will take about "
                                          << DescribeDuration(projected) << " at the current rate ("
                                          << numPoints << " points, " << walks
                                          << " walks per point): lower WalksPerPoint or the "
                                             "probe's resolution, or abort it.");
        }
      }
      self->UpdateProgress(p.Fraction);
      return !self->GetAbortExecute();
    };

    // Copies one finished point's statistics to the output arrays (called
    // for distinct points at once from worker threads).
    const gridfree::SampleLayout layout = problem.Layout(batch);
    auto storePoint = [&](std::size_t at, const gridfree::RunningStatistics& stats,
                        const gridfree::WalkCounters& counters, gridfree::DerivativeStatus status) {
      const auto i = static_cast<vtkIdType>(at);
      for (int c = 0; c < nc; ++c)
      {
        mean->SetValue(i * nc + c, stats.GetMean(layout.Value + c));
        variance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Value + c));
        if (biharmonic)
        {
          laplacian->SetValue(i * nc + c, stats.GetMean(layout.Laplacian + c));
          laplacianVariance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Laplacian + c));
        }
      }
      steps->SetValue(i, counters.MeanSteps());
      escaped->SetValue(i, counters.EscapedFraction());
      truncated->SetValue(i, counters.TruncatedFraction());
      if (anyDerivative)
      {
        derivatives.Store<DIM>(at, stats, layout, nc, static_cast<int>(status));
      }
    };

    const gridfree::BatchSummary summary = problem.Estimate(
      points, batch, storePoint, reportProgress, self->KeepRunningSums ? &kept : nullptr);
    const bool completed = summary.Completed;
    const gridfree::WalkCounters& totals = summary.Totals;
    const std::array<std::uint64_t, 3>& statusCounts = summary.StatusCounts;
    const bool unboundedSource = summary.UnboundedSource;
    const int startWalks = summary.ResumedWalksPerPoint;
    self->LastResumedWalksPerPoint = startWalks;
    const double seconds = summary.Seconds;

    // Walks run now; the output stands for totals.Walks (kept ones included).
    self->LastNumberOfWalks = static_cast<vtkIdType>(summary.WalksRun);
    self->LastSolveSeconds = seconds;
    self->LastDimension = DIM;

    vtkPointData* pd = in.Output->GetPointData();
    pd->AddArray(mean);
    pd->AddArray(variance);
    if (biharmonic)
    {
      pd->AddArray(laplacian);
      pd->AddArray(laplacianVariance);
    }
    pd->AddArray(steps);
    pd->AddArray(escaped);
    pd->AddArray(truncated);
    pd->AddArray(distance);
    pd->AddArray(closestValue);
    pd->SetActiveScalars(mean->GetName());
    if (anyDerivative)
    {
      derivatives.AddTo(pd, nc);
    }

    vtkFieldData* fd = in.Output->GetFieldData();
    AddFieldValue(fd, "TotalWalks", static_cast<double>(totals.Walks));
    AddFieldValue(fd, "TotalSteps", static_cast<double>(totals.Steps));
    AddFieldValue(fd, "EscapedWalks", static_cast<double>(totals.Escaped));
    AddFieldValue(fd, "TruncatedWalks", static_cast<double>(totals.Truncated));
    AddFieldValue(fd, "SolveSeconds", seconds);
    // Progressive refinement: walks per point taken from the kept sums.
    AddFieldValue(fd, "ResumedWalksPerPoint", static_cast<double>(startWalks));
    // The run's summary, ready to read in a spreadsheet view or a script.
    const double walkCount = static_cast<double>(totals.Walks);
    const double walksPerSecond = seconds > 0.0 ? walkCount / seconds : 0.0;
    const double meanSteps = walkCount > 0.0 ? static_cast<double>(totals.Steps) / walkCount : 0.0;
    const double escapedFraction = walkCount > 0.0 ? static_cast<double>(totals.Escaped) / walkCount : 0.0;
    AddFieldValue(fd, "ProbePoints", static_cast<double>(numPoints));
    AddFieldValue(fd, "WalksPerSecond", walksPerSecond);
    AddFieldValue(fd, "MeanStepsPerWalk", meanSteps);
    AddFieldValue(fd, "EscapedWalkFraction", escapedFraction);
    // Debug level: shown in ParaView's Output Messages when the filter's
    // Debug property (advanced) is on, and by vtkObject::DebugOn elsewhere.
    // Not vtkDebugWithObjectMacro: release builds (NDEBUG) compile it out.
    if (self->GetDebug() && vtkObject::GetGlobalWarningDisplay())
    {
      std::ostringstream msg;
      msg << self->GetObjectDescription() << ": summary: " << numPoints << " probe points, "
          << totals.Walks << " walks, " << seconds << " s, " << walksPerSecond << " walks/s, "
          << meanSteps << " steps per walk, escaped fraction " << escapedFraction;
      vtkOutputWindowDisplayDebugText(
        "vtkWalkOnSpheresSolver.cxx", __LINE__, msg.str().c_str(), self);
    }

    if (!completed)
    {
      vtkWarningWithObjectMacro(self, << "Solve aborted: points not reached are NaN.");
      return true;
    }
    // NaN results of finite probe points: walks whose coordinates overflowed
    // (points far beyond the boundary's scale) end with no boundary value.
    vtkIdType nanResults = -nonFinitePoints;
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      nanResults += std::isnan(mean->GetValue(i * nc)) ? 1 : 0;
    }
    if (nanResults > 0)
    {
      vtkWarningWithObjectMacro(self, << nanResults << " of " << numPoints
                                      << " probe points got NaN results: their walks overflowed "
                                         "(coordinates far beyond the boundary's size?).");
    }
    if (totals.Escaped > 0 && biharmonic)
    {
      vtkWarningWithObjectMacro(self, << totals.Escaped << " of " << totals.Walks
                                      << " biharmonic walks left the region enclosed by the "
                                         "boundary and were counted as 0 (see EscapedFraction): "
                                         "the biharmonic solver is for bounded domains.");
    }
    if (unboundedSource && (totals.Escaped > 0 || totals.Returns > 0))
    {
      vtkWarningWithObjectMacro(self, << "Walks reached the exterior region, where the "
                                         "SourceExpression is taken as zero beyond a sphere "
                                         "around the boundary and the Source input.");
    }
    if (anyDerivative && (statusCounts[1] > 0 || statusCounts[2] > 0))
    {
      vtkDebugWithObjectMacro(self, << statusCounts[1] << " probe points lie closer than Epsilon "
                                    << "to the boundary and got one-sided derivatives; "
                                    << statusCounts[2] << " got none (see DerivativeStatus).");
    }
    if (totals.Truncated > 0)
    {
      vtkWarningWithObjectMacro(self, << totals.Truncated << " of " << totals.Walks
                                      << " walks reached MaxSteps = " << self->MaxSteps
                                      << " and were stopped (see TruncatedFraction).");
    }
    return true;
  }
};

//------------------------------------------------------------------------------
vtkWalkOnSpheresSolver::vtkWalkOnSpheresSolver()
  : Cache(new vtkWalkOnSpheresSolverCache)
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresSolver::Modified()
{
  if (!this->ChangingOnlyWalks)
  {
    this->SettingsTime.Modified();
  }
  this->Superclass::Modified();
}

void vtkWalkOnSpheresSolver::SetWalksPerPoint(int walks)
{
  walks = std::max(walks, 2);
  if (walks != this->WalksPerPoint)
  {
    this->WalksPerPoint = walks;
    // Only the walk count changed: the kept running sums stay valid.
    this->ChangingOnlyWalks = true;
    this->Modified();
    this->ChangingOnlyWalks = false;
  }
}

void vtkWalkOnSpheresSolver::Refine()
{
  this->SetWalksPerPoint(this->WalksPerPoint > VTK_INT_MAX / 2 ? VTK_INT_MAX
                                                               : 2 * this->WalksPerPoint);
}

vtkWalkOnSpheresSolver::~vtkWalkOnSpheresSolver()
{
  this->SetSourceExpression(nullptr);
  this->SetBoundaryValueExpression(nullptr);
  this->SetBoundaryLaplacianExpression(nullptr);
  this->SetImplicitBoundary(nullptr);
}

vtkCxxSetObjectMacro(vtkWalkOnSpheresSolver, ImplicitBoundary, vtkImplicitFunction);
bool vtkWalkOnSpheresSolver::GatherInputs(
  vtkDataObject* boundary, vtkDataObject* source, vtkWalkOnSpheresSolverPieces& pieces)
{
  pieces.Distributed = false;
  pieces.Boundary.Whole = boundary;
  pieces.Source.Whole = source;
  return true;
}

void vtkWalkOnSpheresSolver::RequestSharedInput(vtkInformation* info)
{
  gridfree::RequestWholeInput(info);
}

// Editing the implicit function (a ParaView widget) must re-execute the solver.
vtkMTimeType vtkWalkOnSpheresSolver::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->ImplicitBoundary)
  {
    time = std::max(time, this->ImplicitBoundary->GetMTime());
  }
  return time;
}

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

void vtkWalkOnSpheresSolver::SetSourceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(SourcePort, output);
}

void vtkWalkOnSpheresSolver::SetSourceData(vtkDataObject* data)
{
  this->SetInputData(SourcePort, data);
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
    // A composite of polygonal blocks is taken whole (for CSG), not block
    // by block as the composite pipeline would otherwise do.
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  }
  // The boundary mesh is optional when an implicit boundary is set.
  if (port == SourcePort || port == BoundaryPort)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
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
// Every piece needs the whole boundary and source; the probe is split as
// requested. In a distributed run each rank asks for its own piece of the
// boundary and source, and RequestData gathers the rest from the other ranks.
int vtkWalkOnSpheresSolver::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* probeInfo = inputVector[ProbePort]->GetInformationObject(0);
  for (int port : { BoundaryPort, SourcePort })
  {
    this->RequestSharedInput(inputVector[port]->GetInformationObject(0));
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
// The numeric array selected as input array `index` on `data`, or, with no
// selection and `fallback` set, the active point (then cell) scalars. Sets
// `missing` to an error message when a named array is absent or not numeric,
// or when the array found has not one tuple per point (cell) of `data`.
vtkDataArray* vtkWalkOnSpheresSolver::ResolveArray(
  int index, vtkDataSet* data, bool fallback, int& association, std::string& missing)
{
  missing.clear();
  association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkInformation* arrayInfo = this->GetInputArrayInformation(index);
  const char* requested = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  const bool selected = arrayInfo &&
    ((requested && *requested) || arrayInfo->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE()));
  vtkDataArray* values = selected ? this->GetInputArrayToProcess(index, data, association) : nullptr;
  if (!values && requested && *requested)
  {
    vtkAbstractArray* any = data->GetPointData()->GetAbstractArray(requested);
    if (!any)
    {
      any = data->GetCellData()->GetAbstractArray(requested);
    }
    missing = any ? "the array '" + std::string(requested) + "' is a " + any->GetClassName() +
        ", not a numeric array"
                  : "there is no point or cell array named '" + std::string(requested) + "'";
    return nullptr;
  }
  if (!values && fallback)
  {
    association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    values = data->GetPointData()->GetScalars();
    if (!values)
    {
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
      values = data->GetCellData()->GetScalars();
    }
  }
  // vtkDataSetAttributes accepts arrays of any length; reading one tuple per
  // point (or cell) of a shorter array would read past its end.
  const bool cells = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  const vtkIdType expected = cells ? data->GetNumberOfCells() : data->GetNumberOfPoints();
  if (values && (association == vtkDataObject::FIELD_ASSOCIATION_POINTS || cells) &&
    values->GetNumberOfTuples() != expected)
  {
    missing = "the array '" + std::string(values->GetName() ? values->GetName() : "") + "' has " +
      std::to_string(values->GetNumberOfTuples()) + " tuples, but the mesh has " +
      std::to_string(expected) + (cells ? " cells" : " points");
    return nullptr;
  }
  return values;
}

std::vector<std::uint64_t> vtkWalkOnSpheresSolver::BoundaryKey(vtkDataObject* boundaryPiece,
  std::uint64_t gathered, int dimension, const vtkWalkOnSpheresSolverInputs& in,
  vtkDataSet* regionProbe)
{
  std::vector<std::uint64_t> key{ static_cast<std::uint64_t>(dimension), gathered };
  auto addString = [&key](const std::string& s) { gridfree::AppendString(s, key); };
  auto addDouble = [&key](double v) { gridfree::AppendDouble(v, key); };
  for (vtkObject* object : { static_cast<vtkObject*>(boundaryPiece),
         static_cast<vtkObject*>(this->ImplicitBoundary) })
  {
    gridfree::AppendFingerprint(object, key);
    key.push_back(~std::uint64_t(0));
  }
  // The arrays selected for g, h and the back side's g.
  for (int idx : { 0, 1, 3 })
  {
    vtkInformation* info = this->GetInputArrayInformation(idx);
    addString(info && info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME())
                                                              : "");
    key.push_back(info && info->Has(vtkDataObject::FIELD_ASSOCIATION())
        ? static_cast<std::uint64_t>(info->Get(vtkDataObject::FIELD_ASSOCIATION()))
        : ~std::uint64_t(0));
    key.push_back(info && info->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE())
        ? static_cast<std::uint64_t>(info->Get(vtkDataObject::FIELD_ATTRIBUTE_TYPE()))
        : ~std::uint64_t(0));
  }
  for (const std::string& e : in.ValueExpressions)
  {
    addString(e);
  }
  addString(in.Name);
  key.push_back(in.CellData ? 1 : 0);
  key.push_back(in.TwoSided ? 1 : 0);
  key.push_back(this->Equation == BIHARMONIC ? 1 : 0); // values hold g and h
  key.push_back(static_cast<std::uint64_t>(in.CsgOperation));
  addDouble(in.CsgBlendRadius);
  addDouble(this->LipschitzBound);
  if (regionProbe)
  {
    // Implicit and CSG boundaries live in a region around the probe.
    double bounds[6];
    regionProbe->GetBounds(bounds);
    for (double b : bounds)
    {
      addDouble(b);
    }
  }
  return key;
}

int vtkWalkOnSpheresSolver::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastBoundaryBuilt = false;
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  this->LastDimension = 0;

  vtkDataObject* boundaryObject = vtkDataObject::GetData(inputVector[BoundaryPort], 0);
  vtkDataObject* sourceObject = vtkDataObject::GetData(inputVector[SourcePort], 0);
  // The inputs as this rank received them: what kept running sums are keyed on.
  vtkDataObject* const boundaryPiece = boundaryObject;
  vtkDataObject* const sourcePiece = sourceObject;
  // A distributed run gathers the boundary and source first, before anything
  // can return early: every rank must take part in the exchange.
  vtkWalkOnSpheresSolverPieces pieces;
  if (!this->GatherInputs(boundaryPiece, sourcePiece, pieces))
  {
    return 0;
  }
  boundaryObject = pieces.Boundary.Whole;
  sourceObject = pieces.Source.Whole;
  vtkPolyData* boundary = vtkPolyData::SafeDownCast(boundaryObject);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* source = vtkDataSet::SafeDownCast(sourceObject);
  if (sourceObject && !source)
  {
    vtkErrorMacro(<< "The Source input is a " << sourceObject->GetClassName()
                  << ", not a dataset.");
    return 0;
  }
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  const bool implicit = this->ImplicitBoundary != nullptr;
  const bool csg = this->CsgOperation != CSG_NONE;

  // A composite boundary: its vtkPolyData leaves are the CSG operands, or,
  // without CSG, one polygon soup.
  std::vector<vtkPolyData*> blocks;
  vtkNew<vtkAppendPolyData> merged;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(boundaryObject))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    it->SkipEmptyNodesOn();
    int index = 0;
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem(), ++index)
    {
      vtkDataObject* leaf = it->GetCurrentDataObject();
      auto* poly = vtkPolyData::SafeDownCast(leaf);
      if (!poly)
      {
        vtkErrorMacro(<< "Block " << index << " of the Boundary input is a "
                      << (leaf ? leaf->GetClassName() : "null object")
                      << ", not a vtkPolyData: every block of a composite boundary must be a "
                         "surface (or, in 2D, lines).");
        return 0;
      }
      blocks.push_back(poly);
    }
    if (blocks.empty())
    {
      vtkErrorMacro(<< "The composite Boundary input has no vtkPolyData blocks.");
      return 0;
    }
    if (!csg)
    {
      for (vtkPolyData* block : blocks)
      {
        merged->AddInputData(block);
      }
      merged->Update();
      boundary = merged->GetOutput();
    }
  }
  else if (csg && boundary)
  {
    blocks.push_back(boundary); // one closed mesh is one operand
  }
  if (csg)
  {
    boundary = nullptr;
  }
  if (!boundary && blocks.empty() && !implicit)
  {
    vtkErrorMacro(<< "No Boundary input: connect a vtkPolyData with boundary values to port 0, "
                     "or set an ImplicitBoundary.");
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
  vtkWalkOnSpheresSolverInputs inputs;

  // Boundary values from expressions (g, and h for the biharmonic equation).
  if (this->BoundaryValueExpression && *this->BoundaryValueExpression)
  {
    inputs.ValueExpressions.push_back(this->BoundaryValueExpression);
    if (this->Equation == BIHARMONIC)
    {
      if (!this->BoundaryLaplacianExpression || !*this->BoundaryLaplacianExpression)
      {
        vtkErrorMacro(<< "The biharmonic equation with BoundaryValueExpression also needs "
                         "BoundaryLaplacianExpression (h = Δu on the boundary).");
        return 0;
      }
      inputs.ValueExpressions.push_back(this->BoundaryLaplacianExpression);
    }
    for (const std::string& e : inputs.ValueExpressions)
    {
      if (!gridfree::CheckSourceExpression(e, reason))
      {
        vtkErrorMacro(<< "Cannot use the boundary value expression '" << e << "': " << reason
                      << ".");
        return 0;
      }
    }
  }
  const bool expressionValues = !inputs.ValueExpressions.empty();
  if (implicit && !expressionValues && !boundary && !csg)
  {
    vtkErrorMacro(<< "The implicit boundary has no values: set BoundaryValueExpression, or "
                     "connect a mesh with boundary values to port 0 to sample them from.");
    return 0;
  }
  if (implicit && expressionValues && boundary)
  {
    vtkWarningMacro(<< "The Boundary input is not used: the implicit boundary takes its values "
                       "from BoundaryValueExpression.");
    boundary = nullptr;
  }

  if (this->TwoSidedBoundaryValues)
  {
    // The side test needs the mesh's orientation and the value table.
    if (csg || implicit || expressionValues)
    {
      vtkErrorMacro(<< "Two-sided boundary values need a mesh boundary with front and back "
                       "arrays: they cannot be used with "
                    << (csg ? "a CSG boundary" : (implicit ? "an implicit boundary"
                                                           : "BoundaryValueExpression"))
                    << ".");
      return 0;
    }
    if (this->Equation == BIHARMONIC)
    {
      vtkErrorMacro(<< "Two-sided boundary values are not available for the biharmonic "
                       "equation: use the Laplace, Poisson or screened Poisson equation.");
      return 0;
    }
  }

  int dimension = 3;
  std::string name = "Solution";
  vtkSmartPointer<vtkDataArray> combined;
  bool cellData = false;
  if (csg)
  {
    if (!vtkWalkOnSpheresSolverBoundaryValues::OfCsgOperands(
          this, blocks, expressionValues, inputs, dimension, name))
    {
      return 0;
    }
    inputs.CsgOperation = this->CsgOperation;
    inputs.CsgBlendRadius = this->CsgBlendRadius;
  }
  else if (!vtkWalkOnSpheresSolverBoundaryValues::OfBoundary(
             this, boundary, implicit, expressionValues, dimension, name, combined, cellData))
  {
    return 0;
  }

  if (this->Equation == SCREENED_POISSON && !(this->ScreeningCoefficient > 0.0))
  {
    vtkErrorMacro(<< "The screened Poisson equation needs ScreeningCoefficient > 0 (got "
                  << this->ScreeningCoefficient << "); use the Poisson equation for c = 0.");
    return 0;
  }

  // Source terms: the Source input's point array and the expression.
  const bool hasExpression = this->SourceExpression && *this->SourceExpression;
  const bool usesSources = this->Equation == POISSON || this->Equation == SCREENED_POISSON;
  if ((source || hasExpression) && !usesSources)
  {
    vtkWarningMacro(<< "The source term (Source input or SourceExpression) is ignored: only the "
                       "Poisson and screened Poisson equations have one.");
  }
  if (usesSources && source)
  {
    int sourceAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    inputs.SourceArray = this->ResolveArray(2, source, false, sourceAssociation, reason);
    if (!inputs.SourceArray && !reason.empty())
    {
      vtkErrorMacro(<< "Cannot use the Source input: " << reason << ".");
      return 0;
    }
    if (!inputs.SourceArray)
    {
      // No selection: the active point scalars, else the only point array.
      inputs.SourceArray = source->GetPointData()->GetScalars();
      if (!inputs.SourceArray && source->GetPointData()->GetNumberOfArrays() == 1)
      {
        inputs.SourceArray = source->GetPointData()->GetArray(0);
      }
    }
    if (inputs.SourceArray && sourceAssociation != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      vtkErrorMacro(<< "The source array must be point data of the Source input.");
      return 0;
    }
    inputs.Source = source;
  }
  if (usesSources && hasExpression)
  {
    inputs.Expression = this->SourceExpression;
  }

  if (probe->GetNumberOfPoints() == 0)
  {
    // In a distributed run a rank whose piece of the probe is empty (a
    // slice that lies in another rank's block) is normal.
    if (!pieces.Distributed)
    {
      vtkWarningMacro(<< "The Probe input has no points: there is nothing to solve.");
    }
    return 1;
  }

  inputs.Boundary = boundary;
  inputs.Implicit = this->ImplicitBoundary;
  inputs.LipschitzBound = this->LipschitzBound;
  inputs.Values = combined;
  inputs.CellData = cellData;
  inputs.TwoSided = this->TwoSidedBoundaryValues;
  inputs.Probe = probe;
  inputs.Output = output;
  inputs.Name = name;
  // Kept running sums stay usable only if nothing but WalksPerPoint changed.
  // (Gathered inputs are new objects at each execution: the sums are keyed on
  // this rank's pieces and on the signature of every rank's pieces.)
  const std::array<vtkObject*, 4> used = { boundaryPiece, probe, sourcePiece,
    this->ImplicitBoundary };
  const std::uint64_t gatheredSignature = pieces.Boundary.Signature ^
    (pieces.Source.Signature * 1099511628211ULL);
  inputs.BoundaryKey = this->BoundaryKey(boundaryPiece, pieces.Boundary.Signature, dimension,
    inputs, implicit || csg ? probe : nullptr);
  this->Cache->Validate(this->SettingsTime.GetMTime(), used, gatheredSignature);
  this->LastResumedWalksPerPoint = 0;
  bool ok = false;
  try
  {
    ok = dimension == 2 ? vtkWalkOnSpheresSolverRunner<2>::Run(this, inputs)
                        : vtkWalkOnSpheresSolverRunner<3>::Run(this, inputs);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Walk on spheres failed: " << e.what());
    ok = false;
  }
  if (!ok)
  {
    this->Cache->Sums.Clear();
    this->Cache->ForgetBoundary();
  }
  this->Cache->Remember(this->SettingsTime.GetMTime(), used, gatheredSignature);
  if (ok && pieces.Distributed)
  {
    vtkFieldData* fd = output->GetFieldData();
    AddFieldValue(fd, "BoundaryPiecesGathered", pieces.Boundary.ContributingRanks);
    AddFieldValue(fd, "SourcePiecesGathered", pieces.Source.ContributingRanks);
  }
  this->UpdateProgress(1.0);
  return ok ? 1 : 0;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresSolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ImplicitBoundary: " << this->ImplicitBoundary << "\n";
  os << indent << "LipschitzBound: " << this->LipschitzBound << "\n";
  os << indent << "CsgOperation: " << this->CsgOperation << "\n";
  os << indent << "CsgBlendRadius: " << this->CsgBlendRadius << "\n";
  os << indent << "BoundaryValueExpression: "
     << (this->BoundaryValueExpression ? this->BoundaryValueExpression : "(none)") << "\n";
  os << indent << "BoundaryLaplacianExpression: "
     << (this->BoundaryLaplacianExpression ? this->BoundaryLaplacianExpression : "(none)") << "\n";
  os << indent << "TwoSidedBoundaryValues: " << this->TwoSidedBoundaryValues << "\n";
  os << indent << "Equation: " << this->Equation << "\n";
  os << indent << "ScreeningCoefficient: " << this->ScreeningCoefficient << "\n";
  os << indent << "SourceExpression: "
     << (this->SourceExpression ? this->SourceExpression : "(none)") << "\n";
  os << indent << "SourceSampling: " << this->SourceSampling << "\n";
  os << indent << "SourceOperator: " << this->SourceOperator << "\n";
  os << indent << "BiharmonicStrategy: " << this->BiharmonicStrategy << "\n";
  os << indent << "NestedWalks: " << this->NestedWalks << "\n";
  os << indent << "WalksPerPoint: " << this->WalksPerPoint << "\n";
  os << indent << "KeepRunningSums: " << (this->KeepRunningSums ? "On" : "Off") << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "EpsilonIsRelative: " << (this->EpsilonIsRelative ? "On" : "Off") << "\n";
  os << indent << "MaxSteps: " << this->MaxSteps << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "ComputeGradient: " << (this->ComputeGradient ? "On" : "Off") << "\n";
  os << indent << "ComputeHessian: " << (this->ComputeHessian ? "On" : "Off") << "\n";
  os << indent << "ControlVariates: " << (this->ControlVariates ? "On" : "Off") << "\n";
  os << indent << "ComputeDirectionalDerivative: "
     << (this->ComputeDirectionalDerivative ? "On" : "Off") << "\n";
  os << indent << "DerivativeDirection: " << this->DerivativeDirection[0] << " "
     << this->DerivativeDirection[1] << " " << this->DerivativeDirection[2] << "\n";
  os << indent << "LastNumberOfWalks: " << this->LastNumberOfWalks << "\n";
  os << indent << "LastResumedWalksPerPoint: " << this->LastResumedWalksPerPoint << "\n";
  os << indent << "LastSolveSeconds: " << this->LastSolveSeconds << "\n";
  os << indent << "LastDimension: " << this->LastDimension << "\n";
}
