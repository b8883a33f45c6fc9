// The core boundary of a solve from what vtkWalkOnSpheresSolver resolved
// from its inputs: a mesh with its value table, a mesh with values from
// expressions, an implicit surface with values from expressions or sampled
// from a mesh, or a CSG of meshes and an implicit surface (paper Sec.
// 5.1.3–5.1.4). Reports dropped cells and a too small Lipschitz bound as
// warnings, and what makes the inputs unusable as an error, of `reporter`.
// Private to the GridFree::Filters module.
#ifndef GridFreeBoundaryAssembly_h
#define GridFreeBoundaryAssembly_h

#include <gridfree/boundary/Boundary.h>
#include <gridfree/stars/MixedBoundary.h>

class vtkObject;
namespace gridfree
{
struct ProblemInputs;
}

namespace gridfree
{
// Builds `geometry` (values, hierarchy, bound grid; two-sided if asked);
// false after an error message.
template <int DIM>
bool AssembleBoundary(vtkObject* reporter, const gridfree::ProblemInputs& in,
  Boundary<DIM>& geometry);

// Builds the mixed boundary of walk on stars from the mesh, its values and
// its condition, flux and Robin arrays (in.Mixed); false after an error
// message.
template <int DIM>
bool AssembleMixedBoundary(vtkObject* reporter, const gridfree::ProblemInputs& in,
  MixedBoundary<DIM>& mixed);

// The plane of a 2D problem (the boundary's z), where expressions and
// sources are sampled; 0 for a 3D one.
template <int DIM>
double ProblemPlaneZ(const gridfree::ProblemInputs& in);

extern template bool AssembleBoundary<2>(vtkObject*, const gridfree::ProblemInputs&, Boundary<2>&);
extern template bool AssembleBoundary<3>(vtkObject*, const gridfree::ProblemInputs&, Boundary<3>&);
extern template bool AssembleMixedBoundary<2>(
  vtkObject*, const gridfree::ProblemInputs&, MixedBoundary<2>&);
extern template bool AssembleMixedBoundary<3>(
  vtkObject*, const gridfree::ProblemInputs&, MixedBoundary<3>&);
extern template double ProblemPlaneZ<2>(const gridfree::ProblemInputs&);
extern template double ProblemPlaneZ<3>(const gridfree::ProblemInputs&);
} // namespace gridfree

#endif
