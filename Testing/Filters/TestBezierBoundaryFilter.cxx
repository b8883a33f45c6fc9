// vtkWalkOnSpheresSolver on 2D boundaries of cubic Bézier curves (polylines
// marked in the cell array "BezierControlPoints"), and the dropping of
// degenerate boundary cells.
//
// * The filter against the estimator core on a hand-built BezierBoundaryGeometry
//   with the documented value rule, same seed: identical numbers (point and
//   cell values, several components, the biharmonic pair g, h). The inner
//   handles carry absurd values, so any use of them would show.
// * Closed forms: straight curves reproduce a square exactly, so boundary data
//   from a function that is linear along each edge is exactly harmonic inside.
// * The converted boundary's closest points against dense sampling.
// * Error messages and the degenerate-cell warning.
#include "vtkWalkOnSpheresSolver.h"

#include "GridFreeBoundaryConversion.h"
#include "VtkMessageCatcher.h"

#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/geometry/BezierCurves.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace
{
using gridfree::Vec2;

// The classic 4-curve circle: handles at kappa along the tangents.
constexpr double Kappa = 0.5522847498;

// Value given to the inner handles: they are not on the curve and must never
// be used, so any leak of it into a result is obvious.
constexpr double HandleValue = 1e6;

struct Polyline
{
  std::vector<vtkIdType> Ids;
  int Bezier; // the "BezierControlPoints" value
};

// A 2D boundary in z = 0 from points and polylines; `flags` adds the cell
// array "BezierControlPoints".
vtkSmartPointer<vtkPolyData> MakeBoundary(
  const std::vector<Vec2>& points, const std::vector<Polyline>& lines, bool flags = true)
{
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble(); // the control points exactly as the core tests build them
  for (const Vec2& p : points)
  {
    pts->InsertNextPoint(p[0], p[1], 0.0);
  }
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkIntArray> bezier;
  bezier->SetName("BezierControlPoints");
  for (const Polyline& line : lines)
  {
    cells->InsertNextCell(static_cast<vtkIdType>(line.Ids.size()), line.Ids.data());
    bezier->InsertNextValue(line.Bezier);
  }
  auto boundary = vtkSmartPointer<vtkPolyData>::New();
  boundary->SetPoints(pts);
  boundary->SetLines(cells);
  if (flags)
  {
    boundary->GetCellData()->AddArray(bezier);
  }
  return boundary;
}

// Point values: f at the points listed in `onCurve`, HandleValue elsewhere.
void AddPointValues(vtkPolyData* boundary, const char* name, int components,
  const std::function<void(const double*, double*)>& f, const std::vector<bool>& onCurve)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(boundary->GetNumberOfPoints());
  std::vector<double> tuple(components);
  for (vtkIdType i = 0; i < boundary->GetNumberOfPoints(); ++i)
  {
    if (onCurve[i])
    {
      f(boundary->GetPoint(i), tuple.data());
    }
    else
    {
      std::fill(tuple.begin(), tuple.end(), HandleValue);
    }
    a->SetTuple(i, tuple.data());
  }
  boundary->GetPointData()->AddArray(a);
}

// The unit circle: 12 control points, curve i = points 3i .. 3i + 3 (mod 12).
std::vector<Vec2> CirclePoints()
{
  const double k = Kappa;
  return { Vec2(1, 0), Vec2(1, k), Vec2(k, 1), Vec2(0, 1), Vec2(-k, 1), Vec2(-1, k),
    Vec2(-1, 0), Vec2(-1, -k), Vec2(-k, -1), Vec2(0, -1), Vec2(k, -1), Vec2(1, -k) };
}

std::vector<bool> CircleOnCurve()
{
  std::vector<bool> on(12, false);
  for (int i = 0; i < 12; i += 3)
  {
    on[i] = true;
  }
  return on;
}

std::vector<gridfree::CubicBezier> CircleCurves()
{
  const std::vector<Vec2> p = CirclePoints();
  std::vector<gridfree::CubicBezier> curves(4);
  for (int i = 0; i < 4; ++i)
  {
    for (int k = 0; k < 4; ++k)
    {
      curves[i].P[k] = p[(3 * i + k) % 12];
    }
  }
  return curves;
}

