#include "GridFreeProblemBuilder.h"

#include "GridFreeBoundaryAssembly.h"
#include "GridFreeCacheSlot.h"
#include "GridFreeCoefficientConversion.h"
#include "GridFreeBoundaryValueArrays.h"
#include "GridFreeInputFingerprint.h"
#include "GridFreeProblemInputs.h"
#include "GridFreeSourceConversion.h"

#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/execution/PreparationMonitor.h>
#include <gridfree/problem/PolynomialShiftFit.h>

#include "vtkAlgorithm.h"
#include "vtkAppendPolyData.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkImplicitFunction.h"
#include "vtkNew.h"
#include "vtkCellData.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
namespace
{
// The spread of the boundary values g, max - min over their components and
// over every array that holds them (CSG operands; a two-sided boundary's
// front and back); NaN when g is given by expressions only.
double ValueRangeOf(const ProblemInputs& in, int nc, bool biharmonic)
{
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  auto add = [&](vtkDataArray* values)
  {
    // Biharmonic values hold g and then h: only g's components count.
    const int components = values ? values->GetNumberOfComponents() : 0;
    for (int c = 0; c < (biharmonic ? std::min(nc, components) : components); ++c)
    {
      double range[2];
      values->GetRange(range, c);
      lo = std::min(lo, range[0]);
      hi = std::max(hi, range[1]);
    }
  };
  add(in.Values);
  for (const auto& operand : in.CsgValues)
  {
    add(operand);
  }
  return hi >= lo ? hi - lo : std::numeric_limits<double>::quiet_NaN();
}

// The arrays of mixed boundary conditions on the boundary mesh: the
// condition (selection 4, needed), the Neumann flux (5) and the Robin
// coefficient (6), each a point or cell array; false after an error.
bool ResolveMixedArrays(vtkObject* self, const ArraySelections& arrays, vtkPolyData* boundary,
  vtkDataArray* values, ProblemInputs& inputs)
{
  // ParaView's "None" entry of an optional array list.
  auto none = [&](int index) {
    const ArraySelection& s = arrays.Index[static_cast<std::size_t>(index)];
    return !s.Selected ||
      (s.Name == "None" && !boundary->GetPointData()->GetAbstractArray("None") &&
        !boundary->GetCellData()->GetAbstractArray("None"));
  };
  const char* const labels[] = { "boundary condition", "Neumann flux", "Robin coefficient" };
  vtkDataArray* found[3] = { nullptr, nullptr, nullptr };
  bool onCells[3] = { true, false, true };
  for (int k = 0; k < 3; ++k)
  {
    const int index = 4 + k;
    if (none(index))
    {
      continue;
    }
    int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    std::string reason;
    found[k] = arrays.Resolve(index, boundary, false, association, reason);
    if (!found[k])
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the " << labels[k] << " array: "
                                    << (reason.empty() ? "it is not on the Boundary input" : reason)
                                    << ".");
      return false;
    }
    if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS &&
      association != vtkDataObject::FIELD_ASSOCIATION_CELLS)
    {
      vtkErrorWithObjectMacro(self, << "The " << labels[k] << " array must be point or cell data "
                                       "of the Boundary input.");
      return false;
    }
    onCells[k] = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  if (!found[0])
  {
    vtkErrorWithObjectMacro(self, << "Mixed Boundary Conditions is on, but no Boundary Condition "
                                     "Array is chosen: choose the point or cell array of the "
                                     "Boundary input that holds 0 (Dirichlet), 1 (Neumann) or 2 "
                                     "(Robin) for each cell (in ParaView's panel under Boundary "
                                     "Conditions; from Python or C++ it is input array 4), or "
                                     "turn Mixed Boundary Conditions off.");
    return false;
  }
  if (found[0] == values)
  {
    vtkWarningWithObjectMacro(self, << "The boundary condition array is also the boundary "
                                       "values' array: check the selections.");
  }
  inputs.Mixed = true;
  inputs.Conditions = found[0];
  inputs.ConditionsOnCells = onCells[0];
  inputs.Flux = found[1];
  inputs.FluxOnCells = onCells[1];
  inputs.Robin = found[2];
  inputs.RobinOnCells = onCells[2];
  return true;
}
} // namespace

