// Statistical tests of gridfree/estimators/VaryingCoefficientWalk.h against
// manufactured solutions of ∇·(α∇u) − σu = f on three shapes (a ball, a 2D U
// and a 3D L, both nonconvex): values and gradients within 5 standard errors
// at every point and mean z² in [0.7, 1.4]; coefficients that make σ′
// negative (a bump of α), large (a steep step of α, a tenfold contrast) and
// an absorption σ; a wrong transform (Δα dropped) is caught; a point's
// numbers do not depend on the thread count.
#include <gridfree/coefficients/ImageCoefficients.h>
#include <gridfree/estimators/VaryingCoefficientWalk.h>
#include <gridfree/problem/Problem.h>
#include "BlockShapes.h"
#include "EstimatorChecks.h"
#include "ManufacturedCoefficients.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
template <int DIM>
Boundary<DIM> ExactBoundary(const SimplexMesh<DIM>& mesh, const SmoothFunction<DIM>& u)
{
  Boundary<DIM> boundary;
  auto f = u.Value;
  boundary.SetMesh(mesh.Vertices, mesh.Simplices,
    std::make_shared<CallableBoundaryValues<DIM>>(
      [f](const Vec<DIM>& p, std::int64_t, double* out) { *out = f(p); }, 1));
  return boundary;
}

// Random points of a union of unit cells at least `margin` inside it.
template <int DIM>
std::vector<Vec<DIM>> PointsInCells(
  const std::vector<Cell<DIM>>& cells, int count, double margin, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const SimplexMesh<DIM> mesh = MakeBlockShape<DIM>(cells, 1);
  Boundary<DIM> shape;
  shape.Set(mesh.Vertices, mesh.Simplices, ValueAssociation::Points, 1,
    std::vector<double>(mesh.Vertices.size(), 0.0));
  std::vector<Vec<DIM>> points;
  while (static_cast<int>(points.size()) < count)
  {
    const Cell<DIM>& c = cells[pick(rng)];
    Vec<DIM> p;
    for (int i = 0; i < DIM; ++i)
    {
      p[i] = c[i] + unit(rng);
    }
    if (shape.Distance(p) >= margin)
    {
      points.push_back(p);
    }
  }
  return points;
}

struct VaryingResult
{
  Calibration Value;
  Calibration Gradient;
};

// The z-scores of checks pooled into one calibration.
Calibration Pooled(const std::vector<Calibration>& parts)
{
  Calibration pooled;
  for (const Calibration& c : parts)
  {
    pooled.MeanZ2 += c.MeanZ2 * c.Points;
    pooled.MaxAbsZ = std::max(pooled.MaxAbsZ, c.MaxAbsZ);
    pooled.Points += c.Points;
  }
  pooled.MeanZ2 /= pooled.Points;
  return pooled;
}

// The bound grid with the source's range replaced by a wrong one: [0, 0],
// with 1 for the largest |f′| (the walk then samples the source on a
// thirty-second of its steps and counts it 32 times).
template <int DIM>
class SourceRangeMissed final : public ScreeningMajorant<DIM>
{
public:
  explicit SourceRangeMissed(const ScreeningMajorant<DIM>& inner)
    : Inner(inner)
  {
  }
  BallScreening ForBall(const Vec<DIM>& center, double radius) const override
  {
    BallScreening s = this->Inner.ForBall(center, radius);
    s.SourceLowest = s.SourceHighest = 0.0;
    s.SourceScale = 1.0;
    return s;
  }

private:
  const ScreeningMajorant<DIM>& Inner;
};