// The square [-1, 1]² as four straight cubic curves (handles at 1/3, 2/3 of
// each edge): 12 control points, curve i = points 3i .. 3i + 3 (mod 12).
std::vector<Vec2> StraightSquarePoints()
{
  const Vec2 corners[4] = { Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1) };
  std::vector<Vec2> points;
  for (int i = 0; i < 4; ++i)
  {
    const Vec2& a = corners[i];
    const Vec2& b = corners[(i + 1) % 4];
    points.push_back(a);
    points.push_back((2.0 * a + b) / 3.0);
    points.push_back((a + 2.0 * b) / 3.0);
  }
  return points;
}

// Harmonic, and linear along every edge of an axis-aligned square: boundary
// data interpolated linearly between the corners is exact.
double Bilinear(const double* p)
{
  return p[0] * p[1] + 0.3 * p[0] + 0.2;
}

vtkSmartPointer<vtkPolyData> ProbeInBox(int count, double half, unsigned seed)
{
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> u(-half, half);
  vtkNew<vtkPoints> points;
  for (int i = 0; i < count; ++i)
  {
    points->InsertNextPoint(u(engine), u(engine), 0.0);
  }
  auto probe = vtkSmartPointer<vtkPolyData>::New();
  probe->SetPoints(points);
  return probe;
}

vtkSmartPointer<vtkPolyData> ProbeInDisk(int count, double radius, unsigned seed)
{
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  vtkNew<vtkPoints> points;
  while (points->GetNumberOfPoints() < count)
  {
    const double x = u(engine), y = u(engine);
    if (x * x + y * y <= 1.0)
    {
      points->InsertNextPoint(radius * x, radius * y, 0.0);
    }
  }
  auto probe = vtkSmartPointer<vtkPolyData>::New();
  probe->SetPoints(points);
  return probe;
}

struct FilterRun
{
  vtkSmartPointer<vtkDataSet> Output;
  std::string Errors, Warnings;
  int Dimension = 0;
  double Epsilon = 0.0;
  int MaxSteps = 0;
  int Equation = 0;
  int Biharmonic = 0;
  int NestedWalks = 0;
  bool NearBoundarySplitting = false;
  std::uint64_t Seed = 0;
  int Walks = 0;

  vtkDataArray* Array(const std::string& name) const
  {
    return this->Output ? this->Output->GetPointData()->GetArray(name.c_str()) : nullptr;
  }
};

FilterRun RunFilter(vtkPolyData* boundary, vtkPolyData* probe,
  const std::function<void(vtkWalkOnSpheresSolver*)>& configure)
{
  vtkNew<vtkWalkOnSpheresSolver> solver;
  vtkNew<MessageCatcher> catcher;
  solver->AddObserver(vtkCommand::WarningEvent, catcher);
  solver->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  solver->SetBoundaryData(boundary);
  solver->SetProbeData(probe);
  solver->SetWalksPerPoint(64);
  solver->SetSeed(11);
  configure(solver);
  solver->Update();
  FilterRun run;
  run.Output = vtkDataSet::SafeDownCast(solver->GetOutputDataObject(0));
  run.Errors = catcher->Errors;
  run.Warnings = catcher->Warnings;
  run.Dimension = solver->GetLastDimension();
  run.Epsilon = solver->GetEpsilon();
  run.MaxSteps = solver->GetMaxSteps();
  run.Equation = solver->GetEquation();
  run.Biharmonic = solver->GetBiharmonicStrategy();
  run.NestedWalks = solver->GetNestedWalks();
  run.NearBoundarySplitting = solver->GetNearBoundarySplitting();
  run.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(solver->GetSeed()));
  run.Walks = solver->GetWalksPerPoint();
  return run;
}

// The filter's plain estimator (control variates off) run on a hand-built
// core boundary with the filter's settings: means and variances of the mean,
// `components` numbers per probe point.
void RunCore(const gridfree::Boundary<2>& boundary, const FilterRun& filter, vtkPolyData* probe,
  int components, std::vector<double>& mean, std::vector<double>& variance)
{
  gridfree::WalkSettings settings;
  settings.Epsilon = filter.Epsilon * boundary.Diagonal();
  settings.MaxSteps = filter.MaxSteps;
  settings.Problem = static_cast<gridfree::Equation>(filter.Equation);
  settings.Biharmonic = static_cast<gridfree::BiharmonicStrategy>(filter.Biharmonic);
  settings.NestedWalks = filter.NestedWalks;
  settings.NearBoundarySplitting = filter.NearBoundarySplitting;
  gridfree::WalkOnSpheresEstimator<2> estimator(boundary, settings);
  ASSERT_EQ(estimator.OutputComponents(), components);
  for (vtkIdType i = 0; i < probe->GetNumberOfPoints(); ++i)
  {
    double p[3];
    probe->GetPoint(i, p);
    gridfree::RunningStatistics stats(components);
    gridfree::WalkCounters counters;
    estimator.EstimatePoint(p, filter.Seed, 0, filter.Walks, stats, counters);
    for (int c = 0; c < components; ++c)
    {
      mean.push_back(stats.GetMean(c));
      variance.push_back(stats.VarianceOfMean(c));
    }
  }
}

