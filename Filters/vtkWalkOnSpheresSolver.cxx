#include "vtkWalkOnSpheresSolver.h"

#include "GridFreeArrays.h"
#include "GridFreeArraySelection.h"
#include "GridFreePieceGather.h"
#include "GridFreePointEstimates.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSettingAccessors.h"
#include "GridFreeSolveSettings.h"
#include "GridFreeSolverCache.h"
#include "GridFreeTimeBudget.h"
#include "GridFreeWholeInputRequest.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresSolver);

namespace
{
constexpr int BoundaryPort = 0;
constexpr int ProbePort = 1;
constexpr int SourcePort = 2;
} // namespace

//------------------------------------------------------------------------------
vtkWalkOnSpheresSolver::vtkWalkOnSpheresSolver()
  : Cache(new vtkWalkOnSpheresSolverCache)
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(1);
  // ParaView's progress bar shows it (instead of the class name).
  this->SetProgressText("Walk On Spheres Solver");
  // Near the boundary the plain walks' rare deep ones make error bars too
  // small (SetNearBoundarySplitting); the application filters, which have
  // no such property, keep SolveSettings' default, off.
  this->GetSettings().NearBoundarySplitting = true;
  // A flagged point walks on before it is announced as unreliable
  // (SetWalkOnWhereUnreliable); the application filters keep their cost.
  this->GetSettings().WalkOnWhereUnreliable = 4;
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

void vtkWalkOnSpheresSolver::SetAbortExecute(vtkTypeBool abort)
{
  this->AbortExecute = abort;
}

void vtkWalkOnSpheresSolver::SetInputArrayToProcess(
  int idx, int port, int connection, int fieldAssociation, const char* name)
{
  vtkInformation* info = this->GetInputArrayInformation(idx);
  const bool same = info && info->Has(vtkAlgorithm::INPUT_PORT()) &&
    info->Get(vtkAlgorithm::INPUT_PORT()) == port &&
    info->Has(vtkAlgorithm::INPUT_CONNECTION()) &&
    info->Get(vtkAlgorithm::INPUT_CONNECTION()) == connection &&
    info->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
    info->Get(vtkDataObject::FIELD_ASSOCIATION()) == fieldAssociation &&
    !info->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE()) &&
    (name ? info->Has(vtkDataObject::FIELD_NAME()) &&
         std::string(info->Get(vtkDataObject::FIELD_NAME())) == name
          : !info->Has(vtkDataObject::FIELD_NAME()));
  if (!same)
  {
    this->Superclass::SetInputArrayToProcess(idx, port, connection, fieldAssociation, name);
  }
}

void vtkWalkOnSpheresSolver::ModifiedKeepingSums()
{
  this->ChangingOnlyWalks = true;
  this->Modified();
  this->ChangingOnlyWalks = false;
}

void vtkWalkOnSpheresSolver::SetWalksPerPoint(int walks)
{
  walks = std::max(walks, 2);
  if (walks != this->GetSettings().WalksPerPoint)
  {
    this->GetSettings().WalksPerPoint = walks;
    // Only the walk count changed: the kept running sums stay valid.
    this->ModifiedKeepingSums();
  }
}

// The target decides where each point's walks stop: the kept sums are
// kept, and the core continues from them when the new target allows it
// (RunningSumsCache::CanResume; the target it compares is absolute, so a
// relative target's range is part of the decision).
void vtkWalkOnSpheresSolver::SetTargetStandardError(double target)
{
  target = std::isfinite(target) ? std::max(target, 0.0) : 0.0;
  if (target != this->GetSettings().TargetStandardError)
  {
    this->GetSettings().TargetStandardError = target;
    this->ModifiedKeepingSums();
  }
}

void vtkWalkOnSpheresSolver::SetTargetErrorIsRelative(bool relative)
{
  if (relative != this->GetSettings().TargetErrorIsRelative)
  {
    this->GetSettings().TargetErrorIsRelative = relative;
    this->ModifiedKeepingSums();
  }
}