struct ProblemBuilder::Internals
{
  // What the last Resolve found.
  SolveSettings Settings;
  ProblemInputs Inputs;
  int Dimension = 3;
  vtkSmartPointer<vtkDataArray> Values;        // g (and h, or the back's g)
  vtkSmartPointer<vtkPolyData> MergedBoundary; // the blocks of a composite, as one soup
  bool Resolved = false;

  // The last boundary built and what it was built from.
  std::vector<std::uint64_t> BoundaryKey;
  std::shared_ptr<const Boundary<2>> Boundary2;
  std::shared_ptr<const Boundary<3>> Boundary3;
  // The same for mixed boundary conditions.
  std::shared_ptr<const MixedBoundary<2>> Mixed2;
  std::shared_ptr<const MixedBoundary<3>> Mixed3;
  // The caches' slot, what every cache in it is built from, and what each
  // kind's own settings are.
  std::vector<std::uint64_t> CacheKey, BoundaryCacheKey, SphereCacheKey;
  std::shared_ptr<CacheSlot> Caches;

  template <int DIM>
  std::shared_ptr<const Boundary<DIM>>& CachedBoundary()
  {
    if constexpr (DIM == 2)
    {
      return this->Boundary2;
    }
    else
    {
      return this->Boundary3;
    }
  }

  template <int DIM>
  std::shared_ptr<const MixedBoundary<DIM>>& CachedMixed()
  {
    if constexpr (DIM == 2)
    {
      return this->Mixed2;
    }
    else
    {
      return this->Mixed3;
    }
  }

  // What the core boundary is built from: the Boundary input's piece (and
  // the signature of the gathered pieces), the implicit boundary, the
  // selected value arrays and the settings that shape the boundary; for
  // implicit and CSG boundaries, the bounds of the region's points.
  std::vector<std::uint64_t> MakeKey(
    const ProblemData& data, const ArraySelections& arrays, vtkDataSet* regionProbe) const
  {
    const ProblemInputs& in = this->Inputs;
    std::vector<std::uint64_t> key{ static_cast<std::uint64_t>(this->Dimension),
      data.GatheredSignature };
    auto addString = [&key](const std::string& s) { AppendString(s, key); };
    auto addDouble = [&key](double v) { AppendDouble(v, key); };
    for (vtkObject* object : { static_cast<vtkObject*>(data.BoundaryPiece),
           static_cast<vtkObject*>(this->Settings.ImplicitBoundary) })
    {
      AppendFingerprint(object, key);
      key.push_back(~std::uint64_t(0));
    }
    // The arrays selected for g, h and the back side's g.
    for (int idx : { 0, 1, 3, 4, 5, 6 })
    {
      const ArraySelection& s = arrays.Index[static_cast<std::size_t>(idx)];
      addString(s.Name);
      key.push_back(s.Selected ? static_cast<std::uint64_t>(s.Association) : ~std::uint64_t(0));
      key.push_back(s.AttributeType >= 0 ? static_cast<std::uint64_t>(s.AttributeType)
                                         : ~std::uint64_t(0));
    }
    for (const std::string& e : in.ValueExpressions)
    {
      addString(e);
    }
    addString(in.Name);
    key.push_back(in.CellData ? 1 : 0);
    key.push_back(in.TwoSided ? 1 : 0);
    key.push_back(in.Mixed ? 1 : 0);
    // The values hold g and h.
    key.push_back(this->Settings.Equation == Equation::Biharmonic ? 1 : 0);
    key.push_back(static_cast<std::uint64_t>(CodeOf(in.CsgOperation)));
    addDouble(in.CsgBlendRadius);
    addDouble(this->Settings.LipschitzBound);
    if (regionProbe)
    {
      double bounds[6];
      regionProbe->GetBounds(bounds);
      for (double b : bounds)
      {
        addDouble(b);
      }
    }
    return key;
  }