// The documented rule, written independently of the module: point values
// interpolate linearly in t between a curve's end tuples, with the weights
// (1 − t, t) the geometry returns; cell values are the curve's tuple.
class ReferenceValues final : public gridfree::BoundaryValueFunction<2>
{
public:
  // Point values: per curve, its P0 tuple and its P3 tuple.
  ReferenceValues(std::vector<std::vector<double>> start, std::vector<std::vector<double>> end)
    : Start(std::move(start))
    , End(std::move(end))
    , PerCurve(false)
  {
  }
  // Cell values: per curve, one tuple.
  explicit ReferenceValues(std::vector<std::vector<double>> perCurve)
    : Start(std::move(perCurve))
    , PerCurve(true)
  {
  }
  int Components() const override { return static_cast<int>(this->Start.front().size()); }
  void Evaluate(const gridfree::ClosestPointResult<2>& hit, double* out) const override
  {
    const std::vector<double>& a = this->Start.at(static_cast<std::size_t>(hit.primitive));
    for (std::size_t c = 0; c < a.size(); ++c)
    {
      out[c] = this->PerCurve ? a[c]
                              : hit.barycentric[0] * a[c] +
          hit.barycentric[1] * this->End[static_cast<std::size_t>(hit.primitive)][c];
    }
  }

private:
  std::vector<std::vector<double>> Start, End;
  bool PerCurve;
};

// Identical numbers from the filter and the core, for every point and
// component of `names` (the arrays in core component order).
void ExpectIdentical(const FilterRun& run, const std::vector<std::string>& names, int nc,
  const std::vector<double>& mean, const std::vector<double>& variance)
{
  const int components = static_cast<int>(names.size()) * nc;
  const vtkIdType n = run.Output->GetNumberOfPoints();
  ASSERT_EQ(mean.size(), static_cast<std::size_t>(n * components));
  for (std::size_t a = 0; a < names.size(); ++a)
  {
    vtkDataArray* m = run.Array(names[a]);
    vtkDataArray* v = run.Array(names[a] + "_Variance");
    ASSERT_NE(m, nullptr) << names[a];
    ASSERT_NE(v, nullptr) << names[a];
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < nc; ++c)
      {
        const std::size_t k = static_cast<std::size_t>(i * components + a * nc + c);
        ASSERT_EQ(m->GetComponent(i, c), mean[k]) << names[a] << " point " << i << " c " << c;
        ASSERT_EQ(v->GetComponent(i, c), variance[k]) << names[a] << " point " << i;
      }
    }
  }
}

// Copies of one array, for comparing runs.
std::vector<double> Values(const FilterRun& run, const char* name)
{
  std::vector<double> out;
  vtkDataArray* a = run.Array(name);
  if (!a)
  {
    ADD_FAILURE() << "no array " << name;
    return out;
  }
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
    {
      out.push_back(a->GetComponent(i, c));
    }
  }
  return out;
}
} // namespace

TEST(BezierBoundaryFilter, CircleOfCurvesMatchesTheCore)
{
  std::vector<vtkIdType> ids = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0 };
  auto boundary = MakeBoundary(CirclePoints(), { { ids, 1 } });
  auto g = [](const double* p, double* out) { out[0] = p[0] + 0.5 * p[1]; };
  AddPointValues(boundary, "T", 1, g, CircleOnCurve());
  auto probe = ProbeInDisk(12, 0.8, 3);
  const FilterRun run = RunFilter(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    s->ControlVariatesOff();
  });
  EXPECT_EQ(run.Errors, "");
  EXPECT_EQ(run.Warnings, "");
  EXPECT_EQ(run.Dimension, 2);

  std::vector<std::vector<double>> start, end;
  const std::vector<Vec2> p = CirclePoints();
  for (int i = 0; i < 4; ++i)
  {
    const Vec2& a = p[3 * i];
    const Vec2& b = p[(3 * i + 3) % 12];
    start.push_back({ a[0] + 0.5 * a[1] });
    end.push_back({ b[0] + 0.5 * b[1] });
  }
  gridfree::Boundary<2> core;
  core.SetGeometry(std::make_shared<gridfree::BezierBoundaryGeometry>(CircleCurves()),
    std::make_shared<ReferenceValues>(start, end));
  std::vector<double> mean, variance;
  RunCore(core, run, probe, 1, mean, variance);
  ExpectIdentical(run, { "T" }, 1, mean, variance);
  // Maximum principle: the end values lie in [-1.5, 1.5]; a handle's value
  // anywhere in the data would break it.
  for (double v : mean)
  {
    EXPECT_LE(std::abs(v), 1.5);
  }
}

