/**
 * @class   vtkWalkOnSpheresSolver
 * @brief   Solve Laplace, Poisson, screened Poisson and biharmonic
 *          boundary-value problems by walk on spheres, directly on a boundary
 *          surface, at the points of any probe dataset.
 *
 * vtkWalkOnSpheresSolver estimates the solution u of a Dirichlet problem
 * without a volume mesh: from every probe point it runs independent random
 * walks that jump to a uniform point on the largest empty sphere until they
 * come within Epsilon of the boundary, and averages the boundary value at the
 * closest boundary point, minus the source terms met on the way (Sawhney &
 * Crane 2020, Sec. 2). The Equation is one of
 * - Laplace: Δu = 0, u = g (the default);
 * - Poisson: Δu = f, u = g;
 * - ScreenedPoisson: Δu − c·u = f, u = g, with ScreeningCoefficient c > 0;
 * - VaryingCoefficients: ∇·(α∇u) − σu = f, u = g, with α, σ, f from arrays
 *   of a vtkImageData Source (SetDiffusionCoefficient below);
 * - Biharmonic: Δ²u = 0, u = g and Δu = h on the boundary.
 * The sign convention is the standard Laplacian: Δ|x|² = 2n.
 *
 * Input port 0, "Boundary", is a vtkPolyData (or a composite of them, see
 * below). Triangles, polygons and triangle
 * strips make a 3D problem (a polygon soup is fine: no watertightness,
 * manifoldness or orientation is assumed). A boundary made only of lines and
 * polylines that lie in one z-plane makes a 2D problem in that plane. The
 * boundary values g are the array chosen with SetInputArrayToProcess(0, ...):
 * point data are interpolated linearly at the closest point, cell data are
 * constant per cell, and every component of a multi-component array is
 * estimated from the same walks. Without a selection, the active point (then
 * cell) scalars are used. The biharmonic equation's h is the array chosen
 * with SetInputArrayToProcess(1, ...), with g's association and components.
 *
 * Instead of a mesh, the boundary can be an implicit surface: the zero set
 * of a vtkImplicitFunction set with SetImplicitBoundary (negative inside;
 * ParaView's Sphere, Plane, Box, Cylinder, their boolean combinations, or
 * the exact signed distances of this module). Walk on spheres then steps by
 * |φ(x)| / LipschitzBound, which is never farther than the surface when
 * LipschitzBound bounds how fast φ changes (1 for a true signed distance).
 * Its boundary values come from BoundaryValueExpression (an expression in
 * x, y, z at the boundary point) or, without one, from the Boundary input
 * sampled at its closest point to the implicit surface's point. The Boundary
 * input is then optional; an implicit problem is always 3D.
 *
 * The Boundary input may also be a composite dataset (a vtkMultiBlockDataSet,
 * e.g. ParaView's Group Datasets) whose leaves are vtkPolyData. With
 * CsgOperation None (the default) its blocks are one polygon soup. With
 * Union, Intersection or Difference each block is a closed solid (its
 * inside found by ray parity, so orientation and duplicate vertices do not
 * matter) and they are combined, with the implicit boundary, if set, as the
 * last operand (paper Sec. 5.1.4): a Difference removes all other operands
 * from the first block. CsgBlendRadius > 0 blends the surfaces smoothly.
 * Values come from BoundaryValueExpression, or from each block's own array
 * (the one selected, by name) at its closest point.
 *
 * Input port 1, "Probe", is any vtkDataSet; the output has the probe's type,
 * structure and arrays (an image stays an image).
 *
 * Input port 2, "Source", is optional: the source term f of the Poisson and
 * screened Poisson equations, from the point array chosen with
 * SetInputArrayToProcess(2, ...) (default: the active point scalars, or the
 * only point array).
 * - a vtkImageData is interpolated trilinearly from its voxels (a CT volume
 *   as the source), zero outside the image;
 * - a vtkPolyData with vertices and lines gives point sources s·δ_z and
 *   curve sources s·δ_γ with strength s per point (paper Sec. 4.2.2);
 * - any other vtkDataSet is interpolated in the cell that contains the point,
 *   zero outside its cells.
 * SourceExpression adds f given as an expression in x, y and z. A
 * one-component source applies to every component of the boundary values.
 *
 * For a boundary array named T the output holds
 * - `T`: the estimated solution (active scalars);
 * - `T_Variance`: the variance of that Monte Carlo mean (s^2/N), per component;
 * - `T_Laplacian`, `T_Laplacian_Variance` (biharmonic only): the estimate of
 *   Δu, a by-product of the same walks;
 * - `WalkSteps`: mean number of steps per walk (inner walks included);
 * - `EscapedFraction`: fraction of walks that left for infinity in an
 *   exterior problem (they contribute the value at infinity, 0: an exact part
 *   of the estimator, not an error);
 * - `TruncatedFraction`: fraction of walks stopped at MaxSteps (they take the
 *   value at their current closest boundary point);
 * - with ComputeGradient, ComputeHessian or ComputeDirectionalDerivative:
 *   `T_Gradient`, `T_Hessian`, `T_DirectionalDerivative` (`T_Divergence`,
 *   `T_Curl` for a 3-component solution), each with its `_Variance`, and
 *   `DerivativeStatus`: 0 where the first ball is centred at the point,
 *   1 where the point is closer than Epsilon to the boundary and the
 *   derivatives are one-sided (estimated 2·Epsilon inside, along the
 *   direction from the closest boundary point), 2 where no ball could be
 *   found (derivatives 0).
 * Field data `TotalWalks`, `TotalSteps`, `EscapedWalks`, `TruncatedWalks` and
 * `SolveSeconds` summarize the run.
 *
 * Distributed runs (`mpirun -np N pvbatch`, a pvserver with N ranks) use the
 * subclass vtkPWalkOnSpheresSolver (the plugin's proxy does), which gathers
 * every rank's piece of the Boundary and Source inputs; this class solves its
 * probe with the inputs as it receives them, asking its upstreams for the
 * whole Boundary and Source.
 *
 * Probe points outside a closed boundary (or anywhere around an open one)
 * solve the exterior problem with u → 0 at infinity (3D) or u bounded (2D):
 * walks far away are ended or returned by Russian roulette (Sec. 2.6).
 *
 * Results are reproducible: a walk's random stream depends only on Seed, the
 * probe point's coordinates and the walk's number, so the output is identical
 * for any NumberOfThreads and any partition of the probe.
 *
 * Progressive refinement: raising WalksPerPoint (or calling Refine()) with
 * nothing else changed runs only the missing walks, continuing from the
 * running sums the last solve kept (KeepRunningSums); the result is that of
 * one solve with all the walks, bit for bit. A quick preview with few walks
 * can so be refined in place.
 *
 * @sa vtkProbeFilter
 */
