#include "vtkWalkOnSpheresAlgorithm.h"

#include "GridFreeProblemBuilder.h"
#include "GridFreeSettingAccessors.h"
#include "GridFreeSolveSettings.h"

#include "vtkDemandDrivenPipeline.h"
#include "vtkInformation.h"

#include <map>
#include <memory>

// The settings, and the builders of the subclass's solves by number.
struct vtkWalkOnSpheresAlgorithm::State
{
  gridfree::SolveSettings Settings;
  std::map<int, std::unique_ptr<gridfree::ProblemBuilder>> Builders;
  bool LastBoundaryBuilt = false;
};

vtkWalkOnSpheresAlgorithm::vtkWalkOnSpheresAlgorithm()
  : Kept(new State)
{
}

vtkWalkOnSpheresAlgorithm::~vtkWalkOnSpheresAlgorithm() = default;

GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, WalksPerPoint, int, 2, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, Epsilon, double, 0.0, VTK_DOUBLE_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, EpsilonIsRelative, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, MaxSteps, int, 1, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, Seed, int, VTK_INT_MIN, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, NumberOfThreads, int, 0, VTK_INT_MAX)
GRIDFREE_CHOICE_ACCESSORS(vtkWalkOnSpheresAlgorithm, Estimator, gridfree::Estimator, 2)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, CachePoints, int, 2, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, WalksPerCachePoint, int, 2, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, CacheVolumePoints, int, 2, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, CacheOffset, double, 1e-6, 0.5)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, CacheShellDistance, double, 0.0, 1.0)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, WalksPerSphere, int, 4, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, CacheSourceSamples, int, 2, VTK_INT_MAX)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresAlgorithm, PolynomialControlVariate, int, 0, 12)

gridfree::SolveSettings& vtkWalkOnSpheresAlgorithm::GetSettings()
{
  return this->Kept->Settings;
}

const gridfree::SolveSettings& vtkWalkOnSpheresAlgorithm::GetSettings() const
{
  return this->Kept->Settings;
}

bool vtkWalkOnSpheresAlgorithm::GetLastBoundaryBuilt()
{
  return this->Kept->LastBoundaryBuilt;
}

vtkTypeBool vtkWalkOnSpheresAlgorithm::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputs, vtkInformationVector* outputs)
{
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA()))
  {
    this->Kept->LastBoundaryBuilt = false;
  }
  return this->Superclass::ProcessRequest(request, inputs, outputs);
}

bool vtkWalkOnSpheresAlgorithm::BuildKeptProblem(int problem,
  const gridfree::SolveSettings& settings, const gridfree::ArraySelections& arrays,
  const gridfree::ProblemData& data, gridfree::BuiltProblem& built)
{
  gridfree::ProblemBuilder& builder = this->KeptBuilder(problem);
  if (!builder.Build(this, settings, arrays, data, built))
  {
    return false;
  }
  this->NoteBoundaryBuilt(builder.GetLastBoundaryBuilt());
  return true;
}

gridfree::ProblemBuilder& vtkWalkOnSpheresAlgorithm::KeptBuilder(int problem)
{
  std::unique_ptr<gridfree::ProblemBuilder>& builder = this->Kept->Builders[problem];
  if (!builder)
  {
    builder.reset(new gridfree::ProblemBuilder);
  }
  return *builder;
}

void vtkWalkOnSpheresAlgorithm::NoteBoundaryBuilt(bool built)
{
  this->Kept->LastBoundaryBuilt |= built;
}

void vtkWalkOnSpheresAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const gridfree::SolveSettings& s = this->Kept->Settings;
  os << indent << "WalksPerPoint: " << s.WalksPerPoint << "\n";
  os << indent << "Epsilon: " << s.Epsilon << "\n";
  os << indent << "EpsilonIsRelative: " << (s.EpsilonIsRelative ? "On" : "Off") << "\n";
  os << indent << "MaxSteps: " << s.MaxSteps << "\n";
  os << indent << "Seed: " << s.Seed << "\n";
  os << indent << "NumberOfThreads: " << s.NumberOfThreads << "\n";
  os << indent << "Estimator: " << gridfree::CodeOf(s.Estimator) << "\n";
  os << indent << "CachePoints: " << s.CachePoints << "\n";
  os << indent << "WalksPerCachePoint: " << s.WalksPerCachePoint << "\n";
  os << indent << "CacheVolumePoints: " << s.CacheVolumePoints << "\n";
  os << indent << "CacheOffset: " << s.CacheOffset << "\n";
  os << indent << "CacheShellDistance: " << s.CacheShellDistance << "\n";
  os << indent << "WalksPerSphere: " << s.WalksPerSphere << "\n";
  os << indent << "PolynomialControlVariate: " << s.PolynomialControlVariate << "\n";
  os << indent << "CacheSourceSamples: " << s.CacheSourceSamples << "\n";
  os << indent << "LastBoundaryBuilt: " << this->Kept->LastBoundaryBuilt << "\n";
}