TEST(BezierBoundaryFilter, CellValuesWithTwoComponentsMatchTheCore)
{
  // Upper half and lower half as two polylines of two curves each.
  auto boundary = MakeBoundary(
    CirclePoints(), { { { 0, 1, 2, 3, 4, 5, 6 }, 1 }, { { 6, 7, 8, 9, 10, 11, 0 }, 7 } });
  vtkNew<vtkDoubleArray> v;
  v->SetName("V");
  v->SetNumberOfComponents(2);
  v->InsertNextTuple2(1.0, -2.0);
  v->InsertNextTuple2(3.0, 5.0);
  boundary->GetCellData()->AddArray(v);
  auto probe = ProbeInDisk(10, 0.8, 4);
  const FilterRun run = RunFilter(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "V");
    s->ControlVariatesOff();
  });
  EXPECT_EQ(run.Errors, "");
  EXPECT_EQ(run.Warnings, "");

  gridfree::Boundary<2> core;
  core.SetGeometry(std::make_shared<gridfree::BezierBoundaryGeometry>(CircleCurves()),
    std::make_shared<ReferenceValues>(std::vector<std::vector<double>>{
      { 1.0, -2.0 }, { 1.0, -2.0 }, { 3.0, 5.0 }, { 3.0, 5.0 } }));
  std::vector<double> mean, variance;
  RunCore(core, run, probe, 2, mean, variance);
  ExpectIdentical(run, { "V" }, 2, mean, variance);
}

TEST(BezierBoundaryFilter, BiharmonicTakesBothArraysFromTheEndPoints)
{
  std::vector<vtkIdType> ids = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0 };
  auto boundary = MakeBoundary(CirclePoints(), { { ids, 1 } });
  auto g = [](const double* p, double* out) { out[0] = p[0] * p[0] + 0.25 * p[1]; };
  auto h = [](const double* p, double* out) { out[0] = 2.0 + p[0]; };
  AddPointValues(boundary, "G", 1, g, CircleOnCurve());
  AddPointValues(boundary, "H", 1, h, CircleOnCurve());
  auto probe = ProbeInDisk(8, 0.7, 5);
  const FilterRun run = RunFilter(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "G");
    s->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "H");
    s->SetEquationToBiharmonic();
    s->ControlVariatesOff();
  });
  EXPECT_EQ(run.Errors, "");

  std::vector<std::vector<double>> start, end;
  const std::vector<Vec2> p = CirclePoints();
  for (int i = 0; i < 4; ++i)
  {
    const double a[2] = { p[3 * i][0], p[3 * i][1] };
    const double b[2] = { p[(3 * i + 3) % 12][0], p[(3 * i + 3) % 12][1] };
    double ga, ha, gb, hb;
    g(a, &ga);
    h(a, &ha);
    g(b, &gb);
    h(b, &hb);
    start.push_back({ ga, ha });
    end.push_back({ gb, hb });
  }
  gridfree::Boundary<2> core;
  core.SetGeometry(std::make_shared<gridfree::BezierBoundaryGeometry>(CircleCurves()),
    std::make_shared<ReferenceValues>(start, end));
  std::vector<double> mean, variance;
  RunCore(core, run, probe, 2, mean, variance);
  ExpectIdentical(run, { "G", "G_Laplacian" }, 1, mean, variance);
}

