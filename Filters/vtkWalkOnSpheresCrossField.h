/**
 * @class   vtkWalkOnSpheresCrossField
 * @brief   The smoothest 2D cross field aligned with a boundary, its
 *          singularities and the separatrices between them, by walk on
 *          spheres, without a mesh (paper Sec. 6.5, Fig. 19).
 *
 * The boundary normals ν, as unit complex numbers, are raised to the fourth
 * power (so the four directions of a cross give one value) and extended
 * harmonically: Δψ = 0 with ψ = ν⁴ on the boundary, estimated by walk on
 * spheres with both components (Re ψ, Im ψ) from the same walks. The cross
 * at a point has the directions arg(ψ)/4 + kπ/2.
 *
 * Input 0 "Boundary": closed polylines in one z-plane (the domain; holes
 * allowed). Each segment's own normal is used, so corners are exact; the
 * direction in which the lines run does not matter (ν and −ν give the same
 * ν⁴). Input 1 "Probe": where the crosses are wanted.
 *
 * Output 0: the probe with CrossField (Re ψ, Im ψ), CrossField_Variance,
 * CrossField_Gradient (with variance), and CrossDirection1 … 4, unit vectors
 * (zero where ψ = 0) ready for Glyph.
 *
 * Output 1 (SearchSingularities): the singularities, zeros of ψ, as
 * vertices with Index (the winding number of ψ, i.e. the cross-field index
 * in quarter turns: +1 for a three-armed, −1 for a five-armed singularity),
 * IndexResidual, PsiMagnitude, SeedCount and IndexRadius. Two searches
 * (SearchMethod):
 * - WINDING (default): the winding of ψ around the cells of a grid of
 *   SearchGridCells cells along the longer side, refined SearchRefinements
 *   times where it winds (gridfree/applications/CrossFieldWinding.h); the
 *   grid only covers cells wholly inside, so where the indices found fall
 *   short of the boundary's, the search is repeated on a grid twice as fine,
 *   up to 8 times as fine (field data SearchGridCellsUsed). The
 *   windings of all cells add up to the winding around the grid, so no zero
 *   inside it is missed, flat ones (winding ±2) included; zeros closer
 *   together than the noise resolves are one singularity with their summed
 *   index. SeedCount holds the cells of its region, IndexRadius half its
 *   size.
 * - SEED_DESCENT: gradient descent on |ψ|² (dx/dt = −2⟨ψ, ∇ψ⟩) from
 *   NumberOfSeeds points spread inside the boundary, each descent step one
 *   solve for all seeds still moving; the index is the paper's
 *   n = −i (|x − x*| / ψ) D_u ψ averaged on a circle of IndexRadius around
 *   the zero. A seed may stop short of a flat zero, or no seed reach one.
 * Either way the indices are checked against the boundary (Poincaré–Hopf):
 * at a corner where the boundary turns by α, ψ turns by 4α wrapped into
 * (−π, π], and the sum over the corners (4χ for a smooth boundary, χ the
 * Euler characteristic) is what the indices inside add up to. The field data
 * IndexSum and BoundaryIndexSum hold both (quarter turns); a warning gives
 * both when they differ.
 *
 * Output 2 (TraceSeparatrices): separatrices, polylines from each
 * singularity of index n along the |4 − n| directions where the cross points
 * away from it, following at each step the cross direction best aligned with
 * the curve, until the boundary or another singularity: the edges of a quad
 * layout. Cell data: SourceSingularity, TargetSingularity (−1 at the
 * boundary) and StopReason (0 boundary, 1 singularity, 2 steps, 3 length,
 * 4 invalid point, 5 ψ = 0, 6 aborted).
 *
 * Estimator: POINTWISE_WALKS (default) or SPHERE_CACHE
 * (vtkWalkOnSpheresAlgorithm): with the cache, the probe, the singularity
 * search and the separatrices are all answered from one cache of spheres,
 * kept for the next execution; the loops are first turned to have the
 * domain on their left (the cache tells inside from outside by that side),
 * so they must be closed. The output then has FromBoundaryCache and the
 * probe solve's cache field data (CacheWalksRun 0: reused). BOUNDARY_CACHE
 * is an error.
 *
 * Lengths (MergeRadius, IndexRadius, SeparatrixStep) are fractions of the
 * boundary's bounding-box diagonal. Searches and curves are estimated with
 * SearchWalksPerPoint walks per point; the probe with WalksPerPoint.
 *
 * @sa vtkWalkOnSpheresSolver vtkWalkOnSpheresProbeAlgorithm
 */
