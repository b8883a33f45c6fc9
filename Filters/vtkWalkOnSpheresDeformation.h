/**
 * @class   vtkWalkOnSpheresDeformation
 * @brief   2D shape deformation by a biharmonic map between a source and a
 *          target boundary curve, by walk on spheres, without a mesh (paper
 *          Sec. 6.7, Fig. 22).
 *
 * The map φ: Ω → Ω' from the domain Ω bounded by the Source curves to the
 * one bounded by the Target curves solves the biharmonic equation Δ²φ = 0
 * (each coordinate), as Δφ = v, Δv = 0, with
 * - φ = g on ∂Ω: each source point goes to its target point (the two curves
 *   have the same points in the same order: the same parametrization);
 * - Δφ = h on ∂Ω, the paper's "as linear as possible" condition ∂²φ/∂N² = 0,
 *   i.e. h = ∂²φ/∂T² = d²(φ∘γ)/ds² − κ ∂φ/∂N, with the normal derivative
 *   closed by taking φ to be locally a similarity at the boundary
 *   (DeformationBoundaryData.h). Similarity maps are reproduced exactly.
 *
 * Inputs: port 0 "Source" (closed or open polylines in one z-plane: the
 * domain's boundary, and curves inside it that steer the map, as in
 * Fig. 22), port 1 "Probe" (the 2D dataset to deform: an image, polydata,
 * any dataset inside the source domain), port 2 "Target" (the same
 * polylines moved: as many points, point i the image of source point i; its
 * cells are not used).
 *
 * Output: a warped copy of the probe. Point sets keep their type with their
 * points moved to φ(x); images and rectilinear grids become a
 * vtkStructuredGrid of the same dimensions. Arrays: the probe's, plus
 * Deformation (φ(x), 3 components, z kept), Deformation_Variance,
 * Displacement (φ(x) − x) and SourcePosition (x). Field data: TotalWalks,
 * SolveSeconds.
 *
 * Points outside the source domain have no biharmonic solution here (there
 * is no exterior biharmonic solver): keep the probe inside.
 *
 * @sa vtkWalkOnSpheresSolver (biharmonic equation) vtkWalkOnSpheresProbeAlgorithm
 */
#ifndef vtkWalkOnSpheresDeformation_h
#define vtkWalkOnSpheresDeformation_h

#include "GridFreeFiltersModule.h" // for export macro
#include "vtkWalkOnSpheresProbeAlgorithm.h"

class vtkAlgorithmOutput;
class vtkDataObject;

class GRIDFREEFILTERS_EXPORT vtkWalkOnSpheresDeformation : public vtkWalkOnSpheresProbeAlgorithm
{
public:
  static vtkWalkOnSpheresDeformation* New();
  vtkTypeMacro(vtkWalkOnSpheresDeformation, vtkWalkOnSpheresProbeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The source curves (port 0, same as SetBoundary...) and the target
   * curves (port 2).
   */
  void SetSourceConnection(vtkAlgorithmOutput* output) { this->SetBoundaryConnection(output); }
  void SetSourceData(vtkDataObject* data) { this->SetBoundaryData(data); }
  void SetTargetConnection(vtkAlgorithmOutput* output);
  void SetTargetData(vtkDataObject* data);
  ///@}

  ///@{
  /**
   * Use the "as linear as possible" second-order condition (default on);
   * off sets h = 0 (Δφ = 0 on the boundary).
   */
  vtkSetMacro(AsLinearAsPossible, bool);
  vtkGetMacro(AsLinearAsPossible, bool);
  vtkBooleanMacro(AsLinearAsPossible, bool);
  ///@}

protected:
  vtkWalkOnSpheresDeformation();
  ~vtkWalkOnSpheresDeformation() override;

  static constexpr int TargetPort = 2;

  // Images and rectilinear grids become structured grids; point sets keep
  // their type.
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool AsLinearAsPossible = true;

private:
  vtkWalkOnSpheresDeformation(const vtkWalkOnSpheresDeformation&) = delete;
  void operator=(const vtkWalkOnSpheresDeformation&) = delete;
};

#endif