TEST(BezierBoundaryFilter, StraightCurvesReproduceASquareExactly)
{
  std::vector<vtkIdType> ids = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0 };
  auto boundary = MakeBoundary(StraightSquarePoints(), { { ids, 1 } });
  AddPointValues(
    boundary, "T", 1, [](const double* p, double* out) { out[0] = Bilinear(p); },
    CircleOnCurve());
  auto probe = ProbeInBox(60, 0.9, 6);
  const FilterRun run = RunFilter(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    s->SetWalksPerPoint(256);
  });
  EXPECT_EQ(run.Errors, "");
  EXPECT_EQ(run.Warnings, "");
  vtkDataArray* t = run.Array("T");
  vtkDataArray* var = run.Array("T_Variance");
  ASSERT_NE(t, nullptr);
  ASSERT_NE(var, nullptr);
  double sumZ2 = 0.0;
  for (vtkIdType i = 0; i < probe->GetNumberOfPoints(); ++i)
  {
    const double exact = Bilinear(probe->GetPoint(i));
    const double z = (t->GetTuple1(i) - exact) / std::sqrt(var->GetTuple1(i));
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
  }
  const double meanZ2 = sumZ2 / probe->GetNumberOfPoints();
  EXPECT_GT(meanZ2, 0.5);
  EXPECT_LT(meanZ2, 1.6);
}

TEST(BezierBoundaryFilter, MixedPolylinesAndCurvesAgreeWithAPolylineSquare)
{
  // Corners 0..3; bottom and right edges plain polylines (the right one with
  // a middle point), top and left edges straight Bézier curves.
  const std::vector<Vec2> points = { Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1),
    Vec2(1, 0), Vec2(1.0 / 3.0, 1), Vec2(-1.0 / 3.0, 1), Vec2(-1, 1.0 / 3.0),
    Vec2(-1, -1.0 / 3.0) };
  std::vector<bool> onCurve = { true, true, true, true, true, false, false, false, false };
  auto mixed = MakeBoundary(points,
    { { { 0, 1 }, 0 }, { { 1, 4, 2 }, 0 }, { { 2, 5, 6, 3 }, 1 }, { { 3, 7, 8, 0 }, 1 } });
  auto plain = MakeBoundary(
    { Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1) }, { { { 0, 1, 2, 3, 0 }, 0 } }, false);
  auto f = [](const double* p, double* out) { out[0] = Bilinear(p); };
  AddPointValues(mixed, "T", 1, f, onCurve);
  AddPointValues(plain, "T", 1, f, std::vector<bool>(4, true));
  auto probe = ProbeInBox(60, 0.9, 7);
  auto configure = [](int seed) {
    return [seed](vtkWalkOnSpheresSolver* s) {
      s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
      s->SetWalksPerPoint(256);
      s->SetSeed(seed); // independent walks
    };
  };
  const FilterRun a = RunFilter(mixed, probe, configure(21));
  const FilterRun b = RunFilter(plain, probe, configure(22));
  EXPECT_EQ(a.Errors, "");
  EXPECT_EQ(b.Errors, "");
  const std::vector<double> ma = Values(a, "T"), va = Values(a, "T_Variance");
  const std::vector<double> mb = Values(b, "T"), vb = Values(b, "T_Variance");
  ASSERT_EQ(ma.size(), mb.size());
  ASSERT_EQ(ma.size(), static_cast<std::size_t>(probe->GetNumberOfPoints()));
  double sumZ2 = 0.0;
  for (std::size_t i = 0; i < ma.size(); ++i)
  {
    const double z = (ma[i] - mb[i]) / std::sqrt(va[i] + vb[i]);
    EXPECT_LT(std::abs(z), 5.0) << "point " << i;
    sumZ2 += z * z;
    // And each against the closed form.
    const double exact = Bilinear(probe->GetPoint(static_cast<vtkIdType>(i)));
    EXPECT_LT(std::abs(ma[i] - exact), 5.0 * std::sqrt(va[i])) << "point " << i;
  }
  const double meanZ2 = sumZ2 / static_cast<double>(ma.size());
  EXPECT_GT(meanZ2, 0.5);
  EXPECT_LT(meanZ2, 1.6);
}

