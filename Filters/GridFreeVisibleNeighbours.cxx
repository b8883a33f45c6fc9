#include "GridFreeVisibleNeighbours.h"

#include "GridFreeBoundaryConversion.h"

#include "vtkIdList.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStaticPointLocator.h"

#include <algorithm>

namespace gridfree
{
namespace
{
// Visibility needs the geometry only: every boundary point gets the value 0.
template <int DIM>
class NoValues final : public BoundaryValueFunction<DIM>
{
public:
  int Components() const override { return 1; }
  void Evaluate(const ClosestPointResult<DIM>&, double* out) const override { out[0] = 0.0; }
};

template <int DIM>
bool BlockedIn(const Boundary<DIM>& boundary, const double a[3], const double b[3])
{
  Vec<DIM> origin, direction;
  for (int k = 0; k < DIM; ++k)
  {
    origin[k] = a[k];
    direction[k] = b[k] - a[k];
  }
  // The small margins at both ends skip primitives a or b lie on (a slice
  // point on the surface, a sample at a wall).
  constexpr double margin = 1e-6;
  return boundary.Hierarchy().Occluded(origin, direction, 1.0 - margin, margin);
}
} // namespace

VisibleNeighbours::VisibleNeighbours() = default;
VisibleNeighbours::~VisibleNeighbours() = default;

VisibleNeighbours::Scratch::Scratch()
  : Ids(vtkSmartPointer<vtkIdList>::New())
{
}

void VisibleNeighbours::SetSamples(vtkPoints* samples)
{
  this->Samples = samples;
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(samples);
  this->Locator->Initialize();
  this->Locator->SetDataSet(cloud);
  this->Locator->BuildLocator();
}

bool VisibleNeighbours::SetBoundary(vtkPolyData* boundary, std::string& reason)
{
  this->Dimension = 0;
  this->Boundary2.reset();
  this->Boundary3.reset();
  if (!boundary)
  {
    return true;
  }
  const int dimension = DetectBoundaryDimension(boundary, reason);
  BoundaryConversionReport report;
  if (dimension == 3)
  {
    auto converted = std::make_unique<Boundary<3>>();
    if (!ConvertBoundary<3>(boundary, nullptr, false, *converted, report, reason,
          std::make_shared<NoValues<3>>()))
    {
      return false;
    }
    this->Boundary3 = std::move(converted);
  }
  else if (dimension == 2)
  {
    auto converted = std::make_unique<Boundary<2>>();
    if (!ConvertBoundary<2>(boundary, nullptr, false, *converted, report, reason,
          std::make_shared<NoValues<2>>()))
    {
      return false;
    }
    if (!converted->IsMesh())
    {
      reason = "visibility is tested against straight boundaries only, not Bezier curves";
      return false;
    }
    this->Boundary2 = std::move(converted);
  }
  else
  {
    return false;
  }
  this->Dimension = dimension;
  return true;
}

bool VisibleNeighbours::Blocked(const double a[3], const double b[3]) const
{
  if (this->Dimension == 3)
  {
    return BlockedIn<3>(*this->Boundary3, a, b);
  }
  if (this->Dimension == 2)
  {
    return BlockedIn<2>(*this->Boundary2, a, b);
  }
  return false;
}

void VisibleNeighbours::Find(
  const double x[3], int k, Scratch& scratch, std::vector<vtkIdType>& out) const
{
  out.clear();
  const vtkIdType available = this->Samples ? this->Samples->GetNumberOfPoints() : 0;
  if (k <= 0 || available == 0)
  {
    return;
  }
  if (this->Dimension == 0)
  {
    this->Locator->FindClosestNPoints(static_cast<int>(std::min<vtkIdType>(k, available)), x,
      scratch.Ids);
    out.assign(scratch.Ids->begin(), scratch.Ids->end());
    return;
  }
  // Growing batches; each batch re-finds the nearer ones (the locator has
  // no "next n"), and only the new ones are tested.
  vtkIdType examined = 0;
  for (vtkIdType batch = 2 * static_cast<vtkIdType>(k);; batch *= 2)
  {
    const vtkIdType n = std::min<vtkIdType>({ batch, available, kMaxCandidates });
    this->Locator->FindClosestNPoints(static_cast<int>(n), x, scratch.Ids);
    for (vtkIdType i = examined; i < scratch.Ids->GetNumberOfIds(); ++i)
    {
      const vtkIdType id = scratch.Ids->GetId(i);
      double y[3];
      this->Samples->GetPoint(id, y);
      if (!this->Blocked(x, y))
      {
        out.push_back(id);
        if (static_cast<int>(out.size()) == k)
        {
          return;
        }
      }
    }
    examined = scratch.Ids->GetNumberOfIds();
    if (n == available || n == kMaxCandidates)
    {
      return;
    }
  }
}
} // namespace gridfree
