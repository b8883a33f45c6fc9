// The arrays a solve reads, chosen as VTK's SetInputArrayToProcess does
// (by name and association, or by attribute type), kept apart from any
// algorithm: the problem builder resolves the selections of whichever filter
// owns it, and the application filters select the arrays they made
// themselves. Indices: 0 the boundary values g, 1 the biharmonic Laplacian
// h, 2 the source term, 3 the back side's g of two-sided values, 4 the
// boundary condition of mixed conditions, 5 their Neumann flux h, 6 their
// Robin coefficient μ, 7 the diffusion coefficient α and 8 the absorption
// coefficient σ of the equation with varying coefficients (point arrays of
// the Source input, like 2, its f).
// Private to the GridFree::Filters module.
#ifndef GridFreeArraySelection_h
#define GridFreeArraySelection_h

#include <array>
#include <string>

class vtkAlgorithm;
class vtkDataArray;
class vtkDataSet;

namespace gridfree
{
struct ArraySelection
{
  bool Selected = false; // by Name, or by AttributeType when Name is empty
  std::string Name;
  int Association = 0; // vtkDataObject::FIELD_ASSOCIATION_POINTS
  int AttributeType = -1;
};

struct ArraySelections
{
  static constexpr int Count = 9;
  std::array<ArraySelection, Count> Index;

  // The selections made on `algorithm` with SetInputArrayToProcess.
  static ArraySelections Of(vtkAlgorithm* algorithm);
  // Selects the array `name` with `association` as input array `index`.
  void Select(int index, int association, const std::string& name);

  // The numeric array selected as `index` on `data`, or, with no selection
  // and `fallback` set, the active point (then cell) scalars. Sets `missing`
  // to an error message when a named array is absent or not numeric, or when
  // the array found has not one tuple per point (cell) of `data`.
  vtkDataArray* Resolve(
    int index, vtkDataSet* data, bool fallback, int& association, std::string& missing) const;
};
} // namespace gridfree

#endif