TEST(BezierBoundaryFilter, ClosestPointsMatchDenseSampling)
{
  // An S-shaped piecewise curve (two curves, a loop-free wiggle), a plain
  // straight polyline closing it, with point values.
  const std::vector<Vec2> points = { Vec2(0, 0), Vec2(0.8, 1.4), Vec2(1.2, -1.0), Vec2(2, 0.3),
    Vec2(2.8, 1.6), Vec2(3.5, -0.9), Vec2(4, 0.2), Vec2(2, -2) };
  auto boundary = MakeBoundary(
    points, { { { 0, 1, 2, 3, 4, 5, 6 }, 1 }, { { 6, 7, 0 }, 0 } });
  std::vector<double> pointValue = { 1.0, HandleValue, HandleValue, 2.0, HandleValue,
    HandleValue, -3.0, 0.5 };
  vtkNew<vtkDoubleArray> t;
  t->SetName("T");
  for (double v : pointValue)
  {
    t->InsertNextValue(v);
  }
  boundary->GetPointData()->AddArray(t);

  gridfree::Boundary<2> converted;
  gridfree::BoundaryConversionReport report;
  std::string reason;
  ASSERT_TRUE(gridfree::ConvertBoundary<2>(boundary, t, false, converted, report, reason))
    << reason;
  EXPECT_FALSE(converted.IsMesh());
  ASSERT_EQ(converted.NumberOfPrimitives(), 4u);
  EXPECT_EQ(report.DegenerateCells, 0);

  // The expected curves in conversion order (cell order): two Bézier curves,
  // then the two straight segments 6→7 and 7→0.
  std::vector<gridfree::CubicBezier> curves(4);
  for (int i = 0; i < 2; ++i)
  {
    for (int k = 0; k < 4; ++k)
    {
      curves[i].P[k] = points[3 * i + k];
    }
  }
  const int segmentEnds[2][2] = { { 6, 7 }, { 7, 0 } };
  for (int s = 0; s < 2; ++s)
  {
    const Vec2 a = points[segmentEnds[s][0]], b = points[segmentEnds[s][1]];
    curves[2 + s].P[0] = a;
    curves[2 + s].P[1] = (2.0 * a + b) / 3.0;
    curves[2 + s].P[2] = (a + 2.0 * b) / 3.0;
    curves[2 + s].P[3] = b;
  }
  const double endValue[4][2] = { { 1.0, 2.0 }, { 2.0, -3.0 }, { -3.0, 0.5 }, { 0.5, 1.0 } };

  // Dense samples of every curve.
  const int samples = 200000;
  std::vector<Vec2> dense;
  for (const auto& c : curves)
  {
    for (int j = 0; j <= samples; ++j)
    {
      dense.push_back(c.Evaluate(static_cast<double>(j) / samples));
    }
  }
  std::mt19937_64 engine(9);
  std::uniform_real_distribution<double> ux(-0.5, 4.5), uy(-2.5, 2.0);
  for (int q = 0; q < 200; ++q)
  {
    const Vec2 x(ux(engine), uy(engine));
    double best = std::numeric_limits<double>::infinity();
    for (const Vec2& s : dense)
    {
      best = std::min(best, (s - x).norm());
    }
    const gridfree::ClosestPointResult<2> hit = converted.ClosestPoint(x);
    // Sampling only ever overestimates; 2e5 samples per curve bound the
    // overestimate far below 1e-4 (arc length steps < 3e-5).
    EXPECT_LE(hit.distance, best + 1e-12) << "query " << q;
    EXPECT_GE(hit.distance, best - 1e-4) << "query " << q;
    EXPECT_DOUBLE_EQ(converted.Distance(x), hit.distance);
    ASSERT_GE(hit.primitive, 0);
    ASSERT_LT(hit.primitive, 4);
    const double tt = hit.barycentric[1];
    EXPECT_NEAR(hit.barycentric[0], 1.0 - tt, 1e-15);
    // The hit lies on the expected curve at its t, at the reported distance.
    EXPECT_LT((hit.point - curves[hit.primitive].Evaluate(tt)).norm(), 1e-12) << "query " << q;
    EXPECT_NEAR((hit.point - x).norm(), hit.distance, 1e-12);
    // On a straight piece, t is the projection parameter: linear along it.
    if (hit.primitive >= 2 && tt > 1e-6 && tt < 1 - 1e-6)
    {
      const Vec2 a = curves[hit.primitive].P[0], b = curves[hit.primitive].P[3];
      EXPECT_NEAR(tt, (x - a).dot(b - a) / (b - a).squaredNorm(), 1e-9) << "query " << q;
    }
    // The value: linear in t between the curve's end values.
    double g;
    converted.Evaluate(hit, &g);
    const double* e = endValue[hit.primitive];
    EXPECT_NEAR(g, (1.0 - tt) * e[0] + tt * e[1], 1e-12) << "query " << q;
  }
}