// Estimates u and ∇u at `points` and compares them with the case's exact u
// (the source's range missed on purpose with `missSourceRange`), with ε
// and near-boundary splitting as given.
template <int DIM>
VaryingResult CalibrateVarying(const SimplexMesh<DIM>& mesh, const ManufacturedCase<DIM>& with,
  const CoefficientField<DIM>& field, const std::vector<Vec<DIM>>& points, int walks,
  int threads = 2, bool missSourceRange = false, double epsilon = 1e-4, bool splitting = false)
{
  const Boundary<DIM> boundary = ExactBoundary<DIM>(mesh, with.U);
  typename ScreeningBoundGrid<DIM>::Settings grid;
  grid.Cells = 16;
  const ScreeningBoundGrid<DIM> bounds(field, boundary.BoundsMin(), boundary.BoundsMax(), grid);
  const SourceRangeMissed<DIM> missed(bounds);
  const ScreeningMajorant<DIM>& majorant =
    missSourceRange ? static_cast<const ScreeningMajorant<DIM>&>(missed) : bounds;
  VaryingCoefficientSettings settings;
  settings.Gradient = true;
  settings.Epsilon = epsilon;
  settings.NearBoundarySplitting = splitting;
  const DerivativeRun run = RunPointEstimator<DIM>(points, 1 + DIM, walks, 20261129, threads,
    [&]() { return VaryingCoefficientEstimator<DIM>(boundary, field, majorant, settings); });
  std::vector<SlotCheck<DIM>> gradient;
  for (int k = 0; k < DIM; ++k)
  {
    gradient.push_back({ 1 + k, [&with, k](const Vec<DIM>& x) { return with.U.Gradient(x)[k]; } });
  }
  VaryingResult r;
  r.Value = Calibrate<DIM>(run, points, { { 0, with.U.Value } })[0];
  r.Gradient = Pooled(Calibrate<DIM>(run, points, gradient));
  return r;
}

void Report(const char* name, const VaryingResult& r)
{
  std::printf("%s: value mean z² %.3f max |z| %.2f; gradient mean z² %.3f max |z| %.2f\n", name,
    r.Value.MeanZ2, r.Value.MaxAbsZ, r.Gradient.MeanZ2, r.Gradient.MaxAbsZ);
}

// Values and gradients at every point within 5 standard errors, mean z² in
// [0.7, 1.4], 256 walks per point unless told.
template <int DIM>
void ExpectVaryingCalibrated(const char* name, const SimplexMesh<DIM>& mesh,
  const ManufacturedCase<DIM>& with, const CoefficientField<DIM>& field,
  const std::vector<Vec<DIM>>& points, int walks = 256)
{
  const VaryingResult r = CalibrateVarying<DIM>(mesh, with, field, points, walks);
  Report(name, r);
  const int n = static_cast<int>(points.size());
  ExpectCalibrated(r.Value, n);
  ExpectCalibrated(r.Gradient, DIM * n);
}

// The ball: a bump of conductivity (σ′ < 0 on its top) and an absorption.
ManufacturedCase<3> BallCase()
{
  ManufacturedCase<3> with;
  with.U = ExpCosSolution<3>();
  with.Alpha = GaussianBump<3>(1.0, 1.5, Vec<3>(0.2, 0.0, 0.0), 0.4);
  with.Sigma = [](const Vec<3>& x) { return 1.0 + x[0] * x[0]; };
  return with;
}

// The 2D U: a tenfold step of conductivity across x = 1.3, 0.2 wide.
ManufacturedCase<2> UCase()
{
  ManufacturedCase<2> with;
  with.U = SineSolution<2>();
  with.Alpha = SmoothStep<2>(5.5, 4.5, 1.3, 0.1);
  return with;
}

const std::vector<Cell<2>> kUCells = { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 0, 1 }, { 2, 1 } };
const std::vector<Cell<3>> kLCells = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };

// The 3D L: a dip of conductivity (σ′ > 0) and a constant absorption.
ManufacturedCase<3> LCase()
{
  ManufacturedCase<3> with;
  with.U = SineSolution<3>();
  with.Alpha = GaussianBump<3>(2.0, -1.0, Vec<3>(0.6, 0.6, 0.5), 0.5);
  with.Sigma = [](const Vec<3>&) { return 2.0; };
  return with;
}
} // namespace

