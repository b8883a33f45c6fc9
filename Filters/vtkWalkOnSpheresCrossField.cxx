#include "vtkWalkOnSpheresCrossField.h"

#include <gridfree/applications/CrossField.h>
#include <gridfree/applications/CrossFieldWinding.h>
#include "GridFreeArrays.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "GridFreeArraySelection.h"
#include "GridFreeCacheSummary.h"
#include "GridFreePointNumbers.h"
#include "GridFreeSolveSettings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkWalkOnSpheresCrossField);

namespace
{
const char* const kPsi = "CrossField";

struct Segment
{
  gridfree::Vec2 A, B;
};

// The boundary's line segments (polylines split), without zero-length ones.
std::vector<Segment> SegmentsOf(vtkPolyData* boundary)
{
  std::vector<Segment> segments;
  auto lines = vtk::TakeSmartPointer(boundary->GetLines()->NewIterator());
  for (lines->GoToFirstCell(); !lines->IsDoneWithTraversal(); lines->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    lines->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k + 1 < n; ++k)
    {
      double a[3], b[3];
      boundary->GetPoint(ids[k], a);
      boundary->GetPoint(ids[k + 1], b);
      Segment s{ gridfree::Vec2(a[0], a[1]), gridfree::Vec2(b[0], b[1]) };
      if ((s.B - s.A).norm() > 0.0)
      {
        segments.push_back(s);
      }
    }
  }
  return segments;
}

// Even-odd rule: inside the region the closed polylines bound.
bool Inside(const std::vector<Segment>& segments, const gridfree::Vec2& p)
{
  bool inside = false;
  for (const Segment& s : segments)
  {
    if ((s.A.y() > p.y()) != (s.B.y() > p.y()))
    {
      const double x = s.A.x() + (p.y() - s.A.y()) / (s.B.y() - s.A.y()) * (s.B.x() - s.A.x());
      inside = x > p.x() ? !inside : inside;
    }
  }
  return inside;
}

// The boundary's closed loops, each with the domain on its left, from its
// segments (joined where they share an end point, whichever way each runs).
// False when the segments do not form closed loops (an end point not shared
// by exactly two segments).
bool LoopsOf(const std::vector<Segment>& segments, std::vector<std::vector<gridfree::Vec2>>& loops)
{
  using Key = std::pair<double, double>;
  std::map<Key, std::vector<std::size_t>> ends;
  for (std::size_t k = 0; k < segments.size(); ++k)
  {
    ends[{ segments[k].A.x(), segments[k].A.y() }].push_back(k);
    ends[{ segments[k].B.x(), segments[k].B.y() }].push_back(k);
  }
  for (const auto& e : ends)
  {
    if (e.second.size() != 2)
    {
      return false;
    }
  }
  std::vector<char> used(segments.size(), 0);
  for (std::size_t first = 0; first < segments.size(); ++first)
  {
    if (used[first])
    {
      continue;
    }
    std::vector<gridfree::Vec2> loop;
    std::size_t k = first;
    gridfree::Vec2 at = segments[k].A;
    while (!used[k])
    {
      used[k] = 1;
      loop.push_back(at);
      at = (segments[k].A == at) ? segments[k].B : segments[k].A;
      const auto& pair = ends.at({ at.x(), at.y() });
      k = pair[0] == k ? pair[1] : pair[0];
    }
    // The domain on the left: test a point just left of the first side.
    const gridfree::Vec2 next = loop.size() > 1 ? loop[1] : loop[0];
    const gridfree::Vec2 d = next - loop[0];
    const gridfree::Vec2 left = 0.5 * (loop[0] + next) + 1e-6 * gridfree::Vec2(-d.y(), d.x());
    if (!Inside(segments, left))
    {
      std::reverse(loop.begin(), loop.end());
    }
    loops.push_back(std::move(loop));
  }
  return true;
}

// Radical inverse in base b: the Halton sequence spreads the seeds evenly.
double RadicalInverse(unsigned long long index, unsigned base)
{
  double result = 0.0, scale = 1.0 / base;
  for (; index > 0; index /= base, scale /= base)
  {
    result += static_cast<double>(index % base) * scale;
  }
  return result;
}