TEST(BezierBoundaryFilter, WrongControlPointCountIsAnError)
{
  auto probe = ProbeInBox(4, 0.5, 8);
  auto errorsOf = [&](vtkPolyData* boundary) {
    return RunFilter(boundary, probe, [](vtkWalkOnSpheresSolver* s) {
      s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    }).Errors;
  };
  const std::vector<Vec2> points = { Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1),
    Vec2(0, 1.5) };
  const std::vector<bool> all(5, true);
  auto f = [](const double* p, double* out) { out[0] = p[0]; };
  {
    // A plain polyline first, so the bad cell is cell 1, with 5 points.
    auto boundary =
      MakeBoundary(points, { { { 0, 1 }, 0 }, { { 1, 2, 4, 3, 0 }, 1 } });
    AddPointValues(boundary, "T", 1, f, all);
    const std::string errors = errorsOf(boundary);
    EXPECT_NE(errors.find("cell 1 is marked as a Bézier curve"), std::string::npos) << errors;
    EXPECT_NE(errors.find("has 5 points"), std::string::npos) << errors;
    EXPECT_NE(errors.find("3k + 1"), std::string::npos) << errors;
  }
  {
    // The same polyline unmarked is fine.
    auto boundary =
      MakeBoundary(points, { { { 0, 1 }, 0 }, { { 1, 2, 4, 3, 0 }, 0 } });
    AddPointValues(boundary, "T", 1, f, all);
    EXPECT_EQ(errorsOf(boundary), "");
  }
  {
    // The marker as point data is an error: it marks whole polylines.
    auto boundary = MakeBoundary(points, { { { 0, 1, 2, 3 }, 1 } }, false);
    vtkNew<vtkIntArray> marker;
    marker->SetName("BezierControlPoints");
    marker->SetNumberOfTuples(5);
    marker->Fill(1);
    boundary->GetPointData()->AddArray(marker);
    AddPointValues(boundary, "T", 1, f, all);
    const std::string errors = errorsOf(boundary);
    EXPECT_NE(errors.find("must be cell data"), std::string::npos) << errors;
  }
}