// A larger factor only adds walks to flagged points: the kept sums continue,
// as one solve with it would. A smaller one solves afresh: kept points may
// hold more walks than it allows.
void vtkWalkOnSpheresSolver::SetWalkOnWhereUnreliable(int factor)
{
  if (factor < 1 || factor > 64)
  {
    vtkErrorMacro(<< "WalkOnWhereUnreliable must lie in [1, 64] (a factor of WalksPerPoint; 1 "
                     "turns walking on off), not "
                  << factor << "; it stays " << this->GetSettings().WalkOnWhereUnreliable << ".");
    return;
  }
  const int before = this->GetSettings().WalkOnWhereUnreliable;
  if (factor != before)
  {
    this->GetSettings().WalkOnWhereUnreliable = factor;
    if (factor > before)
    {
      this->ModifiedKeepingSums();
    }
    else
    {
      this->Modified();
    }
  }
}

int vtkWalkOnSpheresSolver::GetWalkOnWhereUnreliable()
{
  return this->GetSettings().WalkOnWhereUnreliable;
}

double vtkWalkOnSpheresSolver::GetTargetStandardError()
{
  return this->GetSettings().TargetStandardError;
}

bool vtkWalkOnSpheresSolver::GetTargetErrorIsRelative()
{
  return this->GetSettings().TargetErrorIsRelative;
}

void vtkWalkOnSpheresSolver::Resume()
{
  if (this->LastSolveAborted)
  {
    this->ModifiedKeepingSums();
  }
}

// Enumeration properties: a value that is none of the choices is an error
// that names them, and the property keeps its value (VTK's clamp would pick
// the nearest choice, which is another problem, silently).
namespace
{
bool IsChoice(vtkObject* self, const char* property, int value, int current,
  std::initializer_list<const char*> choices)
{
  const int count = static_cast<int>(choices.size());
  if (value >= 0 && value < count)
  {
    return true;
  }
  std::ostringstream names;
  int k = 0;
  for (const char* choice : choices)
  {
    names << (k ? ", " : "") << k << " " << choice;
    ++k;
  }
  vtkErrorWithObjectMacro(self, << "Set" << property << "(" << value << "): " << property
                                << " is one of " << names.str() << "; it stays "
                                << *(choices.begin() + std::min(std::max(current, 0), count - 1))
                                << ".");
  return false;
}

// The typed choice of an integer code already checked.
template <typename Choice>
void AssignCode(Choice& choice, int code)
{
  choice = static_cast<Choice>(code);
}

void AssignCode(std::optional<gridfree::CsgOperation>& operation, int code)
{
  operation = gridfree::CsgOperationOfCode(code);
}
} // namespace

#define GRIDFREE_CHOICE_SETTER(name, ...)                                                          \
  void vtkWalkOnSpheresSolver::Set##name(int value)                                                \
  {                                                                                                \
    const int current = gridfree::CodeOf(this->GetSettings().name);                               \
    if (IsChoice(this, #name, value, current, { __VA_ARGS__ }) && value != current)               \
    {                                                                                              \
      AssignCode(this->GetSettings().name, value);                                                 \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  int vtkWalkOnSpheresSolver::Get##name() { return gridfree::CodeOf(this->GetSettings().name); }
GRIDFREE_CHOICE_SETTER(
  Equation, "Laplace", "Poisson", "screened Poisson", "biharmonic", "varying coefficients")
GRIDFREE_CHOICE_SETTER(SourceOperator, "value", "divergence", "curl")
GRIDFREE_CHOICE_SETTER(
  SourceSampling, "uniform", "Green's function", "multiple importance", "source density",
  "automatic")
GRIDFREE_CHOICE_SETTER(ScreenedSteps, "automatic", "uniform", "guided")
GRIDFREE_CHOICE_SETTER(PeakSteps, "automatic", "uniform", "guided")
GRIDFREE_CHOICE_SETTER(BiharmonicStrategy, "tree walking", "nested")
GRIDFREE_CHOICE_SETTER(CsgOperation, "none", "union", "intersection", "difference")
#undef GRIDFREE_CHOICE_SETTER

GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, LipschitzBound, double, 1e-300, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, CsgBlendRadius, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, TwoSidedBoundaryValues, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, MixedBoundaryConditions, bool, false, true)
// Unclamped, as before: the problem's check reports a negative coefficient.
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, ScreeningCoefficient, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, NestedWalks, int, 1, VTK_INT_MAX)
// Unclamped: the problem builder names a coefficient that cannot be used.
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, DiffusionCoefficient, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, AbsorptionCoefficient, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, CoefficientSmoothing, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, DiffusionFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, AbsorptionFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, SourceTermFromArray, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, ComputeGradient, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, ComputeHessian, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, ControlVariates, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, AntitheticPairs, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, NearBoundarySplitting, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresSolver, ComputeDirectionalDerivative, bool, false, true)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolver, BoundaryValueExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolver, BoundaryLaplacianExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolver, SourceExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolver, DiffusionExpression)
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresSolver, AbsorptionExpression)
GRIDFREE_IMPLICIT_BOUNDARY_ACCESSORS(vtkWalkOnSpheresSolver)

