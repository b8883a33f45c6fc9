#include "GridFreeBoundaryValueArrays.h"

#include "GridFreeArraySelection.h"
#include "GridFreeBoundaryConversion.h"
#include "GridFreeProblemInputs.h"
#include "GridFreeSolveSettings.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkImplicitFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <cmath>
#include <string>
#include <vector>

namespace
{
vtkIdType CountNonFinite(vtkDataArray* values)
{
  vtkIdType nonFinite = 0;
  for (vtkIdType t = 0; t < values->GetNumberOfTuples(); ++t)
  {
    for (int c = 0; c < values->GetNumberOfComponents(); ++c)
    {
      nonFinite += std::isfinite(values->GetComponent(t, c)) ? 0 : 1;
    }
  }
  return nonFinite;
}

// g and h side by side, so one closest-point query gives both.
vtkSmartPointer<vtkDoubleArray> Concatenate(vtkDataArray* g, vtkDataArray* h)
{
  const int nc = g->GetNumberOfComponents();
  auto both = vtkSmartPointer<vtkDoubleArray>::New();
  both->SetName(g->GetName());
  both->SetNumberOfComponents(2 * nc);
  both->SetNumberOfTuples(g->GetNumberOfTuples());
  for (vtkIdType t = 0; t < g->GetNumberOfTuples(); ++t)
  {
    for (int c = 0; c < nc; ++c)
    {
      both->SetComponent(t, c, g->GetComponent(t, c));
      both->SetComponent(t, nc + c, h->GetComponent(t, c));
    }
  }
  return both;
}
} // namespace

bool gridfree::BoundaryValuesOfMesh(const gridfree::BoundaryValueContext& context,
  vtkPolyData* mesh, const std::string& what, std::string& name,
  vtkSmartPointer<vtkDataArray>& combined, bool& cellData)
{
  std::string reason;
  int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* values = context.Arrays.Resolve(0, mesh, true, association, reason);
  if (!values)
  {
    vtkErrorWithObjectMacro(context.Reporter,
      << (reason.empty() ? "No boundary values on " + what +
               ": select a numeric point or cell array with SetInputArrayToProcess(0, 0, 0, "
               "association, name), or set BoundaryValueExpression."
                         : "Cannot use the boundary values of " + what + ": " + reason + "."));
    return false;
  }
  if (values->GetName() && *values->GetName())
  {
    name = values->GetName();
  }
  cellData = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS && !cellData)
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "Boundary values must be point data or cell data.");
    return false;
  }
  // Non-finite boundary data would silently poison every walk that ends near it.
  if (const vtkIdType nonFinite = CountNonFinite(values))
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The boundary value array '" << name << "' of " << what << " has "
                        << nonFinite << " NaN or infinite values: boundary values must be finite.");
    return false;
  }
  combined = values;
  if (context.Settings.TwoSidedBoundaryValues)
  {
    return gridfree::BackBoundaryValues(context, mesh, what, name, values, association, combined);
  }
  if (context.Settings.Equation != gridfree::Equation::Biharmonic)
  {
    return true;
  }
  // The biharmonic equation's second boundary array h = Δu.
  int hAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* h = context.Arrays.Resolve(1, mesh, false, hAssociation, reason);
  if (!h)
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The biharmonic equation needs a second boundary array for "
                           "the Laplacian h (Δu = h on the boundary) on "
                        << what
                        << ", selected with SetInputArrayToProcess(1, 0, 0, "
                           "association, name)"
                        << (reason.empty() ? std::string(".") : ": " + reason + "."));
    return false;
  }
  if (hAssociation != association || h->GetNumberOfComponents() != values->GetNumberOfComponents())
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The Laplacian array '" << (h->GetName() ? h->GetName() : "")
                        << "' must have the association (point or cell data) and "
                           "the number of components of the boundary value array '"
                        << name << "'.");
    return false;
  }
  if (const vtkIdType nonFinite = CountNonFinite(h))
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The Laplacian array has " << nonFinite
                        << " NaN or infinite values: boundary values must be finite.");
    return false;
  }
  combined = Concatenate(values, h);
  return true;
}

