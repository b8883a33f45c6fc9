#include "GridFreeCsgBoundary.h"

#include "GridFreeBoundaryConversion.h"

#include <gridfree/implicit/ImplicitBoundary.h>
#include <gridfree/implicit/MeshSignedDistance.h>

#include "vtkDataArray.h"
#include "vtkPolyData.h"

#include <limits>
#include <stdexcept>

namespace gridfree
{
namespace
{
// g at the end of a walk: the values of the operand whose surface the walk
// reached (the part the CSG tree reports), sampled at that operand's own
// closest point.
template <int DIM>
class OperandBoundaryValues final : public BoundaryValueFunction<DIM>
{
public:
  explicit OperandBoundaryValues(std::vector<std::shared_ptr<const Boundary<DIM>>> carriers)
    : Carriers(std::move(carriers))
  {
    if (this->Carriers.empty())
    {
      throw std::invalid_argument("CSG values: no operands");
    }
    this->NumberOfComponents = this->Carriers.front()->Components();
    for (const auto& carrier : this->Carriers)
    {
      if (!carrier || carrier->Components() != this->NumberOfComponents)
      {
        throw std::invalid_argument("CSG values: operands differ in their number of components");
      }
    }
  }

  int Components() const override { return this->NumberOfComponents; }

  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const override
  {
    if (hit.primitive < 0 || static_cast<std::size_t>(hit.primitive) >= this->Carriers.size())
    {
      // Not an operand with values: never pass a missing value off as data.
      for (int c = 0; c < this->NumberOfComponents; ++c)
      {
        out[c] = std::numeric_limits<double>::quiet_NaN();
      }
      return;
    }
    const Boundary<DIM>& carrier = *this->Carriers[static_cast<std::size_t>(hit.primitive)];
    carrier.Evaluate(carrier.ClosestPoint(hit.point), out);
  }

private:
  std::vector<std::shared_ptr<const Boundary<DIM>>> Carriers;
  int NumberOfComponents = 1;
};

template <int DIM>
using DistancePointer = std::shared_ptr<const SignedDistanceFunction<DIM>>;

template <int DIM>
DistancePointer<DIM> Combine(
  CsgOperation operation, double blend, const std::vector<DistancePointer<DIM>>& operands)
{
  if (operands.size() == 1)
  {
    return operands.front();
  }
  if (operation == CsgOperation::Difference)
  {
    // A − (B ∪ C ∪ …): parts keep the operands' order.
    DistancePointer<DIM> removed = operands[1];
    for (std::size_t i = 2; i < operands.size(); ++i)
    {
      removed = std::make_shared<CsgDistance<DIM>>(CsgOperation::Union, removed, operands[i], blend);
    }
    return std::make_shared<CsgDistance<DIM>>(CsgOperation::Difference, operands[0], removed, blend);
  }
  DistancePointer<DIM> tree = operands[0];
  for (std::size_t i = 1; i < operands.size(); ++i)
  {
    tree = std::make_shared<CsgDistance<DIM>>(operation, tree, operands[i], blend);
  }
  return tree;
}
} // namespace

template <int DIM>
bool BuildCsgBoundary(const std::vector<CsgMeshOperand>& meshes,
  std::shared_ptr<const SignedDistanceFunction<DIM>> implicitOperand, CsgOperation operation,
  double blendRadius, std::shared_ptr<const BoundaryValueFunction<DIM>> expressionValues,
  const BoundingBox<DIM>& probeBox, Boundary<DIM>& out, CsgBoundaryReport& report,
  std::string& reason)
{
  if (meshes.empty() && !implicitOperand)
  {
    reason = "there is nothing to combine";
    return false;
  }
  if (!(blendRadius >= 0.0) || !std::isfinite(blendRadius))
  {
    reason = "the blend radius must be finite and non-negative";
    return false;
  }
  if (implicitOperand && !expressionValues)
  {
    reason = "an implicit function among the operands has no values of its own: set "
             "BoundaryValueExpression";
    return false;
  }

  std::vector<DistancePointer<DIM>> operands;
  std::vector<std::shared_ptr<const Boundary<DIM>>> carriers;
  BoundingBox<DIM> meshBox;
  for (std::size_t i = 0; i < meshes.size(); ++i)
  {
    const CsgMeshOperand& operand = meshes[i];
    auto carrier = std::make_shared<Boundary<DIM>>();
    BoundaryConversionReport converted;
    std::string why;
    if (!operand.Mesh ||
      !ConvertBoundary<DIM>(operand.Mesh, operand.Values, operand.CellData, *carrier, converted,
        why, expressionValues))
    {
      reason = "block " + std::to_string(i) + " of the Boundary input: " +
        (why.empty() ? std::string("no mesh") : why);
      return false;
    }
    report.DegenerateCells += converted.DegenerateCells;
    report.SkippedCells += converted.SkippedCells;
    report.IgnoredLowerDimensionalCells += converted.IgnoredLowerDimensionalCells;
    if (!carrier->IsMesh())
    {
      reason = "block " + std::to_string(i) +
        " of the Boundary input has Bézier curves, which cannot take part in CSG (their inside "
        "is not defined here): use polylines";
      return false;
    }
    try
    {
      operands.push_back(
        MeshSignedDistance<DIM>::Create(carrier->MeshVertices(), carrier->MeshPrimitives()));
    }
    catch (const std::exception& e)
    {
      reason = "block " + std::to_string(i) + " of the Boundary input: " + e.what();
      return false;
    }
    meshBox.Expand(carrier->BoundsMin());
    meshBox.Expand(carrier->BoundsMax());
    carriers.push_back(std::move(carrier));
  }
  if (implicitOperand)
  {
    operands.push_back(implicitOperand);
  }

  DistancePointer<DIM> phi;
  try
  {
    phi = Combine<DIM>(operation, blendRadius, operands);
  }
  catch (const std::exception& e)
  {
    reason = e.what();
    return false;
  }

  std::shared_ptr<const BoundaryValueFunction<DIM>> values = expressionValues;
  try
  {
    if (!values)
    {
      values = std::make_shared<OperandBoundaryValues<DIM>>(std::move(carriers));
    }
  }
  catch (const std::exception& e)
  {
    reason = e.what();
    return false;
  }

  // Where the combination is unbounded (a half-space operand), the problem
  // lives in the box of the probe and the meshes, enlarged, as for a single
  // implicit boundary.
  BoundingBox<DIM> region = probeBox;
  if (!meshBox.IsEmpty())
  {
    region.Expand(meshBox);
  }
  if (!region.IsEmpty())
  {
    const Vec<DIM> centre = region.Center();
    const Vec<DIM> half =
      0.75 * region.Extent() + Vec<DIM>::Constant(1e-3 * std::max(region.Diagonal(), 1e-12));
    region = BoundingBox<DIM>(centre - half, centre + half);
  }
  try
  {
    auto shape = std::make_shared<ImplicitBoundaryGeometry<DIM>>(phi);
    out.SetGeometry(shape, values, region);
  }
  catch (const std::exception& e)
  {
    reason = e.what();
    return false;
  }
  return true;
}

template bool BuildCsgBoundary<2>(const std::vector<CsgMeshOperand>&,
  std::shared_ptr<const SignedDistanceFunction<2>>, CsgOperation, double,
  std::shared_ptr<const BoundaryValueFunction<2>>, const BoundingBox<2>&, Boundary<2>&,
  CsgBoundaryReport&, std::string&);
template bool BuildCsgBoundary<3>(const std::vector<CsgMeshOperand>&,
  std::shared_ptr<const SignedDistanceFunction<3>>, CsgOperation, double,
  std::shared_ptr<const BoundaryValueFunction<3>>, const BoundingBox<3>&, Boundary<3>&,
  CsgBoundaryReport&, std::string&);
} // namespace gridfree