  // What a solution cache is built from: the boundary's key, the source
  // and its array or expression, the equation, the walks' settings and the
  // seed.
  std::vector<std::uint64_t> MakeCacheKey(const WalkSettings& walk) const
  {
    const ProblemInputs& in = this->Inputs;
    const SolveSettings& s = this->Settings;
    std::vector<std::uint64_t> key = in.BoundaryKey;
    for (vtkObject* object :
      { static_cast<vtkObject*>(in.Source), static_cast<vtkObject*>(in.SourceArray) })
    {
      AppendFingerprint(object, key);
      key.push_back(~std::uint64_t(0));
    }
    AppendString(in.Expression, key);
    AppendDouble(walk.Epsilon, key);
    AppendDouble(walk.ScreeningCoefficient, key);
    // Every walk setting is in it: the kept shifted problem (the
    // polynomial control variate) walks with the settings it was made with.
    for (int v : { walk.MaxSteps, static_cast<int>(walk.Problem), static_cast<int>(walk.Sampling),
           static_cast<int>(walk.Screening), static_cast<int>(s.SourceOperator), s.Seed,
           s.PolynomialControlVariate, static_cast<int>(walk.Biharmonic), walk.NestedWalks,
           static_cast<int>(walk.NearBoundarySplitting), static_cast<int>(walk.MixedBothSides) })
    {
      key.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)));
    }
    return key;
  }

  // The slot for `out`: the same while the cache key holds; a cache kind
  // whose own settings changed is dropped (the walks per cache point or
  // per sphere are not among them: a cache grows to more walks,
  // GridFreeCacheAnswers.h).
  void KeepCaches(const WalkSettings& walk, BuiltProblem& out)
  {
    const SolveSettings& s = this->Settings;
    std::vector<std::uint64_t> key = this->MakeCacheKey(walk);
    if (!this->Caches || key != this->CacheKey)
    {
      this->Caches = std::make_shared<CacheSlot>();
      this->CacheKey = std::move(key);
    }
    std::vector<std::uint64_t> boundary, spheres;
    AppendDouble(s.CacheOffset, boundary);
    AppendDouble(s.CacheShellDistance, boundary);
    boundary.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(s.CachePoints)));
    boundary.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(s.CacheVolumePoints)));
    AppendDouble(s.CacheShellDistance, spheres);
    if (boundary != this->BoundaryCacheKey)
    {
      this->Caches->Boundary2.reset();
      this->Caches->Boundary3.reset();
      this->BoundaryCacheKey = std::move(boundary);
    }
    if (spheres != this->SphereCacheKey)
    {
      this->Caches->Spheres2.reset();
      this->Caches->Spheres3.reset();
      this->SphereCacheKey = std::move(spheres);
    }
    out.Caches = this->Caches;
  }

  template <int DIM>
  bool Make(vtkObject* self, ProblemBuilder& builder, BuiltProblem& out);

  // The problem of w = u − P (the polynomial control variate), kept while
  // its data, equation and degree stay the same: the fit and the copy of
  // the boundary it reads g − P from are made once, not at every moved
  // probe.
  std::vector<std::uint64_t> ShiftKey;
  std::shared_ptr<const Problem<2>> Shifted2;
  std::shared_ptr<const Problem<3>> Shifted3;

  template <int DIM>
  std::shared_ptr<const Problem<DIM>>& ShiftedProblem()
  {
    if constexpr (DIM == 2)
    {
      return this->Shifted2;
    }
    else
    {
      return this->Shifted3;
    }
  }

  // The coefficients of the varying equation, kept while their image, its
  // arrays, the constants, the smoothing and the domain stay the same (the
  // smoothing and the bound grid are the expensive part of a build).
  std::vector<std::uint64_t> CoefficientKey;
  // Whether the last preparation of the coefficients was aborted.
  bool PreparationAborted = false;
  std::shared_ptr<const CoefficientModel<2>> Coefficients2;
  std::shared_ptr<const CoefficientModel<3>> Coefficients3;

  template <int DIM>
  std::shared_ptr<const CoefficientModel<DIM>> CoefficientsFor(
    vtkObject* self, const BoundingBox<DIM>& domain)
  {
    const ProblemInputs& in = this->Inputs;
    const SolveSettings& s = this->Settings;
    std::vector<std::uint64_t> key{ static_cast<std::uint64_t>(DIM) };
    for (vtkObject* object : { static_cast<vtkObject*>(in.CoefficientImage),
           static_cast<vtkObject*>(in.DiffusionArray), static_cast<vtkObject*>(in.AbsorptionArray),
           static_cast<vtkObject*>(in.CoefficientSourceArray) })
    {
      AppendFingerprint(object, key);
      key.push_back(~std::uint64_t(0));
    }
    for (double v : { s.DiffusionCoefficient, s.AbsorptionCoefficient, s.CoefficientSmoothing })
    {
      AppendDouble(v, key);
    }
    for (const std::string* text :
      { &s.DiffusionExpression, &s.AbsorptionExpression, &s.SourceExpression })
    {
      key.push_back(static_cast<std::uint64_t>(std::hash<std::string>{}(*text)));
    }
    for (int i = 0; i < DIM; ++i)
    {
      AppendDouble(domain.Min[i], key);
      AppendDouble(domain.Max[i], key);
    }
    auto& kept = [this]() -> std::shared_ptr<const CoefficientModel<DIM>>& {
      if constexpr (DIM == 2)
      {
        return this->Coefficients2;
      }
      else
      {
        return this->Coefficients3;
      }
    }();
    if (kept && key == this->CoefficientKey)
    {
      return kept;
    }
    std::string reason;
    bool stopped = false;
    PreparationMonitor monitor;
    auto prepare = [&] {
      try
      {
        kept = MakeCoefficientModel<DIM>(in, s, domain, reason, &monitor);
      }
      catch (const PreparationStopped&)
      {
        kept = nullptr;
        stopped = true;
      }
    };
    if (vtkAlgorithm* algorithm = vtkAlgorithm::SafeDownCast(self))
    {
      // The smoothing and the bound grid take about a second on a small CT
      // and grow with the image: on a thread of their own, while this one
      // reports their progress under a label of their own and passes an
      // Abort on to them.
      const bool hadText = algorithm->GetProgressText() != nullptr;
      const std::string before = hadText ? algorithm->GetProgressText() : "";
      std::string name = before;
      if (name.empty())
      {
        name = algorithm->GetClassName();
        name = name.rfind("vtk", 0) == 0 ? name.substr(3) : name;
      }
      algorithm->SetProgressText((name + ", preparing the coefficients").c_str());
      algorithm->UpdateProgress(0.0);
      double shown = 0.0;
      RunWhileReporting(prepare, [&](double) {
        shown = std::max(shown, monitor.Fraction());
        algorithm->UpdateProgress(shown);
        if (algorithm->GetAbortExecute())
        {
          monitor.Stop = true;
        }
      });
      algorithm->SetProgressText(hadText ? before.c_str() : nullptr);
    }
    else
    {
      prepare();
    }
    this->PreparationAborted = stopped;
    if (!kept)
    {
      this->CoefficientKey.clear();
      if (stopped)
      {
        vtkWarningWithObjectMacro(self, << "The solve was aborted while the coefficients were "
                                           "prepared (smoothing the image and bounding the "
                                           "screening): nothing was solved. Apply again to "
                                           "start over.");
      }
      else
      {
        vtkErrorWithObjectMacro(self, << "Cannot use the coefficients: " << reason << ".");
      }
      return nullptr;
    }
    this->CoefficientKey = std::move(key);
    return kept;
  }
};