bool gridfree::BackBoundaryValues(const gridfree::BoundaryValueContext& context, vtkPolyData* mesh,
  const std::string& what, const std::string& name, vtkDataArray* values, int association,
  vtkSmartPointer<vtkDataArray>& combined)
{
  std::string reason;
  int backAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* back = context.Arrays.Resolve(3, mesh, false, backAssociation, reason);
  if (!back)
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "Two-sided boundary values need the back side's array on " << what
                        << ", selected with SetInputArrayToProcess(3, 0, 0, "
                           "association, name)"
                        << (reason.empty() ? std::string(".") : ": " + reason + "."));
    return false;
  }
  if (backAssociation != association ||
    back->GetNumberOfComponents() != values->GetNumberOfComponents())
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The back value array '" << (back->GetName() ? back->GetName() : "")
                        << "' must have the association (point or cell data) and "
                           "the number of components of the front value array '"
                        << name << "'.");
    return false;
  }
  if (const vtkIdType nonFinite = CountNonFinite(back))
  {
    vtkErrorWithObjectMacro(
      context.Reporter, << "The back value array has " << nonFinite
                        << " NaN or infinite values: boundary values must be finite.");
    return false;
  }
  combined = Concatenate(values, back);
  return true;
}

bool gridfree::BoundaryValuesOfBoundary(const gridfree::BoundaryValueContext& context,
  vtkPolyData* boundary, bool implicit, bool expressionValues, int& dimension, std::string& name,
  vtkSmartPointer<vtkDataArray>& combined, bool& cellData)
{
  std::string reason;
  if (boundary)
  {
    dimension = gridfree::DetectBoundaryDimension(boundary, reason);
    if (dimension == 0)
    {
      vtkErrorWithObjectMacro(
        context.Reporter, << "Cannot use the Boundary input: " << reason << ".");
      return false;
    }
    if (implicit && dimension != 3)
    {
      vtkErrorWithObjectMacro(
        context.Reporter, << "An implicit boundary makes a 3D problem: the mesh its "
                             "values are sampled from must be a surface (polygons), "
                             "not lines.");
      return false;
    }
  }
  return expressionValues ||
    gridfree::BoundaryValuesOfMesh(
      context, boundary, "the Boundary input", name, combined, cellData);
}

bool gridfree::BoundaryValuesOfCsgOperands(const gridfree::BoundaryValueContext& context,
  const std::vector<vtkPolyData*>& blocks, bool expressionValues, gridfree::ProblemInputs& inputs,
  int& dimension, std::string& name)
{
  const bool implicit = context.Settings.ImplicitBoundary != nullptr;
  dimension = implicit ? 3 : 0;
  int components = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i)
  {
    const std::string what = blocks.size() == 1 && !implicit
      ? std::string("the Boundary input")
      : "block " + std::to_string(i) + " of the Boundary input";
    std::string reason;
    const int d = gridfree::DetectBoundaryDimension(blocks[i], reason);
    if (d == 0)
    {
      vtkErrorWithObjectMacro(context.Reporter, << "Cannot use " << what << ": " << reason << ".");
      return false;
    }
    if (dimension != 0 && d != dimension)
    {
      vtkErrorWithObjectMacro(context.Reporter,
        << "The CSG operands mix 2D and 3D: " << what << " makes a " << d << "D problem, "
        << (implicit ? "the implicit boundary" : "block 0") << " a " << dimension << "D one.");
      return false;
    }
    dimension = d;
    gridfree::CsgMeshOperand operand;
    operand.Mesh = blocks[i];
    if (!expressionValues)
    {
      vtkSmartPointer<vtkDataArray> values;
      std::string blockName = name;
      if (!gridfree::BoundaryValuesOfMesh(
            context, blocks[i], what, blockName, values, operand.CellData))
      {
        return false;
      }
      if (i == 0)
      {
        name = blockName;
        components = values->GetNumberOfComponents();
      }
      else if (values->GetNumberOfComponents() != components)
      {
        vtkErrorWithObjectMacro(context.Reporter, << "The boundary values of " << what << " have "
                                                  << values->GetNumberOfComponents()
                                                  << " components, those of block 0 " << components
                                                  << ": every block needs the same number.");
        return false;
      }
      operand.Values = values;
      inputs.CsgValues.push_back(values);
    }
    inputs.CsgOperands.push_back(operand);
  }
  return true;
}