TEST(VaryingCoefficientWalk, BallWithBumpAndAbsorptionCalibrated)
{
  ExpectVaryingCalibrated<3>("ball", MakeIcosphere(4), BallCase(),
    ManufacturedField<3>(BallCase()), RandomPointsInBall<3>(240, 0.9, 7));
}

TEST(VaryingCoefficientWalk, NonconvexUWithSteepStepCalibrated2D)
{
  ExpectVaryingCalibrated<2>("U", MakeBlockShape<2>(kUCells, 32), UCase(),
    ManufacturedField<2>(UCase()), PointsInCells<2>(kUCells, 300, 0.02, 11));
}

// The source's roulette takes the middle of f′'s range on a ball exactly
// and samples the rest with a probability never below 1/32: with a range
// that is wrong everywhere (it claims f′ = 0) the estimates stay unbiased
// and calibrated, only wider. Dropping the rest instead (no sampling below
// the range) gives mean z² 57 here.
TEST(VaryingCoefficientWalk, MissedSourceRangeCostsVarianceNotBias)
{
  const auto points = PointsInCells<2>(kUCells, 150, 0.02, 13);
  const VaryingResult r = CalibrateVarying<2>(MakeBlockShape<2>(kUCells, 32), UCase(),
    ManufacturedField<2>(UCase()), points, 256, 2, true);
  Report("U, source range missed", r);
  ExpectCalibrated(r.Value, 150);
  ExpectCalibrated(r.Gradient, 2 * 150);
}

TEST(VaryingCoefficientWalk, NonconvexLWithDipCalibrated3D)
{
  ExpectVaryingCalibrated<3>("L", MakeBlockShape<3>(kLCells, 8), LCase(),
    ManufacturedField<3>(LCase()), PointsInCells<3>(kLCells, 240, 0.02, 13));
}

// Two tissues as voxels (a sphere of α = 0.5, σ = 1 in α = 0.2, σ = 0.5,
// h = 0.04), smoothed by a Gaussian of width 0.05 and the cubic B-spline:
// f from u and the smoothed α, so u is the exact solution of the smoothed
// problem the walk solves.
class TwoTissueField final : public CoefficientField<3>
{
public:
  TwoTissueField()
    : Image(MakeImage())
    , U(ExpCosSolution<3>())
  {
  }
  void Evaluate(const Vec<3>& x, CoefficientSample<3>& out) const override
  {
    this->Image.Evaluate(x, out);
    out.Source = out.Alpha * this->U.Laplacian(x) + out.AlphaGradient.dot(this->U.Gradient(x)) -
      out.Absorption * this->U.Value(x);
  }
  const SmoothFunction<3>& Solution() const { return this->U; }

private:
  static ImageCoefficients<3> MakeImage()
  {
    VoxelGrid grid;
    grid.Origin = { -1.08, -1.08, -1.08 };
    grid.Spacing = { 0.04, 0.04, 0.04 };
    grid.Dims = { 55, 55, 55 };
    std::vector<double> alpha, sigma;
    for (int k = 0; k < 55; ++k)
    {
      for (int j = 0; j < 55; ++j)
      {
        for (int i = 0; i < 55; ++i)
        {
          const Vec<3> p(-1.08 + 0.04 * i, -1.08 + 0.04 * j, -1.08 + 0.04 * k);
          const bool inside = (p - Vec<3>(0.2, 0.0, 0.0)).norm() < 0.4;
          alpha.push_back(inside ? 0.5 : 0.2);
          sigma.push_back(inside ? 1.0 : 0.5);
        }
      }
    }
    return ImageCoefficients<3>(grid, { alpha, 0.0 }, { sigma, 0.0 }, { {}, 0.0 }, 0.05);
  }
  ImageCoefficients<3> Image;
  SmoothFunction<3> U;
};