#ifndef vtkWalkOnSpheresCrossField_h
#define vtkWalkOnSpheresCrossField_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresProbeAlgorithm.h"

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresCrossField : public vtkWalkOnSpheresProbeAlgorithm
{
public:
  static vtkWalkOnSpheresCrossField* New();
  vtkTypeMacro(vtkWalkOnSpheresCrossField, vtkWalkOnSpheresProbeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Find the singularities (output 1; default on).
   */
  vtkSetMacro(SearchSingularities, bool);
  vtkGetMacro(SearchSingularities, bool);
  vtkBooleanMacro(SearchSingularities, bool);
  ///@}

  ///@{
  /**
   * Trace the separatrices from the singularities (output 2; default on;
   * needs SearchSingularities).
   */
  vtkSetMacro(TraceSeparatrices, bool);
  vtkGetMacro(TraceSeparatrices, bool);
  vtkBooleanMacro(TraceSeparatrices, bool);
  ///@}

  enum SearchMethods
  {
    WINDING = 0,
    SEED_DESCENT = 1
  };

  ///@{
  /**
   * How singularities are found (default WINDING; see the class notes). A
   * value out of range is an error that names the choices.
   */
  void SetSearchMethod(int method);
  vtkGetMacro(SearchMethod, int);
  void SetSearchMethodToWinding() { this->SetSearchMethod(WINDING); }
  void SetSearchMethodToSeedDescent() { this->SetSearchMethod(SEED_DESCENT); }
  ///@}

  ///@{
  /**
   * WINDING: cells of the grid along the longer side of the boundary's box
   * (default 16), and times a cell whose ψ winds is split in four (default
   * 5: singularities placed to within a 512th of the box).
   */
  vtkSetClampMacro(SearchGridCells, int, 2, 1024);
  vtkGetMacro(SearchGridCells, int);
  vtkSetClampMacro(SearchRefinements, int, 0, 10);
  vtkGetMacro(SearchRefinements, int);
  ///@}

  ///@{
  /**
   * SEED_DESCENT: starting points of the singularity search, spread inside
   * the boundary (default 32; the same Seed gives the same points).
   */
  vtkSetClampMacro(NumberOfSeeds, int, 1, 100000);
  vtkGetMacro(NumberOfSeeds, int);
  ///@}

  ///@{
  /**
   * Walks per estimate of the search and of the separatrices (default 1024):
   * near a singularity |ψ| is small and must stand out of the noise.
   */
  vtkSetClampMacro(SearchWalksPerPoint, int, 2, VTK_INT_MAX);
  vtkGetMacro(SearchWalksPerPoint, int);
  ///@}

  ///@{
  /**
   * Seeds that stop closer than MergeRadius are one singularity (default
   * 0.02 of the diagonal). Raise it (and IndexRadius) for singularities of
   * high index, where ψ is flat and seeds stop farther apart.
   */
  vtkSetClampMacro(MergeRadius, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MergeRadius, double);
  ///@}

  ///@{
  /**
   * Radius of the circle the index is averaged on (default 0.05 of the
   * diagonal; clamped to half the distance to the boundary and to other
   * singularities).
   */
  vtkSetClampMacro(IndexRadius, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(IndexRadius, double);
  ///@}

  ///@{
  /**
   * Largest step of a separatrix (default 0.01 of the diagonal); steps also
   * shrink near the boundary and near singularities.
   */
  vtkSetClampMacro(SeparatrixStep, double, 1e-9, VTK_DOUBLE_MAX);
  vtkGetMacro(SeparatrixStep, double);
  ///@}

  ///@{
  /**
   * Steps of the descent per seed, and of a separatrix (defaults 100, 1000).
   */
  vtkSetClampMacro(MaximumSearchSteps, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumSearchSteps, int);
  vtkSetClampMacro(MaximumSeparatrixSteps, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumSeparatrixSteps, int);
  ///@}

  ///@{
  /**
   * Solver estimates made by the last search and tracing.
   */
  vtkGetMacro(LastNumberOfEstimates, vtkIdType);
  ///@}

protected:
  vtkWalkOnSpheresCrossField();
  ~vtkWalkOnSpheresCrossField() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool SearchSingularities = true;
  int SearchMethod = WINDING;
  int SearchGridCells = 16;
  int SearchRefinements = 5;
  bool TraceSeparatrices = true;
  int NumberOfSeeds = 32;
  int SearchWalksPerPoint = 1024;
  double MergeRadius = 0.02;
  double IndexRadius = 0.05;
  double SeparatrixStep = 0.01;
  int MaximumSearchSteps = 100;
  int MaximumSeparatrixSteps = 1000;
  vtkIdType LastNumberOfEstimates = 0;

private:
  vtkWalkOnSpheresCrossField(const vtkWalkOnSpheresCrossField&) = delete;
  void operator=(const vtkWalkOnSpheresCrossField&) = delete;
};

#endif