// The solver's boundary: one line per segment in the plane z0, carrying ν⁴
// as cell data (each segment's own normal, so corners are exact).
vtkSmartPointer<vtkPolyData> EncodedBoundary(const std::vector<Segment>& segments, double z0)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  auto nu4 = gridfree::MakeArray(kPsi, 2, static_cast<vtkIdType>(segments.size()));
  for (std::size_t k = 0; k < segments.size(); ++k)
  {
    const Segment& s = segments[k];
    const vtkIdType a = points->InsertNextPoint(s.A.x(), s.A.y(), z0);
    const vtkIdType b = points->InsertNextPoint(s.B.x(), s.B.y(), z0);
    const vtkIdType ids[2] = { a, b };
    lines->InsertNextCell(2, ids);
    const gridfree::Vec2 d = s.B - s.A;
    const std::complex<double> value = gridfree::EncodeNormalFourth(gridfree::Vec2(d.y(), -d.x()));
    nu4->SetComponent(static_cast<vtkIdType>(k), 0, value.real());
    nu4->SetComponent(static_cast<vtkIdType>(k), 1, value.imag());
  }
  auto encoded = vtkSmartPointer<vtkPolyData>::New();
  encoded->SetPoints(points);
  encoded->SetLines(lines);
  encoded->GetCellData()->AddArray(nu4);
  return encoded;
}

// The probe's output arrays: ψ, its variance and gradient as solved, and
// the cross's four directions (0 where ψ vanishes).
void AddCrossArrays(vtkPointData* solved, vtkDataSet* output)
{
  vtkDataArray* psi = solved->GetArray(kPsi);
  for (const std::string suffix : { "", "_Variance", "_Gradient", "_Gradient_Variance" })
  {
    if (vtkDataArray* a = solved->GetArray((kPsi + suffix).c_str()))
    {
      output->GetPointData()->AddArray(a);
    }
  }
  const vtkIdType n = output->GetNumberOfPoints();
  std::array<vtkSmartPointer<vtkDoubleArray>, 4> directions;
  for (int k = 0; k < 4; ++k)
  {
    directions[k] = gridfree::MakeArray("CrossDirection" + std::to_string(k + 1), 3, n);
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    std::array<gridfree::Vec2, 4> cross;
    const bool defined = gridfree::CrossDirections(
      std::complex<double>(psi->GetComponent(i, 0), psi->GetComponent(i, 1)), cross);
    for (int k = 0; k < 4; ++k)
    {
      const double v[3] = { defined ? cross[k].x() : 0.0, defined ? cross[k].y() : 0.0, 0.0 };
      directions[k]->SetTuple(i, v);
    }
  }
  for (const auto& d : directions)
  {
    output->GetPointData()->AddArray(d);
  }
  output->GetPointData()->SetActiveVectors("CrossDirection1");
}

// How the singularities are searched (the filter's properties).
struct SearchParameters
{
  bool Winding = true;
  int GridCells = 64;
  int Refinements = 0;
  int Seed = 0;
  int Seeds = 0;
  int MaximumSteps = 0;
  double MergeRadius = 0.0;
  double IndexRadius = 0.0;
};

// What a search found and how it went.
struct SearchResult
{
  std::vector<gridfree::Singularity> Singularities;
  gridfree::SingularitySearchStatistics Statistics;
  gridfree::WindingSearchStatistics Winding;
  std::size_t Seeds = 0;
  int GridCellsUsed = 0;
};