// The interface is steep (α 0.2 to 0.5 over about 0.1): σ′ has deep
// negative lobes there, where collision weights exceed 1 and their products
// give the values a heavy tail, so the value's mean z² depends on the seed
// more than elsewhere. At 1,024 walks, over ten seeds, it ranged from 0.90
// to 1.63 (mean 1.20; this seed 0.99, the largest |z| over all 4.9); with
// the negative part of σ′ bounded at 2× instead of 4× (collision weights up
// to 3/2, not 5/4) it ranged from 0.97 to 1.59 (mean 1.27) over nine, and
// from 0.94 to 1.70 over five at 2,048 walks, 1.17 and 1.24 at 4,096 and
// 16,384: no trend, so no bias. The value is held to that spread (mean z²
// below 1.8, every |z| below 5), the gradient to the usual [0.7, 1.4].
// ErrorBars.md lists the case.
TEST(VaryingCoefficientWalk, TwoTissuesFromVoxelsCalibrated)
{
  const TwoTissueField field;
  ManufacturedCase<3> with;
  with.U = field.Solution();
  const auto points = RandomPointsInBall<3>(160, 0.9, 23);
  const VaryingResult r = CalibrateVarying<3>(MakeIcosphere(4), with, field, points, 1024);
  Report("two tissues", r);
  EXPECT_EQ(r.Value.Points, 160);
  EXPECT_LT(r.Value.MaxAbsZ, 5.0);
  EXPECT_GT(r.Value.MeanZ2, 0.7);
  EXPECT_LT(r.Value.MeanZ2, 1.8);
  ExpectCalibrated(r.Gradient, 3 * 160);
}

// Without the Δα/(2α) term of σ′ the walk solves another equation: the
// check must see it.
// Near the boundary (points 10⁻³ from a sphere of 1,280 triangles; ε
// 10⁻⁶), u = |x|² under a bump of conductivity: most walks end at once
// and the rare one that wanders deep brings back the source's integral.
// At 512 walks the plain walks' value mean z² was 10–34 (gradient 8–17)
// over three point sets; splitting as walk on spheres does made it
// 0.77–1.44 (gradient 0.96–1.19), at about 4 times the time. Points far
// from the boundary walk as without it, bit for bit.
TEST(VaryingCoefficientWalk, NearBoundarySplittingCarriesTheRareDeepWalks)
{
  ManufacturedCase<3> with;
  with.U.Value = [](const Vec3& x) { return x.squaredNorm(); };
  with.U.Gradient = [](const Vec3& x) { return Vec3(2.0 * x); };
  with.U.Laplacian = [](const Vec3&) { return 6.0; };
  with.Alpha = GaussianBump<3>(1.0, 0.5, Vec<3>(0.2, 0.0, 0.0), 0.4);
  const ManufacturedField<3> field(with);
  const SimplexMesh<3> mesh = MakeIcosphere(3);
  const Boundary<3> shape = ExactBoundary<3>(mesh, with.U);
  const std::vector<Vec3> near = PointsAtGap(RandomPointsInBall<3>(40, 0.9, 61), 1e-3,
    [&](const Vec3& x) { return shape.Distance(x); });
  const VaryingResult plain = CalibrateVarying<3>(mesh, with, field, near, 512, 2, false, 1e-6);
  const VaryingResult split =
    CalibrateVarying<3>(mesh, with, field, near, 512, 2, false, 1e-6, true);
  Report("10^-3 from the sphere, plain", plain);
  Report("10^-3 from the sphere, split", split);
  EXPECT_GT(plain.Value.MeanZ2, 2.0);
  ExpectCalibrated(split.Value, 40);
  ExpectCalibrated(split.Gradient, 3 * 40);

  const auto far = RandomPointsInBall<3>(10, 0.3, 63);
  const VaryingResult farPlain = CalibrateVarying<3>(mesh, with, field, far, 32, 2, false, 1e-6);
  const VaryingResult farSplit =
    CalibrateVarying<3>(mesh, with, field, far, 32, 2, false, 1e-6, true);
  EXPECT_EQ(farPlain.Value.MeanZ2, farSplit.Value.MeanZ2);
  EXPECT_EQ(farPlain.Gradient.MeanZ2, farSplit.Gradient.MeanZ2);
}

