// Every setting of a walk-on-spheres solve, in one place: what shapes the
// boundary and the equation, how the walks sample it, and which derivatives
// are estimated. vtkWalkOnSpheresSolver fills one from its properties; the
// filters that estimate at points of their own (stream tracer, adaptive
// sampler, the applications) fill one from theirs, so that every filter
// builds its problem (GridFreeProblemBuilder) and runs its batches
// (GridFreePointEstimates) the same way. The integer codes are those of
// vtkWalkOnSpheresSolver's enumerations.
// Private to the GridFree::Filters module.
#ifndef GridFreeSolveSettings_h
#define GridFreeSolveSettings_h

#include <array>
#include <string>

class vtkImplicitFunction;

namespace gridfree
{
struct SolveSettings
{
  // The boundary.
  vtkImplicitFunction* ImplicitBoundary = nullptr; // not owned
  double LipschitzBound = 1.0;
  int CsgOperation = 0; // CSG_NONE
  double CsgBlendRadius = 0.0;
  std::string BoundaryValueExpression;
  std::string BoundaryLaplacianExpression;
  bool TwoSidedBoundaryValues = false;
  // Neumann and Robin conditions on the cells that the boundary condition
  // array (selection 4) marks 1 or 2: walk on stars.
  bool MixedBoundaryConditions = false;

  // The equation and its sources.
  int Equation = 0; // LAPLACE
  double ScreeningCoefficient = 1.0;
  std::string SourceExpression;
  int SourceSampling = 1; // GREENS_FUNCTION
  int SourceOperator = 0; // SOURCE_VALUE
  int BiharmonicStrategy = 0; // TREE_WALKING
  int NestedWalks = 1;

  // The walks (the sampling settings every filter shares).
  int WalksPerPoint = 128;
  // Target-error mode when positive: each point walks until the standard
  // error of its value is at most this (WalksPerPoint the most it takes);
  // relative to the boundary values' range (max - min of g) when
  // TargetErrorIsRelative.
  double TargetStandardError = 0.0;
  bool TargetErrorIsRelative = false;
  double Epsilon = 1e-4;
  bool EpsilonIsRelative = true;
  int MaxSteps = 10000;
  int Seed = 0;
  int NumberOfThreads = 0;

  // The derivatives.
  bool ComputeGradient = false;
  bool ComputeHessian = false;
  bool ControlVariates = true;
  bool AntitheticPairs = false;
  bool ComputeDirectionalDerivative = false;
  std::array<double, 3> DerivativeDirection = { 1.0, 0.0, 0.0 };
};
} // namespace gridfree

#endif