// The core's search: by the winding of ψ around grid cells (the grid
// doubled, up to 8 times as fine, while the indices found fall short of the
// boundary's `boundarySum` when `checkable`), or by descent from Halton
// seeds inside.
SearchResult FindCrossFieldSingularities(const gridfree::CrossFieldEvaluator& evaluate,
  const std::vector<Segment>& segments, const double bounds[6], double diagonal,
  const SearchParameters& with, bool checkable, int boundarySum)
{
  SearchResult found;
  int gridCells = with.GridCells;
  if (with.Winding)
  {
    // The grid only covers cells wholly inside: where the indices found
    // fall short of the boundary's (singularities in narrow parts or near
    // corners), the grid is doubled, up to 8 times as fine.
    for (;;)
    {
      gridfree::WindingSearchSettings settings;
      settings.GridCells = gridCells;
      settings.MaxLevels = with.Refinements;
      found.Singularities = gridfree::FindSingularitiesByWinding(
        evaluate, [&segments](const gridfree::Vec2& p) { return Inside(segments, p); },
        gridfree::Vec2(bounds[0], bounds[2]), gridfree::Vec2(bounds[1], bounds[3]), settings,
        &found.Winding);
      int sum = 0;
      for (const gridfree::Singularity& s : found.Singularities)
      {
        sum += s.Index;
      }
      if (found.Winding.Aborted || !checkable || sum == boundarySum ||
        gridCells >= std::min(8 * with.GridCells, 1024))
      {
        break;
      }
      gridCells = std::min(2 * gridCells, 1024);
    }
    found.Statistics.Aborted = found.Winding.Aborted;
    found.GridCellsUsed = gridCells;
    return found;
  }
  // Seeds: a Halton sequence over the boundary's box, inside points only.
  std::vector<gridfree::Vec2> seeds;
  const unsigned long long start =
    1 + static_cast<unsigned long long>(static_cast<unsigned>(with.Seed)) * 7919ULL;
  for (unsigned long long k = 0;
       static_cast<int>(seeds.size()) < with.Seeds && k < 1000ULL * with.Seeds; ++k)
  {
    const gridfree::Vec2 p(bounds[0] + (bounds[1] - bounds[0]) * RadicalInverse(start + k, 2),
      bounds[2] + (bounds[3] - bounds[2]) * RadicalInverse(start + k, 3));
    if (Inside(segments, p))
    {
      seeds.push_back(p);
    }
  }
  gridfree::SingularitySettings settings;
  settings.MaxIterations = with.MaximumSteps;
  settings.InitialStep = 0.01 * diagonal;
  settings.MaxStep = 0.1 * diagonal;
  settings.MinStep = 1e-6 * diagonal;
  settings.MergeRadius = with.MergeRadius * diagonal;
  settings.IndexRadius = with.IndexRadius * diagonal;
  found.Singularities = gridfree::FindSingularities(evaluate, seeds, settings, &found.Statistics);
  found.Seeds = seeds.size();
  found.GridCellsUsed = gridCells;
  return found;
}

// The singularities as vertices with their index, residual, |ψ|, seed
// count and radius, and the search's figures as field data.
void WriteSingularities(const SearchResult& found, bool winding, double z0, vtkPolyData* output)
{
  vtkNew<vtkPoints> singularityPoints;
  singularityPoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> vertices;
  vtkNew<vtkIntArray> index, seedCount;
  index->SetName("Index");
  seedCount->SetName("SeedCount");
  auto residual = gridfree::MakeArray("IndexResidual", 1, 0);
  auto magnitude = gridfree::MakeArray("PsiMagnitude", 1, 0);
  auto radius = gridfree::MakeArray("IndexRadius", 1, 0);
  for (const gridfree::Singularity& s : found.Singularities)
  {
    const vtkIdType id = singularityPoints->InsertNextPoint(s.Position.x(), s.Position.y(), z0);
    vertices->InsertNextCell(1, &id);
    index->InsertNextValue(s.Index);
    seedCount->InsertNextValue(s.SeedCount);
    residual->InsertNextValue(s.IndexResidual);
    magnitude->InsertNextValue(s.PsiMagnitude);
    radius->InsertNextValue(s.Radius);
  }
  output->SetPoints(singularityPoints);
  output->SetVerts(vertices);
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(index), static_cast<vtkDataArray*>(residual),
         static_cast<vtkDataArray*>(magnitude), static_cast<vtkDataArray*>(seedCount),
         static_cast<vtkDataArray*>(radius) })
  {
    output->GetPointData()->AddArray(a);
  }
  output->GetPointData()->SetActiveScalars("Index");
  vtkFieldData* fd = output->GetFieldData();
  if (winding)
  {
    gridfree::AddFieldValue(fd, "SearchGridCellsUsed", found.GridCellsUsed);
    gridfree::AddFieldValue(fd, "GridCellsInside", found.Winding.GridCellsInside);
    gridfree::AddFieldValue(fd, "UnresolvedRegions", found.Winding.UnresolvedRegions);
  }
  else
  {
    // How the seeds ended, for judging a search that found nothing.
    const gridfree::SingularitySearchStatistics& s = found.Statistics;
    gridfree::AddFieldValue(fd, "Seeds", static_cast<double>(found.Seeds));
    gridfree::AddFieldValue(fd, "SeedsConverged", s.SeedsConverged);
    gridfree::AddFieldValue(fd, "SeedsStalled", s.SeedsStalled);
    gridfree::AddFieldValue(fd, "SeedsNotAtZero", s.SeedsNotZero);
    gridfree::AddFieldValue(fd, "SeedsStillMoving", s.SeedsMaxIterations);
    gridfree::AddFieldValue(fd, "ClustersOfIndexZero", s.ClustersZeroIndex);
    gridfree::AddFieldValue(fd, "ClustersUnresolved", s.ClustersUnresolved);
    gridfree::AddFieldValue(fd, "SearchIterations", s.Iterations);
  }
}