TEST(VaryingCoefficientWalk, WrongTransformIsCaught)
{
  const ManufacturedField<2> field(UCase());
  const CallableCoefficients<2> wrong([&field](const Vec<2>& x, CoefficientSample<2>& out) {
    field.Evaluate(x, out);
    out.AlphaLaplacian = 0.0;
  });
  const VaryingResult r = CalibrateVarying<2>(MakeBlockShape<2>(kUCells, 32), UCase(), wrong,
    PointsInCells<2>(kUCells, 150, 0.02, 11), 256);
  Report("U without Δα", r);
  EXPECT_GT(r.Value.MeanZ2, 3.0);
}

TEST(VaryingCoefficientWalk, SameNumbersOnAnyThreadCount)
{
  const ManufacturedField<2> field(UCase());
  const auto points = PointsInCells<2>(kUCells, 16, 0.02, 17);
  const VaryingResult one = CalibrateVarying<2>(MakeBlockShape<2>(kUCells, 8), UCase(), field, points, 32, 1);
  const VaryingResult two = CalibrateVarying<2>(MakeBlockShape<2>(kUCells, 8), UCase(), field, points, 32, 2);
  EXPECT_EQ(one.Value.MeanZ2, two.Value.MeanZ2);
  EXPECT_EQ(one.Gradient.MeanZ2, two.Gradient.MeanZ2);
}

// The Problem's door: values and gradients of the varying equation in a
// batch, a target standard error reached at every point (and the answers
// still within 5 of their error bars), derivatives it cannot give refused.
TEST(VaryingCoefficientWalk, ThroughAProblemToATarget)
{
  const ManufacturedCase<3> with = LCase();
  auto boundary =
    std::make_shared<const Boundary<3>>(ExactBoundary<3>(MakeBlockShape<3>(kLCells, 8), with.U));
  auto model = std::make_shared<CoefficientModel<3>>();
  auto field = std::make_shared<ManufacturedField<3>>(with);
  model->Field = field;
  model->Majorant = std::make_shared<ScreeningBoundGrid<3>>(*field, boundary->BoundsMin(),
    boundary->BoundsMax(), ScreeningBoundGrid<3>::Settings());
  WalkSettings settings;
  EXPECT_THROW(Problem<3>(boundary, settings, model), std::invalid_argument);
  settings.Problem = Equation::VaryingCoefficients;
  EXPECT_THROW(Problem<3>(boundary, settings), std::invalid_argument);
  const Problem<3> problem(boundary, settings, model);

  const auto points = PointsInCells<3>(kLCells, 40, 0.02, 19);
  BatchRequest request;
  request.Seed = 5;
  request.WalksPerPoint = 4096;
  request.TargetStandardError = 0.04;
  request.Derivatives.Gradient = true;
  const BatchEstimates out = problem.EstimateAll(AsProbe<3>(points), request);
  ASSERT_EQ(out.Summary.Layout.Size, 4);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    EXPECT_LE(std::sqrt(out.ValueVariance(i)), 0.04);
    EXPECT_LT(out.Counters[i].Walks, 4096u);
    EXPECT_LT(std::abs(out.Value(i) - with.U.Value(points[i])), 5.0 * std::sqrt(out.ValueVariance(i)));
    const Vec<3> g = with.U.Gradient(points[i]);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_LT(std::abs(out.Mean(i, 1 + k) - g[k]), 5.0 * std::sqrt(out.Variance(i, 1 + k)));
    }
    EXPECT_EQ(out.Status[i], DerivativeStatus::Interior);
  }
  request.Derivatives.Hessian = true;
  EXPECT_THROW(problem.EstimateAll(AsProbe<3>(points), request), std::invalid_argument);
}
