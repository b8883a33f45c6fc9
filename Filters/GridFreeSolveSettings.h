// Every setting of a walk-on-spheres solve, in one place: what shapes the
// boundary and the equation, how the walks sample it, and which derivatives
// are estimated. Every filter keeps one (vtkWalkOnSpheresAlgorithm's
// GetSettings()) as the one home of its properties, so that every filter
// builds its problem (GridFreeProblemBuilder) and runs its batches
// (GridFreePointEstimates) the same way. The choices are the core's typed
// enumerations; the filters' integer properties (vtkWalkOnSpheresSolver's
// public enumerations, the plugin's XML) convert to them here, once.
// Private to the GridFree::Filters module.
#ifndef GridFreeSolveSettings_h
#define GridFreeSolveSettings_h

#include <gridfree/estimators/Equation.h>
#include <gridfree/implicit/CsgOperation.h>
#include <gridfree/sources/SourceOperator.h>
#include <gridfree/sources/SourceSampling.h>

#include <array>
#include <optional>
#include <string>

class vtkImplicitFunction;

namespace gridfree
{
// How probe points are answered: each by its own walks, or by a cache that
// every probe shares, with walks only in the shell near the boundary: the
// boundary value cache (gridfree/cache/BoundaryValueCache.h) or the sphere
// cache (gridfree/cache/SphereCache.h).
enum class Estimator
{
  PointwiseWalks = 0,
  BoundaryCache = 1,
  SphereCache = 2
};

struct SolveSettings
{
  // The boundary.
  vtkImplicitFunction* ImplicitBoundary = nullptr; // not owned
  double LipschitzBound = 1.0;
  // How the blocks of a composite Boundary (and the implicit boundary)
  // combine; none: they are one soup.
  std::optional<gridfree::CsgOperation> CsgOperation;
  double CsgBlendRadius = 0.0;
  std::string BoundaryValueExpression;
  std::string BoundaryLaplacianExpression;
  bool TwoSidedBoundaryValues = false;
  // Neumann and Robin conditions on the cells that the boundary condition
  // array (selection 4) marks 1 or 2: walk on stars.
  bool MixedBoundaryConditions = false;

  // The equation and its sources.
  gridfree::Equation Equation = gridfree::Equation::Laplace;
  double ScreeningCoefficient = 1.0;
  std::string SourceExpression;
  gridfree::SourceSampling SourceSampling = gridfree::SourceSampling::Automatic;
  gridfree::ScreenedSteps ScreenedSteps = gridfree::ScreenedSteps::Automatic;
  gridfree::PeakSteps PeakSteps = gridfree::PeakSteps::Automatic;
  gridfree::SourceOperator SourceOperator = gridfree::SourceOperator::Value;
  gridfree::BiharmonicStrategy BiharmonicStrategy = gridfree::BiharmonicStrategy::TreeWalking;
  int NestedWalks = 1;
  // The equation with varying coefficients, ∇·(α∇u) − σu = f: α and σ where
  // no array of the Source input gives them (selections 7 and 8), and the
  // Gaussian smoothing width of the arrays (world units; the cubic B-spline
  // adds its own, gridfree/coefficients/ImageCoefficients.h).
  double DiffusionCoefficient = 1.0;
  double AbsorptionCoefficient = 0.0;
  double CoefficientSmoothing = 0.0;
  // α and σ as expressions in x, y, z where no array gives them (they
  // replace the constants when not empty); f's expression is
  // SourceExpression, added to the array's f.
  std::string DiffusionExpression;
  std::string AbsorptionExpression;
  // Whether α, σ and f are read from their arrays (selections 7, 8 and 2)
  // at all. On by default for C++ and Python (no selection: the constants);
  // the plugin starts them off, so that choosing the equation never takes
  // the image's active scalars (CT values) as a coefficient by default.
  bool DiffusionFromArray = true;
  bool AbsorptionFromArray = true;
  bool SourceTermFromArray = true;

  // The walks (the sampling settings every filter shares).
  int WalksPerPoint = 128;
  // Target-error mode when positive: each point walks until the standard
  // error of its value is at most this (WalksPerPoint the most it takes);
  // relative to the boundary values' range (max - min of g) when
  // TargetErrorIsRelative.
  double TargetStandardError = 0.0;
  bool TargetErrorIsRelative = false;
  // Fixed-count mode: points whose error bar is not reliable walk on, up to
  // this many times WalksPerPoint (BatchRequest::WalkOnWhereUnreliable; 1:
  // none). 1 here, 4 in the solver, which sets it in its constructor (the
  // other filters have no such property and keep their cost).
  int WalkOnWhereUnreliable = 1;
  double Epsilon = 1e-4;
  bool EpsilonIsRelative = true;
  int MaxSteps = 10000;
  int Seed = 0;
  int NumberOfThreads = 0;

  // The estimator; the caches' shell (points closer to the boundary, relative
  // to its diagonal, take their own walks); the boundary cache's settings
  // (BoundaryCacheSettings: offset relative to the diagonal); the sphere
  // cache's (SphereCacheSettings).
  gridfree::Estimator Estimator = gridfree::Estimator::PointwiseWalks;
  double CacheShellDistance = 0.02;
  int CachePoints = 4096;
  int WalksPerCachePoint = 64;
  int CacheVolumePoints = 8192;
  double CacheOffset = 0.01;
  int WalksPerSphere = 128;
  int CacheSourceSamples = 256;
  // The polynomial control variate's degree (0: none): the walks estimate
  // u − P for a polynomial P fitted to the boundary values and the source
  // (gridfree/problem/PolynomialShiftFit.h).
  int PolynomialControlVariate = 0;

  // The derivatives.
  bool ComputeGradient = false;
  bool ComputeHessian = false;
  bool ControlVariates = true;
  // Walks from near the boundary split as they go deep (WalkSettings): off
  // here, on in the solver, the stream tracer and the adaptive sampler,
  // which set it in their constructors (the application filters have no
  // such property and keep their cost).
  bool NearBoundarySplitting = false;
  bool AntitheticPairs = false;
  bool ComputeDirectionalDerivative = false;
  std::array<double, 3> DerivativeDirection = { 1.0, 0.0, 0.0 };
};

// The integer codes of the filters' properties (vtkWalkOnSpheresSolver's
// CsgOperationType: 0 none, 1 union, 2 intersection, 3 difference) and the
// typed choice; codes out of range are the setters' to refuse.
inline std::optional<CsgOperation> CsgOperationOfCode(int code)
{
  switch (code)
  {
    case 1:
      return CsgOperation::Union;
    case 2:
      return CsgOperation::Intersection;
    case 3:
      return CsgOperation::Difference;
    default:
      return std::nullopt;
  }
}

inline int CodeOf(const std::optional<CsgOperation>& operation)
{
  return operation ? 1 + static_cast<int>(*operation) : 0;
}

// The codes of the other choices are their enumerators' values, in the
// order of the filters' enumerations.
template <typename Choice>
int CodeOf(Choice choice)
{
  return static_cast<int>(choice);
}
} // namespace gridfree

#endif