#ifndef vtkWalkOnSpheresSolver_h
#define vtkWalkOnSpheresSolver_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresAlgorithm.h"
#include "vtkMultiBlockDataSet.h" // for AssembledBoundary
#include "vtkSmartPointer.h"      // for AssembledBoundary
#include "vtkTimeStamp.h"         // for SettingsTime

#include <cstdint> // for std::uint64_t
#include <memory>  // for std::unique_ptr
#include <string>  // for std::string
#include <vector>  // for std::vector

class vtkDataArray;
class vtkDataSet;
class vtkImplicitFunction;
class vtkPolyData;
struct vtkWalkOnSpheresSolverCache;
struct vtkWalkOnSpheresSolverPieces;
namespace gridfree
{
struct SolveSettings;
}

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresSolver : public vtkWalkOnSpheresAlgorithm
{
public:
  static vtkWalkOnSpheresSolver* New();
  vtkTypeMacro(vtkWalkOnSpheresSolver, vtkWalkOnSpheresAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Convenience: connect the boundary (port 0) and the probe (port 1).
   */
  void SetBoundaryConnection(vtkAlgorithmOutput* output);
  void SetBoundaryData(vtkDataObject* data);
  /**
   * The Boundary port takes several connections (AddInputConnection(0, ...)):
   * their surfaces are one boundary, exactly as the blocks of a composite
   * dataset (one polygon soup, or CSG operands with a CsgOperation). A
   * dataset connected both as one of several boundaries and as the Probe is
   * the probe only: ParaView's input dialog first puts every selected
   * dataset on the Boundary. RemoveAllBoundaryConnections clears the port.
   */
  void RemoveAllBoundaryConnections();
  void SetProbeConnection(vtkAlgorithmOutput* output);
  void SetProbeData(vtkDataObject* data);
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * An implicit boundary: the zero set of this function, negative inside
   * (default none: the Boundary input's mesh is the boundary). See the class
   * description.
   */
  void SetImplicitBoundary(vtkImplicitFunction* function);
  vtkImplicitFunction* GetImplicitBoundary();
  ///@}

  /**
   * How the blocks of a composite Boundary input (and the implicit boundary)
   * make one domain: CSG_NONE (default: the blocks are one polygon soup and
   * an implicit boundary takes its values from them), CSG_UNION,
   * CSG_INTERSECTION, or CSG_DIFFERENCE (the first block minus all others).
   */
  enum CsgOperationType
  {
    CSG_NONE = 0,
    CSG_UNION,
    CSG_INTERSECTION,
    CSG_DIFFERENCE
  };

  ///@{
  /**
   * The CSG operation of the boundary operands (see CsgOperationType).
   */
  virtual void SetCsgOperation(int value); // a value out of range is an error
  int GetCsgOperation();
  void SetCsgOperationToNone() { this->SetCsgOperation(CSG_NONE); }
  void SetCsgOperationToUnion() { this->SetCsgOperation(CSG_UNION); }
  void SetCsgOperationToIntersection() { this->SetCsgOperation(CSG_INTERSECTION); }
  void SetCsgOperationToDifference() { this->SetCsgOperation(CSG_DIFFERENCE); }
  ///@}

  ///@{
  /**
   * Radius of the smooth blend between CSG operands (default 0: sharp
   * edges). The blended surface lies within about a quarter of this radius
   * of the sharp one, and the step radius stays a safe distance bound.
   */
  virtual void SetCsgBlendRadius(double value);
  double GetCsgBlendRadius();
  ///@}

  ///@{
  /**
   * A bound L on how fast the implicit boundary's function changes,
   * |φ(x) − φ(y)| ≤ L |x − y| wherever walks go (default 1, right for exact
   * signed distances and their boolean combinations). Steps are |φ(x)| / L;
   * a too small L lets walks jump over the boundary, so the solver checks L
   * on random short segments and warns when it is exceeded. ParaView's
   * Sphere (|x − c|² − r²) needs L = 2r inside the sphere.
   */
  virtual void SetLipschitzBound(double value);
  double GetLipschitzBound();
  ///@}

  ///@{
  /**
   * Boundary values g as an expression in x, y and z, evaluated at the
   * boundary point where a walk ends (default none). Used for implicit
   * boundaries, and for a mesh boundary instead of its arrays when set.
   * BoundaryLaplacianExpression gives the biharmonic equation's h the same
   * way. The output arrays are then named "Solution".
   */
  virtual void SetBoundaryValueExpression(const char* expression); // null clears it
  const char* GetBoundaryValueExpression();
  virtual void SetBoundaryLaplacianExpression(const char* expression); // null clears it
  const char* GetBoundaryLaplacianExpression();
  ///@}

  ///@{
  /**
   * Two-sided boundary values (default off; the diffusion curves and
   * surfaces of paper Sec. 6.4): every boundary point has a front value, the
   * array of SetInputArrayToProcess(0, ...), and a back value, the array of
   * SetInputArrayToProcess(3, 0, 0, association, name) with the same
   * association and number of components. A walk takes the value of the
   * side it ends on: the front where the boundary's oriented normal points
   * to it (left of a line's direction, the side from which a polygon's
   * points turn counter-clockwise), the back elsewhere. On edges and
   * vertices the side follows the angle-weighted pseudonormal, so it is
   * exact for consistently oriented lines and closed surfaces. Probe points
   * on the boundary itself take the mean of both sides. Bézier curves take
   * the side of their left normal. Needs a mesh boundary with arrays (not an
   * implicit, CSG or expression boundary) and an equation other than the
   * biharmonic. The output is named after the front array.
   */
  virtual void SetTwoSidedBoundaryValues(bool value);
  bool GetTwoSidedBoundaryValues();
  vtkBooleanMacro(TwoSidedBoundaryValues, bool);
  ///@}

  ///@{
  /**
   * Mixed boundary conditions (default off): Neumann and Robin conditions on
   * part of a mesh boundary, solved by walk on stars (Sawhney, Miller,
   * Gkioulekas and Crane 2023; Documentation/WalkOnStars.md). The boundary
   * condition array, SetInputArrayToProcess(4, 0, 0, association, name),
   * gives each cell (or point) a condition:
   * - 0 Dirichlet: u = g, the boundary values of SetInputArrayToProcess(0, ...);
   * - 1 Neumann: ∂u/∂n = h, with n the outward normal and h the Neumann flux
   *   array, SetInputArrayToProcess(5, ...) (as many components as g; no
   *   selection: h = 0, an insulated or reflecting wall);
   * - 2 Robin: ∂u/∂n + μu = h, with μ >= 0 the Robin coefficient array,
   *   SetInputArrayToProcess(6, ...) (one component);
   * - 3 insulating sheet: a surface inside the domain (appended to the
   *   boundary) with the domain on both sides and ∂u/∂n = 0 on each; any
   *   orientation, its flux and Robin values not read.
   * A condition given per point applies to a cell when all its points agree;
   * otherwise the smallest wins (a cell is Neumann only if all its points
   * are). Neumann and Robin cells must be oriented with outward normals
   * (counter-clockwise seen from outside; in 2D the domain on the left of
   * every line): the field data BackFaceHits counts walks that met them from
   * the other side, the sign of a wrong orientation or a leak. The boundary
   * must be closed: probe points outside it solve the exterior problem with
   * the same conditions (u → 0 at infinity in 3D, bounded in 2D) for the
   * Laplace equation, or the screened Poisson equation without a source;
   * otherwise they are NaN (field data OutsidePoints, with a warning).
   * Outside, a Neumann flux keeps its direction (along the cells' normals,
   * out of the object) and a Robin condition is taken along the normal
   * out of the exterior domain (μ > 0, h/μ what the surface exchanges
   * with, on either side). Laplace,
   * Poisson and screened Poisson equations, the solution and its
   * derivatives (a first ball clear of the whole boundary, then walk on
   * stars): not the biharmonic equation, implicit, CSG or two-sided
   * boundaries, or Bézier curves. With Neumann cells alone the
   * Laplace and Poisson equations have no unique solution: some cells must be
   * Dirichlet or Robin (or the equation screened). The name "None" for the
   * flux or Robin selection means no array.
   */
  virtual void SetMixedBoundaryConditions(bool value);
  bool GetMixedBoundaryConditions();
  vtkBooleanMacro(MixedBoundaryConditions, bool);
  ///@}

  enum EquationType
  {
    LAPLACE = 0,
    POISSON = 1,
    SCREENED_POISSON = 2,
    BIHARMONIC = 3,
    VARYING_COEFFICIENTS = 4
  };

  ///@{
  /**
   * The equation to solve (default LAPLACE); see the class description.
   */
  virtual void SetEquation(int value); // a value out of range is an error
  int GetEquation();
  void SetEquationToLaplace() { this->SetEquation(LAPLACE); }
  void SetEquationToPoisson() { this->SetEquation(POISSON); }
  void SetEquationToScreenedPoisson() { this->SetEquation(SCREENED_POISSON); }
  void SetEquationToBiharmonic() { this->SetEquation(BIHARMONIC); }
  void SetEquationToVaryingCoefficients() { this->SetEquation(VARYING_COEFFICIENTS); }
  ///@}

  ///@{
  /**
   * The equation with varying coefficients, ∇·(α∇u) − σu = f with u = g on
   * the boundary (the Pennes bioheat equation for u = T − T_a with α the
   * conductivity, σ the perfusion and f = −Q the metabolic heat; α = 1,
   * σ = 0 is the Poisson equation Δu = f). α, σ and f come from point
   * arrays of a vtkImageData on the Source port that covers the boundary:
   * input arrays 7 (α), 8 (σ) and 2 (f), each chosen by name with
   * SetInputArrayToProcess; without a choice α is DiffusionExpression or,
   * when that is empty, DiffusionCoefficient (default 1), σ is
   * AbsorptionExpression or AbsorptionCoefficient (default 0), and f is
   * SourceExpression (added to the array's f when both are given) or 0. The
   * arrays are smoothed by a Gaussian of standard deviation
   * CoefficientSmoothing (world units, default 0) and by their cubic
   * B-spline (standard deviation h/√3 for a spacing h), which makes α twice
   * differentiable, as the walk needs. α > 0 and σ ≥ 0 everywhere. Walk on
   * spheres with delta tracking (Sawhney et al. 2022): values and
   * gradients with their variances; Dirichlet conditions, pointwise walks.
   */
  virtual void SetDiffusionCoefficient(double value);
  double GetDiffusionCoefficient();
  virtual void SetAbsorptionCoefficient(double value);
  double GetAbsorptionCoefficient();
  virtual void SetCoefficientSmoothing(double value);
  double GetCoefficientSmoothing();
  ///@}

  ///@{
  /**
   * The equation with varying coefficients: α and σ as expressions in x, y
   * and z in the syntax of VTK's ExprTk function parser, as SourceExpression
   * (e.g. "0.5 + 0.2*tanh((z - 40)/5)"), used where no array gives them;
   * empty (the default) for the constants. They are evaluated where the
   * walks need them, not smoothed: α must be positive and twice
   * differentiable (its gradient and Laplacian are central differences of
   * the expression with a step of 1e-4 of the boundary's diagonal), σ at
   * least 0. In 2D they are evaluated in the plane of the boundary.
   */
  virtual void SetDiffusionExpression(const char* expression); // null clears it
  const char* GetDiffusionExpression();
  virtual void SetAbsorptionExpression(const char* expression); // null clears it
  const char* GetAbsorptionExpression();
  ///@}

  ///@{
  /**
   * Whether the equation with varying coefficients reads α, σ and f from
   * input arrays 7, 8 and 2 at all (default on; an array not chosen still
   * means the constant). ParaView's panel starts them off, so that an image
   * on the Source port never gives a coefficient by default.
   */
  virtual void SetDiffusionFromArray(bool value);
  bool GetDiffusionFromArray();
  vtkBooleanMacro(DiffusionFromArray, bool);
  virtual void SetAbsorptionFromArray(bool value);
  bool GetAbsorptionFromArray();
  vtkBooleanMacro(AbsorptionFromArray, bool);
  virtual void SetSourceTermFromArray(bool value);
  bool GetSourceTermFromArray();
  vtkBooleanMacro(SourceTermFromArray, bool);
  ///@}

  ///@{
  /**
   * c in the screened Poisson equation Δu − c·u = f (default 1, in inverse
   * squared length units; must be positive). Large c confines the solution
   * to a layer of width about 1/sqrt(c) near the boundary.
   */
  virtual void SetScreeningCoefficient(double value);
  double GetScreeningCoefficient();
  ///@}

  ///@{
  /**
   * A source term f(x, y, z) added to the Source input's, in the syntax of
   * VTK's ExprTk function parser, e.g. "exp(-(x^2+y^2+z^2))" (default empty:
   * none). Used by the Poisson, screened Poisson and varying-coefficient
   * equations (for the last, a number: f in div(α grad u) − σu = f). A vector
   * written with iHat, jHat and kHat as in VTK's calculator (e.g.
   * "y*iHat - x*jHat") gives one source per component of a 3-component
   * solution, or the vector field X of SourceOperator.
   */
  virtual void SetSourceExpression(const char* expression); // null clears it
  const char* GetSourceExpression();
  ///@}

  enum SourceOperatorType
  {
    SOURCE_VALUE = 0,
    SOURCE_DIVERGENCE = 1,
    SOURCE_CURL = 2
  };

  ///@{
  /**
   * What the source term f is made of the source data (the Source input's
   * array and SourceExpression): SOURCE_VALUE, the data themselves (the
   * default); SOURCE_DIVERGENCE, f = ∇·X of the vector field X they give
   * (an array of 2 or 3 components in 2D, 3 in 3D, or a vector expression);
   * SOURCE_CURL, f = ∇×X (3 components in 3D, for a 3-component solution;
   * the scalar ∂X_y/∂x − ∂X_x/∂y in 2D). Derivatives are exact for data
   * (those of the trilinear or cell interpolant; an image's field drops to
   * zero outside the image, so the image must cover the domain) and central
   * differences for expressions. The Helmholtz decomposition
   * (vtkWalkOnSpheresHelmholtzDecomposition) solves its potentials this way.
   * Point and curve sources (a vtkPolyData Source) have no operator.
   */
  virtual void SetSourceOperator(int value); // a value out of range is an error
  int GetSourceOperator();
  void SetSourceOperatorToValue() { this->SetSourceOperator(SOURCE_VALUE); }
  void SetSourceOperatorToDivergence() { this->SetSourceOperator(SOURCE_DIVERGENCE); }
  void SetSourceOperatorToCurl() { this->SetSourceOperator(SOURCE_CURL); }
  ///@}

  enum SourceSamplingType
  {
    UNIFORM = 0,
    GREENS_FUNCTION = 1,
    MULTIPLE_IMPORTANCE = 2,
    SOURCE_DENSITY = 3,
    AUTOMATIC_SOURCE_SAMPLING = 4
  };

  ///@{
  /**
   * How a walk samples the volume source in each ball (paper Sec. 4.2):
   * AUTOMATIC_SOURCE_SAMPLING (the default): SOURCE_DENSITY for a narrow
   * source (half of |f|'s mass, on the grid below, in at most 2% of its
   * cells), GREENS_FUNCTION otherwise; the field data SourceSamplingUsed
   * says which (1 or 3). Or
   * UNIFORM in the ball, proportional to the GREENS_FUNCTION (best for
   * smooth sources), or MULTIPLE_IMPORTANCE, one sample of each
   * combined by the balance heuristic (robust for concentrated sources such
   * as bright spots in a CT volume, at twice the source evaluations), or
   * SOURCE_DENSITY, one sample proportional to the Green's function and one
   * proportional to |f| (from a grid of |f| filled once per solve), combined
   * the same way: for sources much narrower than the domain, whose error
   * bars the other three underestimate below a few thousand walks.
   */
  virtual void SetSourceSampling(int value); // a value out of range is an error
  int GetSourceSampling();
  ///@}

  enum ScreenedStepsType
  {
    SCREENED_STEPS_AUTOMATIC = 0,
    SCREENED_STEPS_UNIFORM = 1,
    SCREENED_STEPS_GUIDED = 2
  };

  ///@{
  /**
   * Where a screened walk's step lands on its sphere: SCREENED_STEPS_UNIFORM
   * (the paper's walk, the weight times the sphere's boundary weight C) or
   * SCREENED_STEPS_GUIDED, mostly near the direction of the boundary point
   * with the largest log|g| − √c·distance and reweighted (unbiased): where
   * 1/√c is short beside the domain, uniform steps' error bars are wrong by
   * orders of magnitude and guided ones stay right.
   * SCREENED_STEPS_AUTOMATIC (the default) guides when there is no source
   * and √c times the boundary's diagonal is at least 10, or, under milder
   * screening, when the data lead one way (the guide's directions from
   * points inside the mesh agree, as for a plane wave), there is no
   * source, and Peak Steps is Automatic and does not take the walk. On
   * implicit, CSG and Bézier boundaries the guide reads the values at
   * boundary points sampled near a lattice
   * (gridfree/estimators/ScreenedGuide.h).
   */
  virtual void SetScreenedSteps(int value); // a value out of range is an error
  int GetScreenedSteps();
  ///@}

  enum PeakStepsType
  {
    PEAK_STEPS_AUTOMATIC = 0,
    PEAK_STEPS_UNIFORM = 1,
    PEAK_STEPS_GUIDED = 2
  };

  ///@{
  /**
   * Whether walk on spheres' steps lean toward a narrow peak of the
   * boundary data (a small hot spot, the potential of a charge just outside
   * the boundary): PEAK_STEPS_GUIDED draws 70% of the landing points with
   * density proportional to e^{−√c·s}/s, s the distance to the data's
   * largest |g| or to one of up to three more peaks at least a quarter as
   * high (1/s for the Laplace and Poisson equations; K0(√c·s) in 2D),
   * and reweights them (unbiased). Uniform steps rarely end on such a peak, which carries
   * much of the answer far from it, and their error bars come out too
   * small. PEAK_STEPS_AUTOMATIC (the default) leans where the largest |g| is
   * at least 10 times the area-weighted mean |g|, with no source, no
   * polynomial control variate, and no guided screened steps (nor Screened
   * Steps set to uniform). Dirichlet data only (on implicit, CSG and
   * Bézier boundaries the peak is sought among boundary points sampled
   * near a lattice), in 3D and (the screened equation) in 2D
   * (gridfree/estimators/PeakGuide.h).
   */
  virtual void SetPeakSteps(int value); // a value out of range is an error
  int GetPeakSteps();
  ///@}

  enum BiharmonicStrategyType
  {
    TREE_WALKING = 0,
    NESTED = 1
  };

  ///@{
  /**
   * Biharmonic estimator: TREE_WALKING (default, paper Sec. 4.3) reuses the
   * boundary hit of the walk for u to estimate Δu along it, at the cost of a
   * Laplace walk; NESTED runs NestedWalks inner walks at every step (Sec. 2.5).
   */
  virtual void SetBiharmonicStrategy(int value); // a value out of range is an error
  int GetBiharmonicStrategy();
  virtual void SetNestedWalks(int value);
  int GetNestedWalks();
  ///@}

  ///@{
  /**
   * Estimate the gradient ∇u from the same walks (default off; paper Sec. 3.1,
   * Eqns. 13–14): output `T_Gradient` with 3 components per solution
   * component (∂/∂x, ∂/∂y, ∂/∂z; ∂/∂z = 0 in 2D), set as the active vectors
   * for a one-component solution, and `T_Gradient_Variance`. It costs one
   * more source sample pair per walk. For a 3-component solution the output
   * also holds `T_Divergence` and `T_Curl` (with their variances).
   */
  virtual void SetComputeGradient(bool value);
  bool GetComputeGradient();
  vtkBooleanMacro(ComputeGradient, bool);
  ///@}

  ///@{
  /**
   * Estimate the Hessian ∇²u (default off; Sec. 3.3, Eqn. 15 and its
   * integration-by-parts source term, which uses ∇f: the exact gradient of
   * the interpolated Source input, central differences of the
   * SourceExpression). Output `T_Hessian` (9 components per solution
   * component, row-major and symmetric; zero z row and column in 2D), set as
   * the active tensors for a one-component solution so vtkTensorGlyph draws
   * it, and `T_Hessian_Variance`.
   */
  virtual void SetComputeHessian(bool value);
  bool GetComputeHessian();
  vtkBooleanMacro(ComputeHessian, bool);
  ///@}

  ///@{
  /**
   * Control variates (default on; Sec. 4.1): each walk subtracts a
   * zero-mean term built from the running estimates of the earlier walks at
   * the same point (the gradient for the value, the mean of u on the first
   * sphere for the gradient, both for the Hessian). The estimates stay
   * unbiased and the variance arrays stay honest. The gain is largest where
   * u is large compared with its variation over the point's first ball: on
   * the Poisson problem of the convergence study the gradient's error falls
   * 3.5×, the Hessian's 4.2×, the value's 1.1× at 1024 walks.
   */
  virtual void SetControlVariates(bool value);
  bool GetControlVariates();
  vtkBooleanMacro(ControlVariates, bool);
  ///@}

  ///@{
  /**
   * Antithetic pairs (default off): each of the WalksPerPoint samples of
   * the derivatives is a pair of walks whose first steps go to opposite
   * points of the first ball, the second walk replaying the first one's
   * random numbers. In the gradient the constant and the even part of u
   * over the ball cancel exactly, so at equal walk count its error falls
   * (1.3× on the CT meshes of the peer benchmark); each sample costs two
   * walks. Values stay unbiased, their variance arrays honest.
   */
  virtual void SetAntitheticPairs(bool value);
  bool GetAntitheticPairs();
  vtkBooleanMacro(AntitheticPairs, bool);
  ///@}

  ///@{
  /**
   * Near-boundary splitting (default on). From a point near the boundary
   * most walks end close by, and the rare one that wanders deep brings back
   * what the others never see (the source's integral, data far away): a
   * heavy tail that a few hundred walks misjudge, with error bars too small.
   * With splitting, a walk whose ball grows to twice the largest it had
   * goes on as two walks of half its weight (up to a quarter of the
   * boundary's diagonal, or the screening length 1/√c; at most 32
   * branches per walk), so that nearly every walk carries a share of the
   * deep ones. Unbiased; walks from points farther than half that depth
   * from the boundary walk as without it (those that go on from a first
   * ball's sphere, for derivatives and the control variates, split only
   * beyond twice that ball), those near it cost more walk steps (on the CT
   * workflow's default solve 1.2 times the time; it then flags 1 point
   * of 4,096 instead of 9 whose error bars were wrong). Off: the plain
   * walks (the core's WalkSettings default).
   * Walk on spheres (Dirichlet conditions), not the biharmonic equation.
   */
  virtual void SetNearBoundarySplitting(bool value);
  bool GetNearBoundarySplitting();
  vtkBooleanMacro(NearBoundarySplitting, bool);
  ///@}

  ///@{
  /**
   * Estimate the directional derivative Z·∇u along DerivativeDirection Z
   * (default off; Sec. 3.2): `T_DirectionalDerivative` and its variance,
   * computed walk by walk so the variance is exact. Z is used as given (not
   * normalized).
   */
  virtual void SetComputeDirectionalDerivative(bool value);
  bool GetComputeDirectionalDerivative();
  vtkBooleanMacro(ComputeDirectionalDerivative, bool);
  void SetDerivativeDirection(double x, double y, double z);
  void SetDerivativeDirection(const double direction[3]);
  double* GetDerivativeDirection() VTK_SIZEHINT(3);
  void GetDerivativeDirection(double direction[3]);
  ///@}

  ///@{
  /**
   * Number of random walks per probe point (default 128, at least 2 so a
   * variance can be reported). The standard error falls as 1/sqrt(walks).
   *
   * Progressive refinement: when only WalksPerPoint has changed since the
   * last solve (same inputs, same settings) and KeepRunningSums is on, a
   * larger value continues from the running sums kept by that solve and runs
   * only the missing walks; the result is bit for bit that of one solve with
   * all of them, with or without derivative walks (their control-block
   * state is kept with the sums).
   */
  void SetWalksPerPoint(int walks) override;
  ///@}

  ///@{
  /**
   * Target-error mode (when TargetStandardError is positive; default 0, off):
   * each probe point walks until the standard error of its value (the
   * largest over the components) is at most TargetStandardError, checked
   * after 128 walks and then every 32 (and the point's error bar is
   * reliable: GetLastUnreliableErrorBars()), and WalksPerPoint is the most a
   * point takes. Points near the boundary stop early, points deep inside walk
   * longer. The decision uses only the point's own walks, so the result is
   * the same for any thread count; it is that of a fixed-count solve cut
   * short at each point's count (array WalkCount). With
   * TargetErrorIsRelative the target is a fraction of the boundary values'
   * range (max - min of the boundary array; not available for values given
   * by expressions). Progressive refinement works in this mode too: a
   * larger WalksPerPoint (Refine) keeps the points that reached the target
   * and continues the others, with the result of one solve at that maximum;
   * GetLastPointsShortOfTarget() says how many points are still above it.
   * Changing the target keeps the kept sums where they serve: a tighter
   * target continues from them (points that stopped at the looser one are
   * checked again), and so does a fixed count (target 0) after a target;
   * both give the result of one solve with the new settings. A looser
   * target solves afresh (a solve with it stops points earlier).
   */
  virtual void SetTargetStandardError(double target);
  double GetTargetStandardError();
  virtual void SetTargetErrorIsRelative(bool relative);
  bool GetTargetErrorIsRelative();
  vtkBooleanMacro(TargetErrorIsRelative, bool);
  ///@}

  ///@{
  /**
   * Walking on where an error bar cannot be trusted (fixed-count mode; a
   * factor of WalksPerPoint, default 4, 1 turns it off, at most 64): a probe
   * point whose error bar is not reliable after WalksPerPoint walks (array
   * <name>_VarianceReliable) walks on to 2, 4, ... times WalksPerPoint,
   * checked at each, until it is reliable or holds this many times
   * WalksPerPoint. The commonest false alarm, a spread made by a single
   * walk, settles this way, and so does a too small bar the single walk
   * hid: more walks bring the rare walks that were due (not always with
   * NearBoundarySplitting on data that jump, whose split walks can hide a
   * spread made by few walks: Documentation/ErrorBars.md). Points flagged for
   * uneven screening weights walk on only where more walks could clear
   * them (the weights do not even out with walks). Only flagged points walk
   * more (array WalkCount, present when counts differ; field
   * PointsWalkedOnForReliability counts them); the decision uses only the
   * point's own walks, so the result is the same for any thread count.
   * Refinement stays bit for bit that of one solve when WalksPerPoint
   * doubles (Refine), or grows by any power of 2. Target-error mode walks
   * on at such points anyway and ignores this. Raising it keeps the
   * running sums (the points still flagged walk on); lowering it solves
   * afresh.
   */
  virtual void SetWalkOnWhereUnreliable(int factor); // out of [1, 64] is an error
  int GetWalkOnWhereUnreliable();
  ///@}

  ///@{
  /**
   * Time budget in seconds (default 0, off). When positive, the solve runs
   * in rounds of 128, 256, 512, ... walks per point up to WalksPerPoint,
   * each continuing from the running sums of the one before, and stops
   * before a round whose projected time (at the rate measured so far) would
   * not fit in the budget; the first round always runs. With a target
   * standard error the rounds raise the most walks a point may take and
   * stop once every point is at the target. The result is bit for bit that
   * of one solve with the last round's walks per point
   * (GetLastWalksPerPointReached(), field WalksPerPointReached, array
   * WalkCount): the count the budget reaches depends on the machine, the
   * numbers at that count do not. Changing the budget keeps the kept sums,
   * as changing WalksPerPoint does: a larger one continues.
   */
  virtual void SetTimeBudgetSeconds(double seconds);
  vtkGetMacro(TimeBudgetSeconds, double);
  ///@}

  /**
   * Walks per point of the last execution: WalksPerPoint, or under a time
   * budget the last round's (the most a point took, with a target).
   */
  vtkGetMacro(LastWalksPerPointReached, int);

  /**
   * Doubles WalksPerPoint (up to VTK_INT_MAX): the next update adds as many
   * walks as the last one had, continuing from the kept running sums. With
   * a cache estimator, WalksPerSphere (SPHERE_CACHE) or WalksPerCachePoint
   * (BOUNDARY_CACHE) doubles too: the cache's spheres or points continue
   * their walks. ParaView's "Refine" button.
   */
  void Refine();

  /**
   * After an aborted solve (GetLastSolveAborted()): marks the filter
   * modified without touching its settings, so that the next update
   * continues from the walks the aborted one ran (and those kept before
   * it), with the result of one uninterrupted solve. Does nothing otherwise.
   * ParaView calls it when Apply is pressed after an Abort.
   */
  void Resume();

  /**
   * Whether the last execution was aborted (SetAbortExecute, ParaView's
   * Abort button). Its output then holds, at each point, the estimate of
   * the walks the point holds (array WalkCount; NaN values and zero
   * derivatives where there are none), and the running sums are kept for
   * Resume(). VTK 9.2 leaves AbortExecute set after an abort: clear it
   * (SetAbortExecute(0)) before the next update, as ParaView's plugin does.
   */
  vtkGetMacro(LastSolveAborted, bool);

  ///@{
  /**
   * Keep every probe point's running sums after a solve, for progressive
   * refinement (default on). They cost 16 bytes per output number and point
   * plus 48 bytes per point (e.g. 80 bytes per point for a scalar solution);
   * off frees them.
   */
  vtkSetMacro(KeepRunningSums, bool);
  vtkGetMacro(KeepRunningSums, bool);
  vtkBooleanMacro(KeepRunningSums, bool);
  ///@}

  // Epsilon, EpsilonIsRelative, MaxSteps, Seed and NumberOfThreads are
  // vtkWalkOnSpheresAlgorithm's (the same properties in every filter).

  ///@{
  /**
   * Statistics of the last execution: walks run, wall-clock seconds of the
   * solve, walks per second, dimension of the problem (2 or 3; 0 if none).
   */
  vtkGetMacro(LastNumberOfWalks, vtkIdType);
  vtkGetMacro(LastSolveSeconds, double);
  double GetLastWalksPerSecond() const;
  vtkGetMacro(LastDimension, int);
  ///@}

  /**
   * Walks per point the last execution took from kept running sums instead
   * of running them (0 when it started afresh).
   */
  vtkGetMacro(LastResumedWalksPerPoint, vtkIdType);

  /**
   * Target-error mode: probe points of the last execution that took every
   * walk allowed (WalksPerPoint) with a standard error still above the
   * target (0 otherwise). Refine until it is 0 for the target everywhere.
   */
  vtkGetMacro(LastPointsShortOfTarget, vtkIdType);

  /**
   * Probe points of the last execution whose error bar cannot be trusted
   * (NAME_VarianceReliable = 0; Documentation/UserGuide.md, "Error bars you
   * can trust"): their walks' screening weights are very uneven, or all
   * their walks gave one value although others were possible. Their
   * NAME_Variance may be far too small. In target-error mode such points
   * never stop at the target.
   */
  vtkGetMacro(LastUnreliableErrorBars, vtkIdType);

  // GetLastBoundaryBuilt (vtkWalkOnSpheresAlgorithm): whether the last
  // execution built the boundary (conversion, hierarchy, distance bounds) or
  // reused the one built before. It is reused while the Boundary input, the
  // implicit boundary and the properties that shape the boundary (value
  // arrays and expressions, Equation, two-sided values, CSG, Lipschitz
  // bound) stay the same: moving the probe, changing the walks, the seed or
  // Epsilon, or refining does not rebuild it.

  /**
   * Any change but WalksPerPoint's also marks the kept running sums stale.
   */
  void Modified() override;

  /**
   * Sets the abort flag without marking the solver modified: an aborted
   * solve's output and the walks it ran stay as they are (no re-execution
   * at the next update, and Resume() continues from them).
   */
  void SetAbortExecute(vtkTypeBool abort) override;

  ///@{
  /**
   * Selecting the array already selected changes nothing (ParaView's Apply
   * sends every selection again): the kept running sums stay valid.
   */
  using Superclass::SetInputArrayToProcess;
  void SetInputArrayToProcess(
    int idx, int port, int connection, int fieldAssociation, const char* name) override;
  ///@}

  /**
   * Includes the implicit boundary's MTime: editing it re-executes the solver.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkWalkOnSpheresSolver();
  ~vtkWalkOnSpheresSolver() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// The Boundary port's data: one connection's, or several as one composite.
  vtkDataObject* BoundaryOf(vtkInformationVector* connections, vtkDataObject* probe);

  /**
   * The Boundary and Source inputs the solve uses, from `boundary` and
   * `source` as this rank received them. Here they are used as they are;
   * vtkPWalkOnSpheresSolver gathers every rank's pieces. Called before any
   * check that could end the execution early (a gather is collective).
   * False after an error.
   */
  virtual bool GatherInputs(
    vtkDataObject* boundary, vtkDataObject* source, vtkWalkOnSpheresSolverPieces& pieces);

  /**
   * Asks the Boundary or Source upstream (`info`) for what this rank needs:
   * here the whole data.
   */
  virtual void RequestSharedInput(vtkInformation* info);

  bool KeepRunningSums = true;
  // Several Boundary connections as one composite (kept for the execution).
  vtkSmartPointer<vtkMultiBlockDataSet> AssembledBoundary;

  vtkIdType LastNumberOfWalks = 0;
  double LastSolveSeconds = 0.0;
  int LastDimension = 0;
  vtkIdType LastResumedWalksPerPoint = 0;
  vtkIdType LastPointsShortOfTarget = 0;
  vtkIdType LastUnreliableErrorBars = 0;
  int LastWalksPerPointReached = 0;
  bool LastSolveAborted = false;
  double TimeBudgetSeconds = 0.0;

private:
  vtkWalkOnSpheresSolver(const vtkWalkOnSpheresSolver&) = delete;
  void operator=(const vtkWalkOnSpheresSolver&) = delete;

  // The running sums kept for progressive refinement, with what they were
  // computed from.
  std::unique_ptr<vtkWalkOnSpheresSolverCache> Cache;
  // Modified by every change except one of WalksPerPoint alone (or of the
  // time budget or the target, which decide how far the walks go).
  vtkTimeStamp SettingsTime;
  bool ChangingOnlyWalks = false;
  // Marks the filter modified, keeping the running sums.
  void ModifiedKeepingSums();

};

#endif