void vtkWalkOnSpheresSolver::SetDerivativeDirection(double x, double y, double z)
{
  const std::array<double, 3> direction = { x, y, z };
  if (direction != this->GetSettings().DerivativeDirection)
  {
    this->GetSettings().DerivativeDirection = direction;
    this->Modified();
  }
}

void vtkWalkOnSpheresSolver::SetDerivativeDirection(const double direction[3])
{
  this->SetDerivativeDirection(direction[0], direction[1], direction[2]);
}

double* vtkWalkOnSpheresSolver::GetDerivativeDirection()
{
  return this->GetSettings().DerivativeDirection.data();
}

void vtkWalkOnSpheresSolver::GetDerivativeDirection(double direction[3])
{
  std::copy_n(this->GetSettings().DerivativeDirection.data(), 3, direction);
}

void vtkWalkOnSpheresSolver::SetTimeBudgetSeconds(double seconds)
{
  seconds = std::isfinite(seconds) ? std::max(seconds, 0.0) : 0.0;
  if (seconds != this->TimeBudgetSeconds)
  {
    this->TimeBudgetSeconds = seconds;
    // The budget only decides how far the walks go: kept sums stay valid.
    this->ModifiedKeepingSums();
  }
}

void vtkWalkOnSpheresSolver::Refine()
{
  auto twice = [](int walks) { return walks > VTK_INT_MAX / 2 ? VTK_INT_MAX : 2 * walks; };
  this->SetWalksPerPoint(twice(this->GetWalksPerPoint()));
  // A cache answers most points from its own walks: they double too (the
  // spheres or cache points continue their sample sequences).
  if (this->GetEstimator() == SPHERE_CACHE)
  {
    this->SetWalksPerSphere(twice(this->GetWalksPerSphere()));
  }
  else if (this->GetEstimator() == BOUNDARY_CACHE)
  {
    this->SetWalksPerCachePoint(twice(this->GetWalksPerCachePoint()));
  }
}