TEST(BezierBoundaryFilter, DegenerateCellsAreDroppedAndCounted)
{
  // 3D: a sphere, then the same sphere with a zero-area triangle of three
  // collinear new points and a triangle with a repeated point.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(24);
  sphere->Update();
  auto clean = vtkSmartPointer<vtkPolyData>::New();
  clean->DeepCopy(sphere->GetOutput());
  auto addT = [](vtkPolyData* mesh) {
    vtkNew<vtkDoubleArray> t;
    t->SetName("T");
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    {
      const double* p = mesh->GetPoint(i);
      t->InsertNextValue(p[0] * p[0] - p[1] * p[1] + p[2]);
    }
    mesh->GetPointData()->AddArray(t);
  };
  auto dirty = vtkSmartPointer<vtkPolyData>::New();
  dirty->DeepCopy(clean);
  {
    const vtkIdType a = dirty->GetPoints()->InsertNextPoint(0.1, 0.1, 0.1);
    const vtkIdType b = dirty->GetPoints()->InsertNextPoint(0.2, 0.2, 0.2);
    const vtkIdType c = dirty->GetPoints()->InsertNextPoint(0.4, 0.4, 0.4);
    const vtkIdType collinear[3] = { a, b, c };
    const vtkIdType repeated[3] = { 0, 5, 5 };
    dirty->GetPolys()->InsertNextCell(3, collinear);
    dirty->GetPolys()->InsertNextCell(3, repeated);
  }
  addT(clean);
  addT(dirty);
  auto probe3 = vtkSmartPointer<vtkPolyData>::New();
  {
    vtkNew<vtkPoints> p;
    p->InsertNextPoint(0.1, 0.2, 0.3);
    p->InsertNextPoint(-0.4, 0.1, 0.0);
    p->InsertNextPoint(0.05, -0.3, 0.5);
    probe3->SetPoints(p);
  }
  auto pointValues = [](vtkWalkOnSpheresSolver* s) {
    s->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "T");
    s->SetWalksPerPoint(32);
  };
  {
    const FilterRun a = RunFilter(clean, probe3, pointValues);
    const FilterRun b = RunFilter(dirty, probe3, pointValues);
    EXPECT_EQ(a.Errors, "");
    EXPECT_EQ(b.Errors, "");
    EXPECT_EQ(a.Warnings, "");
    EXPECT_NE(b.Warnings.find("Ignored 2 degenerate boundary triangles"), std::string::npos)
      << b.Warnings;
    EXPECT_EQ(Values(a, "T"), Values(b, "T"));
    EXPECT_EQ(Values(a, "T_Variance"), Values(b, "T_Variance"));
  }

  // 2D mesh: a polygon circle, then with a repeated point inside the polyline
  // and a separate segment whose two points coincide.
  const int n = 64;
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i)
  {
    ring.emplace_back(std::cos(2.0 * M_PI * i / n), std::sin(2.0 * M_PI * i / n));
  }
  std::vector<vtkIdType> loop;
  for (int i = 0; i <= n; ++i)
  {
    loop.push_back(i % n);
  }
  std::vector<vtkIdType> loopWithRepeat = loop;
  loopWithRepeat.insert(loopWithRepeat.begin() + 10, loopWithRepeat[10]);
  std::vector<Vec2> ringPlus = ring;
  ringPlus.emplace_back(0.3, 0.2);
  ringPlus.emplace_back(0.3, 0.2);
  auto f = [](const double* p, double* out) { out[0] = p[0] * p[1] + p[0]; };
  auto clean2 = MakeBoundary(ring, { { loop, 0 } }, false);
  auto dirty2 = MakeBoundary(ringPlus, { { loopWithRepeat, 0 }, { { n, n + 1 }, 0 } }, false);
  AddPointValues(clean2, "T", 1, f, std::vector<bool>(n, true));
  AddPointValues(dirty2, "T", 1, f, std::vector<bool>(n + 2, true));
  auto probe2 = ProbeInDisk(4, 0.8, 10);
  {
    const FilterRun a = RunFilter(clean2, probe2, pointValues);
    const FilterRun b = RunFilter(dirty2, probe2, pointValues);
    EXPECT_EQ(a.Errors, "");
    EXPECT_EQ(b.Errors, "");
    EXPECT_EQ(a.Warnings, "");
    EXPECT_NE(b.Warnings.find("Ignored 2 degenerate boundary segments"), std::string::npos)
      << b.Warnings;
    EXPECT_EQ(Values(a, "T"), Values(b, "T"));
    EXPECT_EQ(Values(a, "T_Variance"), Values(b, "T_Variance"));
  }

  // 2D Bézier: the circle, then with a point-like curve (four equal control
  // points) and a zero-length straight segment.
  {
    std::vector<vtkIdType> ids = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0 };
    std::vector<Vec2> plus = CirclePoints();
    for (int k = 0; k < 4; ++k)
    {
      plus.emplace_back(0.5, -0.5);
    }
    auto cleanB = MakeBoundary(CirclePoints(), { { ids, 1 } });
    auto dirtyB = MakeBoundary(plus, { { ids, 1 }, { { 12, 13, 14, 15 }, 1 }, { { 12, 13 }, 0 } });
    std::vector<bool> on = CircleOnCurve();
    AddPointValues(cleanB, "T", 1, f, on);
    on.insert(on.end(), { true, true, true, true });
    AddPointValues(dirtyB, "T", 1, f, on);
    const FilterRun a = RunFilter(cleanB, probe2, pointValues);
    const FilterRun b = RunFilter(dirtyB, probe2, pointValues);
    EXPECT_EQ(a.Errors, "");
    EXPECT_EQ(b.Errors, "");
    EXPECT_NE(b.Warnings.find("Ignored 2 degenerate boundary segments or Bézier curves"),
      std::string::npos)
      << b.Warnings;
    EXPECT_EQ(Values(a, "T"), Values(b, "T"));
    EXPECT_EQ(Values(a, "T_Variance"), Values(b, "T_Variance"));
  }

  // Nothing but degenerate cells: the usual error, with the count.
  {
    auto only = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> p;
    p->InsertNextPoint(0, 0, 0);
    p->InsertNextPoint(1, 1, 1);
    p->InsertNextPoint(2, 2, 2);
    only->SetPoints(p);
    vtkNew<vtkCellArray> polys;
    const vtkIdType tri[3] = { 0, 1, 2 };
    polys->InsertNextCell(3, tri);
    only->SetPolys(polys);
    addT(only);
    const FilterRun r = RunFilter(only, probe3, pointValues);
    EXPECT_NE(r.Errors.find("no triangles (1 degenerate"), std::string::npos) << r.Errors;
  }
}