ProblemBuilder::ProblemBuilder()
  : Internal(new Internals)
{
}

ProblemBuilder::~ProblemBuilder() = default;

void ProblemBuilder::Forget()
{
  this->Internal->BoundaryKey.clear();
  this->Internal->Boundary2.reset();
  this->Internal->Boundary3.reset();
  this->Internal->Mixed2.reset();
  this->Internal->Mixed3.reset();
  this->Internal->CacheKey.clear();
  this->Internal->Caches.reset();
  this->Internal->CoefficientKey.clear();
  this->Internal->Coefficients2.reset();
  this->Internal->Coefficients3.reset();
  this->Internal->ShiftKey.clear();
  this->Internal->Shifted2.reset();
  this->Internal->Shifted3.reset();
}

bool ProblemBuilder::Resolve(vtkObject* self, const SolveSettings& settings,
  const ArraySelections& arrays, const ProblemData& data)
{
  Internals& state = *this->Internal;
  state.Resolved = false;
  state.Settings = settings;
  state.Inputs = ProblemInputs();
  state.Values = nullptr;
  state.MergedBoundary = nullptr;
  ProblemInputs& inputs = state.Inputs;

  vtkDataObject* boundaryObject = data.Boundary;
  vtkDataObject* sourceObject = data.Source;
  vtkPolyData* boundary = vtkPolyData::SafeDownCast(boundaryObject);
  vtkDataSet* source = vtkDataSet::SafeDownCast(sourceObject);
  if (sourceObject && !source)
  {
    vtkErrorWithObjectMacro(self, << "The Source input is a " << sourceObject->GetClassName()
                                  << ", not a dataset.");
    return false;
  }
  const bool implicit = settings.ImplicitBoundary != nullptr;
  const bool csg = settings.CsgOperation.has_value();
  const bool biharmonicEquation = settings.Equation == Equation::Biharmonic;

  // A composite boundary: its vtkPolyData leaves are the CSG operands, or,
  // without CSG, one polygon soup.
  std::vector<vtkPolyData*> blocks;
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
        vtkErrorWithObjectMacro(self,
          << "Block " << index << " of the Boundary input is a "
          << (leaf ? leaf->GetClassName() : "null object")
          << ", not a vtkPolyData: every block of a composite boundary must be a "
             "surface (or, in 2D, lines).");
        return false;
      }
      blocks.push_back(poly);
    }
    if (blocks.empty())
    {
      vtkErrorWithObjectMacro(self, << "The composite Boundary input has no vtkPolyData blocks.");
      return false;
    }
    if (!csg)
    {
      vtkNew<vtkAppendPolyData> merged;
      for (vtkPolyData* block : blocks)
      {
        merged->AddInputData(block);
      }
      merged->Update();
      state.MergedBoundary = merged->GetOutput();
      boundary = state.MergedBoundary;
    }
  }
  else if (csg && boundary)
  {
    blocks.push_back(boundary); // one closed mesh is one operand
  }
  if (csg && blocks.size() + (implicit ? 1 : 0) == 1)
  {
    vtkWarningWithObjectMacro(self, << "CsgOperation is set, but there is one operand only ("
                                    << (implicit ? "the ImplicitBoundary" : "one Boundary surface")
                                    << "): nothing is combined. CSG combines the blocks of a "
                                       "multiblock Boundary (or several Boundary connections) "
                                       "and the ImplicitBoundary.");
  }
  if (csg)
  {
    boundary = nullptr;
  }
  if (!boundary && blocks.empty() && !implicit)
  {
    vtkErrorWithObjectMacro(self, << "No Boundary input: connect a vtkPolyData with boundary "
                                     "values to port 0, or set an ImplicitBoundary.");
    return false;
  }

  std::string reason;
  // Boundary values from expressions (g, and h for the biharmonic equation).
  if (!settings.BoundaryValueExpression.empty())
  {
    inputs.ValueExpressions.push_back(settings.BoundaryValueExpression);
    if (biharmonicEquation)
    {
      if (settings.BoundaryLaplacianExpression.empty())
      {
        vtkErrorWithObjectMacro(self, << "The biharmonic equation with BoundaryValueExpression "
                                         "also needs BoundaryLaplacianExpression (h = Δu on the "
                                         "boundary).");
        return false;
      }
      inputs.ValueExpressions.push_back(settings.BoundaryLaplacianExpression);
    }
    for (const std::string& e : inputs.ValueExpressions)
    {
      if (!CheckSourceExpression(e, reason))
      {
        vtkErrorWithObjectMacro(
          self, << "Cannot use the boundary value expression '" << e << "': " << reason << ".");
        return false;
      }
    }
  }
  const bool expressionValues = !inputs.ValueExpressions.empty();
  if (implicit && !expressionValues && !boundary && !csg)
  {
    vtkErrorWithObjectMacro(self, << "The implicit boundary has no values: set "
                                     "BoundaryValueExpression, or connect a mesh with boundary "
                                     "values to port 0 to sample them from.");
    return false;
  }
  if (implicit && expressionValues && boundary)
  {
    vtkWarningWithObjectMacro(self, << "The Boundary input is not used: the implicit boundary "
                                       "takes its values from BoundaryValueExpression.");
    boundary = nullptr;
  }

  if (settings.TwoSidedBoundaryValues)
  {
    // The side test needs the mesh's orientation and the value table.
    if (csg || implicit || expressionValues)
    {
      vtkErrorWithObjectMacro(self,
        << "Two-sided boundary values need a mesh boundary with front and back arrays: they "
           "cannot be used with "
        << (csg ? "a CSG boundary"
                : (implicit ? "an implicit boundary" : "BoundaryValueExpression"))
        << ".");
      return false;
    }
    if (biharmonicEquation)
    {
      vtkErrorWithObjectMacro(self, << "Two-sided boundary values are not available for the "
                                       "biharmonic equation: use the Laplace, Poisson or "
                                       "screened Poisson equation.");
      return false;
    }
  }

  if (settings.MixedBoundaryConditions)
  {
    // Walk on stars: the reflecting part must be a mesh whose orientation
    // is known.
    const char* unsupported = csg ? "a CSG boundary"
      : implicit                  ? "an implicit boundary"
      : settings.TwoSidedBoundaryValues ? "two-sided boundary values"
      : biharmonicEquation        ? "the biharmonic equation"
                                  : nullptr;
    if (unsupported)
    {
      vtkErrorWithObjectMacro(self, << "Mixed boundary conditions (walk on stars) are not "
                                       "available with "
                                    << unsupported
                                    << ": they need a mesh boundary and the Laplace, Poisson or "
                                       "screened Poisson equation.");
      return false;
    }
  }

  int dimension = 3;
  std::string name = "Solution";
  bool cellData = false;
  const BoundaryValueContext context{ self, state.Settings, arrays };
  if (csg)
  {
    if (!BoundaryValuesOfCsgOperands(context, blocks, expressionValues, inputs, dimension, name))
    {
      return false;
    }
    inputs.CsgOperation = settings.CsgOperation;
    inputs.CsgBlendRadius = settings.CsgBlendRadius;
  }
  else if (!BoundaryValuesOfBoundary(context, boundary, implicit, expressionValues, dimension,
             name, state.Values, cellData))
  {
    return false;
  }

  if (settings.MixedBoundaryConditions &&
    !ResolveMixedArrays(self, arrays, boundary, state.Values, inputs))
  {
    return false;
  }

  if (settings.Equation == Equation::ScreenedPoisson &&
    !(settings.ScreeningCoefficient > 0.0))
  {
    vtkErrorWithObjectMacro(self, << "The screened Poisson equation needs ScreeningCoefficient "
                                     "> 0 (got "
                                  << settings.ScreeningCoefficient
                                  << "); use the Poisson equation for c = 0.");
    return false;
  }

  const bool varying = settings.Equation == Equation::VaryingCoefficients;
  if (varying)
  {
    // What walk on spheres with delta tracking does not give (yet).
    const char* unsupported = settings.MixedBoundaryConditions ? "mixed boundary conditions"
      : settings.Estimator != Estimator::PointwiseWalks       ? "a solution cache (Estimator)"
      : settings.ComputeHessian                               ? "the Hessian"
      : settings.ComputeDirectionalDerivative                 ? "the directional derivative"
                                                              : nullptr;
    if (unsupported)
    {
      vtkErrorWithObjectMacro(self, << "The equation with varying coefficients is not available "
                                       "with "
                                    << unsupported
                                    << ": it gives values and gradients by pointwise walks with "
                                       "Dirichlet conditions.");
      return false;
    }
    if (!ResolveCoefficientArrays(self, settings, arrays, source, inputs))
    {
      return false;
    }
  }

  // Source terms: the Source input's point array and the expression.
  const bool hasExpression = !settings.SourceExpression.empty();
  const bool usesSources = settings.Equation == Equation::Poisson ||
    settings.Equation == Equation::ScreenedPoisson;
  if ((source || hasExpression) && !usesSources && !varying)
  {
    vtkWarningWithObjectMacro(self, << "The source term (Source input or SourceExpression) is "
                                       "ignored: only the Poisson and screened Poisson equations "
                                       "have one.");
  }
  if (usesSources && source)
  {
    int sourceAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    inputs.SourceArray = arrays.Resolve(2, source, false, sourceAssociation, reason);
    if (!inputs.SourceArray && !reason.empty())
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the Source input: " << reason << ".");
      return false;
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
      vtkErrorWithObjectMacro(self, << "The source array must be point data of the Source input.");
      return false;
    }
    inputs.Source = source;
  }
  if (usesSources && hasExpression)
  {
    inputs.Expression = settings.SourceExpression;
  }

  inputs.Boundary = boundary;
  inputs.Implicit = settings.ImplicitBoundary;
  inputs.LipschitzBound = settings.LipschitzBound;
  inputs.Values = state.Values;
  inputs.CellData = cellData;
  inputs.TwoSided = settings.TwoSidedBoundaryValues;
  inputs.Region = data.Region;
  inputs.Name = name;
  state.Dimension = dimension;
  inputs.BoundaryKey = state.MakeKey(data, arrays, implicit || csg ? data.Region : nullptr);
  state.Resolved = true;
  return true;
}