vtkWalkOnSpheresSolver::~vtkWalkOnSpheresSolver()
{
  this->SetImplicitBoundary(nullptr);
}

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
  if (vtkImplicitFunction* implicit = this->GetSettings().ImplicitBoundary)
  {
    time = std::max(time, implicit->GetMTime());
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

//------------------------------------------------------------------------------
void vtkWalkOnSpheresSolver::RemoveAllBoundaryConnections()
{
  this->RemoveAllInputConnections(BoundaryPort);
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
    // Several surfaces make one boundary (as the blocks of a composite).
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  }
  // The boundary mesh is optional when an implicit boundary is set. The
  // probe is not, but a missing one is reported by RequestData in words of
  // this filter ("No Probe input ...") rather than by the executive.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
// The output is a copy of the probe's structure: make it the probe's type.
int vtkWalkOnSpheresSolver::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!probe)
  {
    // An empty polygonal output until a probe is connected, so that the
    // missing input is reported once, by RequestData, in one line.
    if (!vtkDataSet::GetData(outInfo))
    {
      vtkNew<vtkPolyData> empty;
      outInfo->Set(vtkDataObject::DATA_OBJECT(), empty);
    }
    return 1;
  }
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
    for (int c = 0; c < inputVector[port]->GetNumberOfInformationObjects(); ++c)
    {
      this->RequestSharedInput(inputVector[port]->GetInformationObject(c));
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
// The public enumerations are the core's choices, code for code (the
// settings convert by value).
static_assert(vtkWalkOnSpheresSolver::LAPLACE == static_cast<int>(gridfree::Equation::Laplace) &&
  vtkWalkOnSpheresSolver::POISSON == static_cast<int>(gridfree::Equation::Poisson) &&
  vtkWalkOnSpheresSolver::SCREENED_POISSON ==
    static_cast<int>(gridfree::Equation::ScreenedPoisson) &&
  vtkWalkOnSpheresSolver::BIHARMONIC == static_cast<int>(gridfree::Equation::Biharmonic) &&
  vtkWalkOnSpheresSolver::VARYING_COEFFICIENTS ==
    static_cast<int>(gridfree::Equation::VaryingCoefficients));
static_assert(vtkWalkOnSpheresSolver::UNIFORM == static_cast<int>(gridfree::SourceSampling::Uniform) &&
  vtkWalkOnSpheresSolver::GREENS_FUNCTION ==
    static_cast<int>(gridfree::SourceSampling::GreensFunction) &&
  vtkWalkOnSpheresSolver::MULTIPLE_IMPORTANCE ==
    static_cast<int>(gridfree::SourceSampling::MultipleImportance) &&
  vtkWalkOnSpheresSolver::SOURCE_DENSITY ==
    static_cast<int>(gridfree::SourceSampling::SourceDensity) &&
  vtkWalkOnSpheresSolver::AUTOMATIC_SOURCE_SAMPLING ==
    static_cast<int>(gridfree::SourceSampling::Automatic));
static_assert(vtkWalkOnSpheresSolver::SOURCE_VALUE == static_cast<int>(gridfree::SourceOperator::Value) &&
  vtkWalkOnSpheresSolver::SOURCE_DIVERGENCE ==
    static_cast<int>(gridfree::SourceOperator::Divergence) &&
  vtkWalkOnSpheresSolver::SOURCE_CURL == static_cast<int>(gridfree::SourceOperator::Curl));
static_assert(vtkWalkOnSpheresSolver::SCREENED_STEPS_AUTOMATIC ==
    static_cast<int>(gridfree::ScreenedSteps::Automatic) &&
  vtkWalkOnSpheresSolver::SCREENED_STEPS_UNIFORM ==
    static_cast<int>(gridfree::ScreenedSteps::Uniform) &&
  vtkWalkOnSpheresSolver::SCREENED_STEPS_GUIDED == static_cast<int>(gridfree::ScreenedSteps::Guided));
static_assert(vtkWalkOnSpheresSolver::PEAK_STEPS_AUTOMATIC ==
    static_cast<int>(gridfree::PeakSteps::Automatic) &&
  vtkWalkOnSpheresSolver::PEAK_STEPS_UNIFORM == static_cast<int>(gridfree::PeakSteps::Uniform) &&
  vtkWalkOnSpheresSolver::PEAK_STEPS_GUIDED == static_cast<int>(gridfree::PeakSteps::Guided));
static_assert(vtkWalkOnSpheresSolver::TREE_WALKING ==
    static_cast<int>(gridfree::BiharmonicStrategy::TreeWalking) &&
  vtkWalkOnSpheresSolver::NESTED == static_cast<int>(gridfree::BiharmonicStrategy::Nested));

//------------------------------------------------------------------------------
// The Boundary port's data: its one connection's, or the surfaces of several
// connections as the blocks of one composite (the probe left out: ParaView's
// input dialog first puts every selected dataset on the Boundary).
vtkDataObject* vtkWalkOnSpheresSolver::BoundaryOf(
  vtkInformationVector* connections, vtkDataObject* probe)
{
  std::vector<vtkDataObject*> surfaces;
  for (int c = 0; c < connections->GetNumberOfInformationObjects(); ++c)
  {
    vtkDataObject* data = vtkDataObject::GetData(connections, c);
    if (data)
    {
      surfaces.push_back(data);
    }
  }
  if (surfaces.size() > 1)
  {
    surfaces.erase(std::remove(surfaces.begin(), surfaces.end(), probe), surfaces.end());
  }
  if (surfaces.size() <= 1)
  {
    return surfaces.empty() ? nullptr : surfaces[0];
  }
  this->AssembledBoundary = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  this->AssembledBoundary->SetNumberOfBlocks(static_cast<unsigned int>(surfaces.size()));
  for (std::size_t b = 0; b < surfaces.size(); ++b)
  {
    this->AssembledBoundary->SetBlock(static_cast<unsigned int>(b), surfaces[b]);
  }
  return this->AssembledBoundary;
}

//------------------------------------------------------------------------------
int vtkWalkOnSpheresSolver::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  this->LastDimension = 0;
  this->LastResumedWalksPerPoint = 0;
  this->LastPointsShortOfTarget = 0;
  this->LastUnreliableErrorBars = 0;
  this->LastWalksPerPointReached = 0;
  this->LastSolveAborted = false;

  // The inputs as this rank received them: what kept running sums are keyed on.
  vtkDataObject* const boundaryPiece = this->BoundaryOf(
    inputVector[BoundaryPort], vtkDataObject::GetData(inputVector[ProbePort], 0));
  vtkDataObject* const sourcePiece = vtkDataObject::GetData(inputVector[SourcePort], 0);
  // A distributed run gathers the boundary and source first, before anything
  // can return early: every rank must take part in the exchange.
  vtkWalkOnSpheresSolverPieces pieces;
  if (!this->GatherInputs(boundaryPiece, sourcePiece, pieces))
  {
    return 0;
  }
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);

  // The inputs and settings checked, the arrays resolved.
  const gridfree::SolveSettings& settings = this->GetSettings();
  gridfree::ProblemData data;
  data.Boundary = pieces.Boundary.Whole;
  data.BoundaryPiece = boundaryPiece;
  data.GatheredSignature = pieces.Boundary.Signature;
  data.Source = pieces.Source.Whole;
  data.Region = probe;
  gridfree::ProblemBuilder& builder = this->KeptBuilder(0);
  if (!builder.Resolve(this, settings, gridfree::ArraySelections::Of(this), data))
  {
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

  // Kept running sums stay usable only if nothing but WalksPerPoint changed.
  // (Gathered inputs are new objects at each execution: the sums are keyed on
  // this rank's pieces and on the signature of every rank's pieces.)
  const std::array<vtkObject*, 4> used = { boundaryPiece, probe, sourcePiece,
    this->GetSettings().ImplicitBoundary };
  const std::uint64_t gatheredSignature = pieces.Boundary.Signature ^
    (pieces.Source.Signature * 1099511628211ULL);
  this->Cache->Validate(this->SettingsTime.GetMTime(), used, gatheredSignature);
  if (!this->KeepRunningSums)
  {
    this->Cache->Sums.Clear();
  }

  gridfree::BuiltProblem problem;
  bool ok = builder.Build(this, problem);
  this->NoteBoundaryBuilt(builder.GetLastBoundaryBuilt());
  if (!ok && builder.GetLastBuildAborted())
  {
    // Aborted before any walk (the builder's warning says so): the probe
    // passes through without solution arrays, and the next update starts
    // over.
    this->Cache->Sums.Clear();
    this->LastSolveAborted = true;
    this->LastNumberOfWalks = 0;
    this->UpdateProgress(1.0);
    return 1;
  }
  if (ok)
  {
    const std::vector<std::array<double, 3>> points = gridfree::PointsOf(probe);
    gridfree::PointEstimateRun run;
    // A time budget's rounds continue from each other's sums, kept or not.
    const bool budgeted = this->TimeBudgetSeconds > 0.0;
    run.Kept = this->KeepRunningSums || budgeted ? &this->Cache->Sums : nullptr;
    run.Warn = [this](const std::string& text) { vtkWarningMacro(<< text); };
    gridfree::PointEstimateSummary summary;
    try
    {
      // False when aborted: each point shows the walks it holds (NaN where
      // it holds none), and the warning says so.
      if (budgeted)
      {
        gridfree::TimeBudgetSummary rounds;
        if (gridfree::EstimateWithinTimeBudget(this, problem, settings, this->TimeBudgetSeconds,
              points, output->GetPointData(), output->GetFieldData(), run, summary, rounds))
        {
          this->LastWalksPerPointReached = rounds.WalksPerPointReached;
        }
      }
      else if (gridfree::EstimateAtPoints(this, problem, settings, points,
                 output->GetPointData(), output->GetFieldData(), run, summary))
      {
        this->LastWalksPerPointReached = settings.WalksPerPoint;
      }
      if (!this->KeepRunningSums)
      {
        this->Cache->Sums.Clear();
      }
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro(<< "Walk on spheres failed: " << e.what());
      ok = false;
    }
    // Walks run now; the output stands for TotalWalks (kept ones included).
    this->LastNumberOfWalks = static_cast<vtkIdType>(summary.WalksRun);
    this->LastSolveSeconds = summary.Seconds;
    this->LastDimension = problem.Dimension;
    this->LastResumedWalksPerPoint = summary.ResumedWalksPerPoint;
    this->LastPointsShortOfTarget = static_cast<vtkIdType>(summary.PointsShortOfTarget);
    this->LastUnreliableErrorBars = static_cast<vtkIdType>(summary.UnreliableErrorBars);
    this->LastSolveAborted = ok && !summary.Completed;
  }
  if (!ok)
  {
    this->Cache->Sums.Clear();
    builder.Forget();
  }
  this->Cache->Remember(this->SettingsTime.GetMTime(), used, gatheredSignature);
  if (ok && pieces.Distributed)
  {
    vtkFieldData* fd = output->GetFieldData();
    gridfree::AddFieldValue(fd, "BoundaryPiecesGathered", pieces.Boundary.ContributingRanks);
    gridfree::AddFieldValue(fd, "SourcePiecesGathered", pieces.Source.ContributingRanks);
  }
  this->UpdateProgress(1.0);
  return ok ? 1 : 0;
}

//------------------------------------------------------------------------------
void vtkWalkOnSpheresSolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  gridfree::PrintProblemSettings(os, indent, this->GetSettings());
  os << indent << "KeepRunningSums: " << (this->KeepRunningSums ? "On" : "Off") << "\n";
  os << indent << "LastNumberOfWalks: " << this->LastNumberOfWalks << "\n";
  os << indent << "LastResumedWalksPerPoint: " << this->LastResumedWalksPerPoint << "\n";
  os << indent << "LastPointsShortOfTarget: " << this->LastPointsShortOfTarget << "\n";
  os << indent << "LastUnreliableErrorBars: " << this->LastUnreliableErrorBars << "\n";
  os << indent << "TimeBudgetSeconds: " << this->TimeBudgetSeconds << "\n";
  os << indent << "LastWalksPerPointReached: " << this->LastWalksPerPointReached << "\n";
  os << indent << "LastSolveAborted: " << (this->LastSolveAborted ? "On" : "Off") << "\n";
  os << indent << "LastSolveSeconds: " << this->LastSolveSeconds << "\n";
  os << indent << "LastDimension: " << this->LastDimension << "\n";
}
