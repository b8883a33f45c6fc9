// The k nearest samples of a point that are visible from it: no boundary
// primitive crosses the segment between them (paper Sec. 5.2.1: "to avoid
// bleeding artifacts we shoot rays to exclude neighbors not visible from
// sample points"). Shared by the moving least squares interpolator and the
// adaptive sampler, so both see the same neighbourhoods.
// Private to the GridFree::Filters module.
//
// Nearest candidates come from a vtkStaticPointLocator over the samples;
// visibility from the estimator core's hierarchy over the boundary (3D
// triangles, or 2D segments for a boundary of lines in one z-plane), with
// Bvh::Occluded. Candidates are taken in order of distance, in growing
// batches (2k, 4k, ... up to kMaxCandidates) until k visible ones are found,
// so a point walled off from most samples still finds the ones on its side.
#ifndef GridFreeVisibleNeighbours_h
#define GridFreeVisibleNeighbours_h

#include <gridfree/boundary/Boundary.h>

#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class vtkIdList;
class vtkPoints;
class vtkPolyData;
class vtkStaticPointLocator;

namespace gridfree
{
class VisibleNeighbours
{
public:
  // Candidates examined at most per query (visible or not).
  static constexpr int kMaxCandidates = 1024;

  VisibleNeighbours();
  ~VisibleNeighbours();

  // The samples to search. Keeps a reference; rebuild after changing them.
  void SetSamples(vtkPoints* samples);

  // The boundary that blocks visibility (null: everything is visible).
  // False with a reason when it holds no surface (3D) or lines (2D).
  bool SetBoundary(vtkPolyData* boundary, std::string& reason);
  bool HasBoundary() const { return this->Dimension != 0; }

  // Per-thread scratch of Find().
  struct Scratch
  {
    Scratch();
    vtkSmartPointer<vtkIdList> Ids;
  };

  // The ids of up to k samples nearest to x that x sees, nearest first.
  // Thread-safe (after SetSamples, SetBoundary, from one thread).
  void Find(const double x[3], int k, Scratch& scratch, std::vector<vtkIdType>& out) const;

  // Whether the segment from a to b crosses the boundary (primitives that a
  // or b lie on do not count).
  bool Blocked(const double a[3], const double b[3]) const;

private:
  vtkSmartPointer<vtkPoints> Samples;
  vtkNew<vtkStaticPointLocator> Locator;
  int Dimension = 0; // of the blocking boundary; 0 without one
  std::unique_ptr<Boundary<2>> Boundary2;
  std::unique_ptr<Boundary<3>> Boundary3;
};
} // namespace gridfree

#endif