template <int DIM>
bool ProblemBuilder::Internals::Make(vtkObject* self, ProblemBuilder& builder, BuiltProblem& out)
{
  const ProblemInputs& in = this->Inputs;
  std::shared_ptr<const Boundary<DIM>>& cached = this->CachedBoundary<DIM>();
  std::shared_ptr<const MixedBoundary<DIM>>& cachedMixed = this->CachedMixed<DIM>();
  if ((in.Mixed ? !cachedMixed : !cached) || this->BoundaryKey != in.BoundaryKey)
  {
    builder.Forget(); // frees the old hierarchy before building
    if (in.Mixed)
    {
      auto built = std::make_shared<MixedBoundary<DIM>>();
      if (!AssembleMixedBoundary<DIM>(self, in, *built))
      {
        return false;
      }
      cachedMixed = built;
    }
    else
    {
      auto built = std::make_shared<Boundary<DIM>>();
      if (!AssembleBoundary<DIM>(self, in, *built))
      {
        return false;
      }
      cached = built;
    }
    this->BoundaryKey = in.BoundaryKey;
    builder.LastBoundaryBuilt = true;
  }
  // A mixed problem's Dirichlet part (its reflecting part when it has none)
  // stands for its boundary where one part is asked for.
  const std::shared_ptr<const MixedBoundary<DIM>> mixed = in.Mixed ? cachedMixed : nullptr;
  const std::shared_ptr<const Boundary<DIM>> shared = !mixed ? cached
    : mixed->HasDirichlet()                                  ? mixed->SharedDirichlet()
                                                             : mixed->SharedReflecting();
  const Boundary<DIM>& geometry = *shared;
  const SolveSettings& s = this->Settings;

  WalkSettings settings;
  const double diagonal = mixed ? mixed->Diagonal() : geometry.Diagonal();
  settings.Epsilon = s.EpsilonIsRelative ? s.Epsilon * diagonal : s.Epsilon;
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
  settings.MaxSteps = s.MaxSteps;
  settings.Problem = s.Equation;
  settings.ScreeningCoefficient = s.ScreeningCoefficient;
  settings.Sampling = s.SourceSampling;
  settings.Screening = s.ScreenedSteps;
  settings.PeakGuiding = s.PeakSteps;
  settings.NearBoundarySplitting = s.NearBoundarySplitting;
  // Mixed conditions: points outside the closed boundary get the exterior
  // problem's answer where it is solved (the Laplace equation, or the
  // screened one without sources: AnswersBothSides), as
  // walk on spheres answers points on both sides.
  settings.MixedBothSides = true;
  settings.Biharmonic = s.BiharmonicStrategy;
  settings.NestedWalks = s.NestedWalks;

  const bool biharmonic = settings.Problem == Equation::Biharmonic;
  const int nc = biharmonic ? geometry.Components() / 2 : geometry.Components();

  // Sources (only for the equations that have them; Resolve warned otherwise).
  auto sources = std::make_shared<SourceSet<DIM>>();
  if (WalkOnSpheresEstimator<DIM>::UsesSources(settings.Problem))
  {
    std::string reason;
    if (!ConvertSource<DIM>(in.Source, in.SourceArray, in.Expression, nc,
          ProblemPlaneZ<DIM>(in), *sources, reason,
          s.SourceOperator))
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the source term: " << reason << ".");
      return false;
    }
    if (sources->IgnoredSurfaceCells > 0)
    {
      vtkWarningWithObjectMacro(self, << "Ignored " << sources->IgnoredSurfaceCells
                                      << " polygons of the Source input: a vtkPolyData source "
                                         "gives point sources (vertices) and curve sources "
                                         "(lines) only.");
    }
  }

  out = BuiltProblem();
  out.Dimension = DIM;
  out.ValueRange = ValueRangeOf(in, nc, biharmonic);
  out.Name = in.Name;
  out.Components = nc;
  out.Biharmonic = biharmonic;
  if (mixed && !mixed->HasDirichlet() && !mixed->HasRobin() &&
    settings.Problem != Equation::ScreenedPoisson)
  {
    vtkErrorWithObjectMacro(self, << "Every boundary cell has the Neumann condition: the Laplace "
                                     "and Poisson equations then have no unique solution (any "
                                     "constant can be added to one). Mark some cells Dirichlet "
                                     "(0) or Robin (2), or use the screened Poisson equation.");
    return false;
  }
  std::shared_ptr<const Problem<DIM>> problem;
  if (settings.Problem == Equation::VaryingCoefficients)
  {
    if (nc != 1)
    {
      vtkErrorWithObjectMacro(self, << "The equation with varying coefficients takes boundary "
                                       "values of one component; the boundary array has "
                                    << nc << ".");
      return false;
    }
    if (s.PolynomialControlVariate > 0)
    {
      vtkWarningWithObjectMacro(self, << "PolynomialControlVariate is ignored by the equation "
                                         "with varying coefficients (its walks carry no shift).");
    }
    auto model = this->CoefficientsFor<DIM>(self,
      BoundingBox<DIM>(shared->BoundsMin(), shared->BoundsMax()));
    if (!model)
    {
      return false;
    }
    problem = std::make_shared<const Problem<DIM>>(shared, settings, model);
  }
  else if (s.PolynomialControlVariate > 0)
  {
    if (mixed)
    {
      vtkErrorWithObjectMacro(self, << "The polynomial control variate takes Dirichlet "
                                       "conditions only: set PolynomialControlVariate to 0 for "
                                       "a problem with Neumann or Robin parts.");
      return false;
    }
    if (settings.Problem == Equation::Biharmonic || nc != 1)
    {
      vtkErrorWithObjectMacro(self, << "The polynomial control variate takes the Laplace, "
                                       "Poisson and screened Poisson equations with boundary "
                                       "values of one component: set PolynomialControlVariate "
                                       "to 0.");
      return false;
    }
    std::vector<std::uint64_t> key = this->MakeCacheKey(settings);
    std::shared_ptr<const Problem<DIM>>& kept = this->ShiftedProblem<DIM>();
    if (!kept || key != this->ShiftKey)
    {
      kept.reset();
      try
      {
        kept = MakeShiftedProblem<DIM>(*shared, settings, sources.get(), s.PolynomialControlVariate);
      }
      catch (const std::invalid_argument& e)
      {
        vtkErrorWithObjectMacro(self, << "Cannot use the polynomial control variate: " << e.what()
                                      << ". Set PolynomialControlVariate to 0.");
        return false;
      }
      this->ShiftKey = std::move(key);
    }
    problem = kept;
  }
  else
  {
    problem = mixed ? std::make_shared<const Problem<DIM>>(mixed, settings, sources)
                    : std::make_shared<const Problem<DIM>>(shared, settings, sources);
  }
  if constexpr (DIM == 2)
  {
    out.Problem2 = problem;
  }
  else
  {
    out.Problem3 = problem;
  }
  // The caches live with the problem: the same slot while the problem is
  // built from the same data and settings (kept while the pointwise
  // estimator is chosen, so that choosing a cache again reuses it).
  if (s.Estimator != Estimator::PointwiseWalks)
  {
    this->KeepCaches(settings, out);
  }
  return true;
}

bool ProblemBuilder::Build(vtkObject* self, BuiltProblem& problem)
{
  this->LastBoundaryBuilt = false;
  this->LastBuildAborted = false;
  Internals& state = *this->Internal;
  state.PreparationAborted = false;
  if (!state.Resolved)
  {
    vtkErrorWithObjectMacro(self, << "No problem to build: its inputs were not resolved.");
    return false;
  }
  bool ok = false;
  try
  {
    ok = state.Dimension == 2 ? state.Make<2>(self, *this, problem)
                              : state.Make<3>(self, *this, problem);
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << "Walk on spheres failed: " << e.what());
    ok = false;
  }
  this->LastBuildAborted = !ok && state.PreparationAborted;
  if (!ok && !this->LastBuildAborted)
  {
    // (An abort keeps the boundary: only the coefficients were stopped.)
    this->Forget();
  }
  return ok;
}
} // namespace gridfree
