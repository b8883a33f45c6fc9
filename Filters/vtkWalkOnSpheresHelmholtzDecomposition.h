/**
 * @class   vtkWalkOnSpheresHelmholtzDecomposition
 * @brief   Splits a vector field X into curl-free, divergence-free and
 *          harmonic parts inside a boundary, by walk on spheres, without a
 *          volume mesh (paper Sec. 6.6).
 *
 * X = ∇u + ∇×A + Y (2D: X = ∇u + J∇a + Y, J the counter-clockwise quarter
 * turn), where
 * - u solves Δu = ∇·X with u = 0 on the boundary;
 * - A solves ΔA = −∇×X with A = 0 on the boundary (three scalar Poisson
 *   equations; 2D: Δa = ∂X_y/∂x − ∂X_x/∂y, a scalar). The minus sign makes
 *   ∇×A the solenoidal part: ∇×∇×A = −ΔA when ∇·A = 0 (the paper prints
 *   ΔA = ∇×X);
 * - Y = X − ∇u − ∇×A is the rest, divergence-free; it is harmonic (also
 *   curl-free) whenever ∇·A = 0, always in 2D.
 * Zero potentials on the boundary are the "normal-parallel" boundary
 * conditions of Bhatia et al. that make the split unique.
 *
 * Inputs: port 0 "Boundary" (vtkPolyData: triangles for 3D, lines or Bézier
 * control polygons in one z-plane for 2D), port 1 "Probe" (any vtkDataSet:
 * where the parts are wanted), port 2 "Field" (optional: a dataset with the
 * vector point array X, selected with SetInputArrayToProcess(0, 2, 0,
 * vtkDataObject::FIELD_ASSOCIATION_POINTS, name); default its active
 * vectors). Without a Field input, FieldExpression gives X in closed form.
 * Images are sampled trilinearly, other datasets by their cells'
 * interpolation; ∇·X and ∇×X are the exact derivatives of that interpolant
 * (central differences for an expression), so the field must cover the
 * domain.
 *
 * Output: the probe with, for a field named X (the array's name, or
 * FieldName), X itself (as sampled), X_CurlFree (∇u), X_DivergenceFree
 * (∇×A), X_Harmonic (Y), each a 3-component vector (z = 0 in 2D, where X's
 * z component is not used) with its per-component variance (…_Variance),
 * and the potentials X_Potential (u), X_VectorPotential (A, 3D) or
 * X_StreamFunction (a, 2D), with variances. Field data: TotalWalks,
 * SolveSeconds.
 *
 * Estimator: POINTWISE_WALKS (default) or SPHERE_CACHE (vtkWalkOnSpheresAlgorithm):
 * each potential keeps its own cache of spheres, so a moved or denser probe
 * costs only the spheres it has not met; the output then has the point
 * array FromBoundaryCache and, summed over both caches, the field data
 * CacheSpheres, CacheWalks, CacheWalksRun (0: both reused) and
 * CacheSeconds, with PointsFromCache, PointsWalkedInShell and
 * OutsidePoints. BOUNDARY_CACHE is an error (it gives no curl, and its
 * gradients' error bars are too short for these potentials).
 *
 * The two potentials are solved separately (seeds Seed and Seed + 1), so
 * their estimates are independent and X_Harmonic_Variance is the sum of the
 * other two parts' variances. Every walk of each solve gives all components
 * of its potential's gradient (or curl), so each vector's components come
 * from the same walks.
 *
 * @sa vtkWalkOnSpheresSolver (SourceOperator) vtkWalkOnSpheresProbeAlgorithm
 */
#ifndef vtkWalkOnSpheresHelmholtzDecomposition_h
#define vtkWalkOnSpheresHelmholtzDecomposition_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresProbeAlgorithm.h"

class vtkAlgorithmOutput;
class vtkDataObject;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresHelmholtzDecomposition
  : public vtkWalkOnSpheresProbeAlgorithm
{
public:
  static vtkWalkOnSpheresHelmholtzDecomposition* New();
  vtkTypeMacro(vtkWalkOnSpheresHelmholtzDecomposition, vtkWalkOnSpheresProbeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The dataset carrying the vector field X (port 2, optional).
   */
  void SetFieldConnection(vtkAlgorithmOutput* output);
  void SetFieldData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * X in closed form when there is no Field input: a vector expression in
   * x, y, z with iHat, jHat, kHat, as in VTK's calculator, e.g.
   * "-y*iHat + x*jHat" (default empty). Ignored, with a warning, when a
   * Field input is connected.
   */
  vtkSetStringMacro(FieldExpression);
  vtkGetStringMacro(FieldExpression);
  ///@}

  ///@{
  /**
   * Prefix of the output arrays (default empty: the field array's name, or
   * "X" for an expression).
   */
  vtkSetStringMacro(FieldName);
  vtkGetStringMacro(FieldName);
  ///@}

  ///@{
  /**
   * Control variates for the gradients (paper Sec. 4.1; default on).
   */
  virtual void SetControlVariates(bool value);
  bool GetControlVariates();
  vtkBooleanMacro(ControlVariates, bool);
  ///@}

  ///@{
  /**
   * Antithetic pairs of walks for the gradients (default off; see
   * vtkWalkOnSpheresSolver).
   */
  virtual void SetAntitheticPairs(bool value);
  bool GetAntitheticPairs();
  vtkBooleanMacro(AntitheticPairs, bool);
  ///@}

protected:
  vtkWalkOnSpheresHelmholtzDecomposition();
  ~vtkWalkOnSpheresHelmholtzDecomposition() override;

  static constexpr int FieldPort = 2;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FieldExpression = nullptr;
  char* FieldName = nullptr;

private:
  vtkWalkOnSpheresHelmholtzDecomposition(const vtkWalkOnSpheresHelmholtzDecomposition&) = delete;
  void operator=(const vtkWalkOnSpheresHelmholtzDecomposition&) = delete;
};

#endif
