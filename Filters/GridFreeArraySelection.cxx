#include "GridFreeArraySelection.h"

#include "vtkAbstractArray.h"
#include "vtkAlgorithm.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"

namespace gridfree
{
namespace
{
// The array `selection` names (or the attribute it asks for), looked up as
// vtkAlgorithm::GetInputArrayToProcess does; `association` becomes where it
// was found.
vtkAbstractArray* Lookup(const ArraySelection& selection, vtkDataSet* data, int& association)
{
  association = selection.Association;
  const bool byName = !selection.Name.empty();
  auto find = [&](vtkDataSetAttributes* attributes) -> vtkAbstractArray* {
    return byName ? attributes->GetAbstractArray(selection.Name.c_str())
                  : attributes->GetAbstractAttribute(selection.AttributeType);
  };
  switch (selection.Association)
  {
    case vtkDataObject::FIELD_ASSOCIATION_POINTS:
      return find(data->GetPointData());
    case vtkDataObject::FIELD_ASSOCIATION_NONE:
      return byName ? data->GetFieldData()->GetAbstractArray(selection.Name.c_str()) : nullptr;
    case vtkDataObject::FIELD_ASSOCIATION_POINTS_THEN_CELLS:
      if (vtkAbstractArray* onPoints = find(data->GetPointData()))
      {
        association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
        return onPoints;
      }
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
      return find(data->GetCellData());
    default:
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
      return find(data->GetCellData());
  }
}
} // namespace

ArraySelections ArraySelections::Of(vtkAlgorithm* algorithm)
{
  ArraySelections selections;
  for (int index = 0; index < Count; ++index)
  {
    vtkInformation* info = algorithm ? algorithm->GetInputArrayInformation(index) : nullptr;
    if (!info)
    {
      continue;
    }
    ArraySelection& s = selections.Index[static_cast<std::size_t>(index)];
    if (info->Has(vtkDataObject::FIELD_NAME()) && info->Get(vtkDataObject::FIELD_NAME()))
    {
      s.Name = info->Get(vtkDataObject::FIELD_NAME());
    }
    if (info->Has(vtkDataObject::FIELD_ATTRIBUTE_TYPE()))
    {
      s.AttributeType = info->Get(vtkDataObject::FIELD_ATTRIBUTE_TYPE());
    }
    if (info->Has(vtkDataObject::FIELD_ASSOCIATION()))
    {
      s.Association = info->Get(vtkDataObject::FIELD_ASSOCIATION());
    }
    s.Selected = !s.Name.empty() || s.AttributeType >= 0;
  }
  return selections;
}

void ArraySelections::Select(int index, int association, const std::string& name)
{
  ArraySelection& s = this->Index.at(static_cast<std::size_t>(index));
  s.Selected = !name.empty();
  s.Name = name;
  s.Association = association;
  s.AttributeType = -1;
}

vtkDataArray* ArraySelections::Resolve(
  int index, vtkDataSet* data, bool fallback, int& association, std::string& missing) const
{
  missing.clear();
  association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  const ArraySelection& selection = this->Index.at(static_cast<std::size_t>(index));
  vtkDataArray* values = nullptr;
  if (selection.Selected)
  {
    values = vtkDataArray::SafeDownCast(Lookup(selection, data, association));
  }
  if (!values && !selection.Name.empty())
  {
    vtkAbstractArray* any = data->GetPointData()->GetAbstractArray(selection.Name.c_str());
    if (!any)
    {
      any = data->GetCellData()->GetAbstractArray(selection.Name.c_str());
    }
    missing = any ? "the array '" + selection.Name + "' is a " + any->GetClassName() +
        ", not a numeric array"
                  : "there is no point or cell array named '" + selection.Name + "'";
    return nullptr;
  }
  if (!values && fallback)
  {
    association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    values = data->GetPointData()->GetScalars();
    if (!values)
    {
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
      values = data->GetCellData()->GetScalars();
    }
  }
  // vtkDataSetAttributes accepts arrays of any length; reading one tuple per
  // point (or cell) of a shorter array would read past its end.
  const bool cells = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  const vtkIdType expected = cells ? data->GetNumberOfCells() : data->GetNumberOfPoints();
  if (values && (association == vtkDataObject::FIELD_ASSOCIATION_POINTS || cells) &&
    values->GetNumberOfTuples() != expected)
  {
    missing = "the array '" + std::string(values->GetName() ? values->GetName() : "") + "' has " +
      std::to_string(values->GetNumberOfTuples()) + " tuples, but the mesh has " +
      std::to_string(expected) + (cells ? " cells" : " points");
    return nullptr;
  }
  return values;
}
} // namespace gridfree