// The separatrices as polylines with their end singularities, why they
// stopped and their length; a connection traced from both ends is kept once.
void WriteSeparatrices(
  const std::vector<gridfree::Separatrix>& curves, double z0, vtkPolyData* output)
{
  vtkNew<vtkPoints> curvePoints;
  curvePoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polylines;
  vtkNew<vtkIntArray> source, target, reason;
  source->SetName("SourceSingularity");
  target->SetName("TargetSingularity");
  reason->SetName("StopReason");
  auto length = gridfree::MakeArray("Length", 1, 0);
  for (const gridfree::Separatrix& c : curves)
  {
    bool duplicate = false;
    if (c.Target >= 0 && c.Target < c.Source)
    {
      for (const gridfree::Separatrix& other : curves)
      {
        duplicate = duplicate || (other.Source == c.Target && other.Target == c.Source);
      }
    }
    if (duplicate || c.Points.size() < 2)
    {
      continue;
    }
    polylines->InsertNextCell(static_cast<vtkIdType>(c.Points.size()));
    for (const gridfree::Vec2& p : c.Points)
    {
      polylines->InsertCellPoint(curvePoints->InsertNextPoint(p.x(), p.y(), z0));
    }
    source->InsertNextValue(c.Source);
    target->InsertNextValue(c.Target);
    reason->InsertNextValue(static_cast<int>(c.Reason));
    length->InsertNextValue(c.Length);
  }
  output->SetPoints(curvePoints);
  output->SetLines(polylines);
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(source), static_cast<vtkDataArray*>(target),
         static_cast<vtkDataArray*>(reason), static_cast<vtkDataArray*>(length) })
  {
    output->GetCellData()->AddArray(a);
  }
}
} // namespace

vtkWalkOnSpheresCrossField::vtkWalkOnSpheresCrossField()
{
  this->SetNumberOfOutputPorts(3);
}

vtkWalkOnSpheresCrossField::~vtkWalkOnSpheresCrossField() = default;

void vtkWalkOnSpheresCrossField::SetSearchMethod(int method)
{
  if (method != WINDING && method != SEED_DESCENT)
  {
    vtkErrorMacro(<< "SearchMethod " << method
                  << " is not a choice: 0 (winding) or 1 (seed descent). It stays "
                  << this->SearchMethod << ".");
    return;
  }
  if (method != this->SearchMethod)
  {
    this->SearchMethod = method;
    this->Modified();
  }
}

