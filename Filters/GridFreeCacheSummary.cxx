#include "GridFreeCacheSummary.h"

#include "GridFreeArrays.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"

namespace gridfree
{
void AddCacheSummary(const std::vector<vtkDataSet*>& solves, vtkDataSet* output)
{
  if (solves.empty())
  {
    return;
  }
  if (vtkDataArray* fromCache = solves.front()->GetPointData()->GetArray("FromBoundaryCache"))
  {
    output->GetPointData()->AddArray(fromCache);
  }
  auto value = [](vtkDataSet* solve, const char* name) {
    vtkDataArray* array = solve->GetFieldData()->GetArray(name);
    return array && array->GetNumberOfTuples() > 0 ? array->GetComponent(0, 0) : 0.0;
  };
  for (const char* shared : { "PointsFromCache", "PointsWalkedInShell", "OutsidePoints" })
  {
    AddFieldValue(output->GetFieldData(), shared, value(solves.front(), shared));
  }
  for (const char* summed : { "CacheSpheres", "CacheWalks", "CacheWalksRun", "CacheSeconds" })
  {
    double total = 0.0;
    for (vtkDataSet* solve : solves)
    {
      total += value(solve, summed);
    }
    AddFieldValue(output->GetFieldData(), summed, total);
  }
}
} // namespace gridfree