int vtkWalkOnSpheresCrossField::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  this->LastNumberOfEstimates = 0;
  vtkPolyData* boundary = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  vtkPolyData* singularityOutput = vtkPolyData::GetData(outputVector, 1);
  vtkPolyData* separatrixOutput = vtkPolyData::GetData(outputVector, 2);
  if (!probe || !output)
  {
    vtkErrorMacro(<< "No Probe: connect the dataset to draw crosses on to port 1.");
    return 0;
  }
  output->CopyStructure(probe);
  output->GetPointData()->PassData(probe->GetPointData());
  output->GetCellData()->PassData(probe->GetCellData());
  output->GetFieldData()->PassData(probe->GetFieldData());
  if (!boundary || boundary->GetNumberOfLines() == 0 ||
    boundary->GetNumberOfPolys() + boundary->GetNumberOfStrips() > 0)
  {
    vtkErrorMacro(<< "The Boundary must be closed polylines in one z-plane (a 2D domain): "
                  << (boundary ? "it has no lines or has polygons." : "none is connected."));
    return 0;
  }
  std::vector<Segment> segments = SegmentsOf(boundary);
  if (segments.empty())
  {
    vtkErrorMacro(<< "The Boundary's lines have no segment of non-zero length.");
    return 0;
  }
  if (this->GetEstimator() == BOUNDARY_CACHE)
  {
    vtkErrorMacro(<< "The cross field takes the Pointwise Walks or the Sphere Cache estimator, "
                     "not the Boundary Cache (its gradients' error bars are too short here).");
    return 0;
  }
  if (this->GetEstimator() == SPHERE_CACHE)
  {
    // The cache tells inside from outside by the side of the closest
    // segment, so every segment must have the domain on the same side; the
    // input's loops may run either way (ν and −ν give the same ν⁴), so
    // they are turned to have the domain on their left.
    std::vector<std::vector<gridfree::Vec2>> loops;
    if (!LoopsOf(segments, loops))
    {
      vtkErrorMacro(<< "With the Sphere Cache the Boundary's lines must form closed loops (each "
                       "end point shared by exactly two segments).");
      return 0;
    }
    segments.clear();
    for (const std::vector<gridfree::Vec2>& loop : loops)
    {
      for (std::size_t k = 0; k < loop.size(); ++k)
      {
        segments.push_back(Segment{ loop[k], loop[(k + 1) % loop.size()] });
      }
    }
  }
  double bounds[6];
  boundary->GetBounds(bounds);
  const double z0 = bounds[4];
  if (bounds[5] - bounds[4] > 1e-9 * (1.0 + std::abs(z0)))
  {
    vtkErrorMacro(<< "The Boundary's lines are not in one z-plane (z from " << bounds[4]
                  << " to " << bounds[5] << "): cross fields are 2D.");
    return 0;
  }
  const double diagonal = std::hypot(bounds[1] - bounds[0], bounds[3] - bounds[2]);

  const vtkSmartPointer<vtkPolyData> encoded = EncodedBoundary(segments, z0);

  // One solve of ψ and ∇ψ at `where`, with `walks` walks per point: as the
  // probe's arrays, or as numbers for the singularity search.
  gridfree::ArraySelections psiArrays;
  psiArrays.Select(0, vtkDataObject::FIELD_ASSOCIATION_CELLS, kPsi);
  auto settingsFor = [&](int walks) {
    // The properties this filter keeps (the sampling settings and its own),
    // the solver's defaults for the rest; the solve's own choices below.
    gridfree::SolveSettings settings = this->GetSettings();
    settings.WalksPerPoint = std::max(walks, 2);
    settings.ComputeGradient = true;
    return settings;
  };
  auto solve = [&](vtkDataSet* where, int walks, double begin, double end,
                 vtkSmartPointer<vtkDataSet>& result) {
    bool aborted = false;
    return this->Solve(
      settingsFor(walks), psiArrays, encoded, nullptr, where, begin, end, result, aborted);
  };
  auto solveNumbers = [&](vtkDataSet* where, int walks, double begin, double end,
                        gridfree::PointNumbers& found) {
    bool aborted = false;
    return this->SolveNumbers(
      settingsFor(walks), psiArrays, encoded, nullptr, where, begin, end, found, aborted);
  };

  // The probe: ψ and the four directions.
  const bool search = this->SearchSingularities;
  vtkSmartPointer<vtkDataSet> solved;
  if (probe->GetNumberOfPoints() > 0)
  {
    if (!solve(probe, this->GetWalksPerPoint(), 0.0, search ? 0.3 : 1.0, solved))
    {
      return this->CheckAbort() ? 1 : 0;
    }
    AddCrossArrays(solved->GetPointData(), output);
    if (this->GetEstimator() == SPHERE_CACHE)
    {
      gridfree::AddCacheSummary({ solved.GetPointer() }, output);
    }
  }

  if (search)
  {
    // The evaluator of the core's search and tracing: one solve per batch,
    // each taking a twentieth of the remaining progress of its phase.
    double progress = 0.3, phaseEnd = 0.7;
    bool failed = false;
    gridfree::CrossFieldEvaluator evaluate = [&](const std::vector<gridfree::Vec2>& where,
                                               std::vector<gridfree::CrossFieldSample>& out) {
      if (failed || this->CheckAbort())
      {
        return false;
      }
      vtkNew<vtkPoints> batchPoints;
      batchPoints->SetDataTypeToDouble();
      for (const gridfree::Vec2& p : where)
      {
        batchPoints->InsertNextPoint(p.x(), p.y(), z0);
      }
      vtkNew<vtkPolyData> batch;
      batch->SetPoints(batchPoints);
      const double next = progress + 0.05 * (phaseEnd - progress);
      // ψ (two components) with its gradient and variance, and the distance
      // to the boundary, as numbers from the batch.
      gridfree::PointNumbers found;
      if (!solveNumbers(batch, this->SearchWalksPerPoint, progress, next, found))
      {
        failed = true;
        return false;
      }
      progress = next;
      this->LastNumberOfEstimates += static_cast<vtkIdType>(where.size());
      if (found.Size() != where.size() || found.Components != 2 || !found.HasGradient())
      {
        failed = true;
        return false;
      }
      out.resize(where.size());
      for (std::size_t i = 0; i < where.size(); ++i)
      {
        gridfree::CrossFieldSample& s = out[i];
        s.Psi = std::complex<double>(found.Value(i, 0), found.Value(i, 1));
        s.GradRe = gridfree::Vec2(found.Gradient(i, 0, 0), found.Gradient(i, 0, 1));
        s.GradIm = gridfree::Vec2(found.Gradient(i, 1, 0), found.Gradient(i, 1, 1));
        s.PsiVariance = found.ValueVariance(i, 0) + found.ValueVariance(i, 1);
        s.BoundaryDistance = found.Distance[i];
        s.Valid = Inside(segments, where[i]);
      }
      return true;
    };

    // Poincaré–Hopf: what the indices inside must add up to, from the
    // boundary's corners (when its lines form closed loops).
    std::vector<std::vector<gridfree::Vec2>> loops;
    const bool closedLoops = LoopsOf(segments, loops);
    bool ambiguous = false;
    const int boundarySum = closedLoops ? gridfree::BoundaryWinding(loops, &ambiguous) : 0;
    const bool checkable = closedLoops && !ambiguous;

    SearchParameters with;
    with.Winding = this->SearchMethod == WINDING;
    with.GridCells = this->SearchGridCells;
    with.Refinements = this->SearchRefinements;
    with.Seed = this->GetSeed();
    with.Seeds = this->NumberOfSeeds;
    with.MaximumSteps = this->MaximumSearchSteps;
    with.MergeRadius = this->MergeRadius;
    with.IndexRadius = this->IndexRadius;
    const SearchResult found =
      FindCrossFieldSingularities(evaluate, segments, bounds, diagonal, with, checkable, boundarySum);
    const std::vector<gridfree::Singularity>& singularities = found.Singularities;
    if (found.Statistics.Aborted)
    {
      if (!this->CheckAbort())
      {
        return 0; // the solver's error was reported
      }
      vtkWarningMacro(<< "Singularity search aborted: no singularities or separatrices.");
      return 1;
    }

    WriteSingularities(found, with.Winding, z0, singularityOutput);
    vtkFieldData* fd = singularityOutput->GetFieldData();

    // Poincaré–Hopf: the indices found against the boundary's.
    int indexSum = 0;
    for (const gridfree::Singularity& s : singularities)
    {
      indexSum += s.Index;
    }
    gridfree::AddFieldValue(fd, "IndexSum", indexSum);
    if (closedLoops)
    {
      gridfree::AddFieldValue(fd, "BoundaryIndexSum", boundarySum);
      if (ambiguous)
      {
        vtkWarningMacro(<< "The boundary turns by 45 degrees (or 135) at a corner, where psi "
                           "vanishes: a singularity sits on the boundary there, and the indices "
                           "inside need not add up to the boundary's.");
      }
      else if (indexSum != boundarySum)
      {
        vtkWarningMacro(<< "The singularities found have indices summing to " << indexSum
                        << " quarter turns, but the boundary requires " << boundarySum
                        << " (Poincare-Hopf): "
                        << (with.Winding
                               ? "some lie too close to the boundary even for a grid 8 times "
                                 "as fine, or in regions the noise leaves unresolved (see "
                                 "UnresolvedRegions): raise SearchGridCells or "
                                 "SearchWalksPerPoint."
                               : "the seed descent missed some: use SearchMethod WINDING, or "
                                 "raise NumberOfSeeds and SearchWalksPerPoint."));
      }
    }
    else
    {
      vtkWarningMacro(<< "The boundary's lines do not form closed loops: the singularities' "
                         "indices are not checked against it.");
    }

    if (this->TraceSeparatrices && !singularities.empty())
    {
      progress = 0.7;
      phaseEnd = 1.0;
      gridfree::SeparatrixSettings tracing;
      tracing.MinStep = 1e-4 * diagonal;
      tracing.MaxStep = this->SeparatrixStep * diagonal;
      tracing.StopDistance = 0.005 * diagonal;
      tracing.CaptureRadius = 0.02 * diagonal;
      tracing.MaxSteps = this->MaximumSeparatrixSteps;
      tracing.MaxLength = 10.0 * diagonal;
      gridfree::SeparatrixStatistics tracingStatistics;
      const std::vector<gridfree::Separatrix> curves =
        gridfree::TraceSeparatrices(evaluate, singularities, tracing, &tracingStatistics);
      if (failed && !this->CheckAbort())
      {
        return 0;
      }
      WriteSeparatrices(curves, z0, separatrixOutput);
      if (tracingStatistics.Aborted && this->CheckAbort())
      {
        vtkWarningMacro(<< "Separatrix tracing aborted: the curves end where they were.");
      }
    }
  }
  this->AddSummary(output);
  gridfree::AddFieldValue(
    output->GetFieldData(), "SearchEstimates", static_cast<double>(this->LastNumberOfEstimates));
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWalkOnSpheresCrossField::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SearchSingularities: " << this->SearchSingularities << "\n";
  os << indent << "TraceSeparatrices: " << this->TraceSeparatrices << "\n";
  os << indent << "SearchMethod: " << this->SearchMethod << "\n";
  os << indent << "SearchGridCells: " << this->SearchGridCells << "\n";
  os << indent << "SearchRefinements: " << this->SearchRefinements << "\n";
  os << indent << "NumberOfSeeds: " << this->NumberOfSeeds << "\n";
  os << indent << "SearchWalksPerPoint: " << this->SearchWalksPerPoint << "\n";
  os << indent << "MergeRadius: " << this->MergeRadius << "\n";
  os << indent << "IndexRadius: " << this->IndexRadius << "\n";
  os << indent << "SeparatrixStep: " << this->SeparatrixStep << "\n";
  os << indent << "MaximumSearchSteps: " << this->MaximumSearchSteps << "\n";
  os << indent << "MaximumSeparatrixSteps: " << this->MaximumSeparatrixSteps << "\n";
  os << indent << "LastNumberOfEstimates: " << this->LastNumberOfEstimates << "\n";
}
