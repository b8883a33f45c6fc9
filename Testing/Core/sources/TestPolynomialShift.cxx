// Tests of gridfree/sources/PolynomialShift.h and the shifted problem
// (problem/PolynomialShiftFit.h):
// * the polynomial's derivatives and operator agree with finite
//   differences of its value;
// * a problem whose solution is a polynomial of the fitted degree is
//   answered exactly (to round-off) with 8 walks, values and gradients, for
//   the Poisson, Laplace and screened equations: the boundary reads g − P,
//   the source f − (ΔP − c·P), and P, ∇P come back in the answer — a
//   mistake in any of the three shows as an error of order one; a point
//   outside the closed boundary is NaN and counted;
// * on solutions that are not polynomials (3D on an L of three cubes, 2D
//   in the disc, Poisson and screened) the shifted walks stay calibrated
//   (|z| < 5, mean z² in [0.7, 1.4], values and gradients) and their
//   per-walk variance is under half the plain walks';
// * the sphere cache of a shifted problem holds w (its walks ask for w,
//   BatchRequest::AddPolynomialShift) and, with P added to its answers,
//   is calibrated over independent caches (values and gradients).
#include <gridfree/cache/SphereCache.h>
#include <gridfree/problem/PolynomialShiftFit.h>
#include <gridfree/problem/Problem.h>
#include "BlockShapes.h"
#include "EstimatorChecks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
TEST(PolynomialShift, DerivativesMatchDifferences)
{
  PolynomialShift<3> p(4, Vec3(-1.0, -2.0, 0.0), Vec3(2.0, 1.0, 3.0));
  std::vector<double> c(p.NumberOfTerms());
  for (std::size_t t = 0; t < c.size(); ++t)
  {
    c[t] = std::sin(1.7 * static_cast<double>(t) + 0.3);
  }
  p.SetCoefficients(c);
  p.SetScreening(2.5);
  const Vec3 x(0.3, -0.4, 1.1);
  const double h = 1e-4;
  for (int i = 0; i < 3; ++i)
  {
    Vec3 e = Vec3::Zero();
    e[i] = h;
    EXPECT_NEAR(p.Gradient(x)[i], (p.Value(x + e) - p.Value(x - e)) / (2 * h), 1e-6);
    const Vec3 dg = (p.Gradient(x + e) - p.Gradient(x - e)) / (2 * h);
    for (int j = 0; j < 3; ++j)
    {
      EXPECT_NEAR(p.Hessian(x)(j, i), dg[j], 1e-6);
    }
    EXPECT_NEAR(p.OperatorGradient(x)[i], (p.Operator(x + e) - p.Operator(x - e)) / (2 * h), 1e-6);
  }
  EXPECT_NEAR(p.Operator(x), p.Hessian(x).trace() - 2.5 * p.Value(x), 1e-12);
}

struct ShiftManufactured
{
  Field<3> U;
  std::function<Vec3(const Vec3&)> Gradient;
  Field<3> F; // Δu − c·u
};

// A mesh with g from a function (exact on every triangle: the shifted walks
// are narrow enough to see the bias of values interpolated between
// vertices, which the plain walks' error bars hide).
std::shared_ptr<Boundary<3>> ShiftExactBoundary(const Field<3>& u, const SimplexMesh<3>& mesh)
{
  auto values = std::make_shared<CallableBoundaryValues<3>>(
    [u](const Vec3& p, std::int64_t, double* out) { out[0] = u(p); }, 1);
  auto boundary = std::make_shared<Boundary<3>>();
  boundary->SetMesh(mesh.Vertices, mesh.Simplices, values);
  return boundary;
}

void ExpectShiftExact(Equation equation, double screening, const ShiftManufactured& m)
{
  const auto boundary = ShiftExactBoundary(m.U, MakeIcosphere(4));
  WalkSettings settings;
  settings.Problem = equation;
  settings.ScreeningCoefficient = screening;
  auto sources = std::make_shared<SourceSet<3>>();
  const Field<3> f = m.F;
  sources->MakeVolume = [f](double) { return std::make_unique<FunctionSource<3>>(f); };
  const auto problem = MakeShiftedProblem<3>(*boundary, settings, sources.get(), 4);
  std::vector<Vec3> points = RandomPointsInBall<3>(40, 0.9, 3);
  points.push_back(Vec3(1.5, 0.2, 0.0)); // outside: NaN, counted
  BatchRequest request;
  request.WalksPerPoint = 8;
  request.Derivatives.Gradient = true;
  const BatchEstimates e = problem->EstimateAll(AsProbe<3>(points), request);
  const SampleLayout& l = e.Summary.Layout;
  EXPECT_TRUE(std::isnan(e.Value(points.size() - 1)));
  EXPECT_EQ(e.Summary.PointsOutsideShift, 1u);
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
  {
    worst = std::max(worst, std::abs(e.Value(i) - m.U(points[i])));
    for (int k = 0; k < 3; ++k)
    {
      worst = std::max(worst, std::abs(e.Mean(i, l.Gradient + k) - m.Gradient(points[i])[k]));
    }
  }
  EXPECT_LT(worst, 1e-6) << "equation " << static_cast<int>(equation);
}

TEST(PolynomialShift, PolynomialSolutionsAreExact)
{
  // Poisson: u = 1 + x²y − z³ + xyz − x⁴/2, f = Δu = 2y − 6z − 6x².
  ExpectShiftExact(Equation::Poisson, 0.0,
    { [](const Vec3& x) {
       return 1 + x[0] * x[0] * x[1] - x[2] * x[2] * x[2] + x[0] * x[1] * x[2] -
         0.5 * std::pow(x[0], 4);
     },
      [](const Vec3& x) {
        return Vec3(2 * x[0] * x[1] + x[1] * x[2] - 2 * std::pow(x[0], 3),
          x[0] * x[0] + x[0] * x[2], -3 * x[2] * x[2] + x[0] * x[1]);
      },
      [](const Vec3& x) { return 2 * x[1] - 6 * x[2] - 6 * x[0] * x[0]; } });
  // Laplace: u = x² − y² + xyz + 3z (harmonic); solved as Poisson with −ΔP.
  ExpectShiftExact(Equation::Laplace, 0.0,
    { [](const Vec3& x) { return x[0] * x[0] - x[1] * x[1] + x[0] * x[1] * x[2] + 3 * x[2]; },
      [](const Vec3& x) {
        return Vec3(2 * x[0] + x[1] * x[2], -2 * x[1] + x[0] * x[2], x[0] * x[1] + 3);
      },
      [](const Vec3&) { return 0.0; } });
  // Screened, c = 3: u = 2 + x y² − z², f = Δu − 3u = 2x − 2 − 3u.
  ExpectShiftExact(Equation::ScreenedPoisson, 3.0,
    { [](const Vec3& x) { return 2 + x[0] * x[1] * x[1] - x[2] * x[2]; },
      [](const Vec3& x) { return Vec3(x[1] * x[1], 2 * x[0] * x[1], -2 * x[2]); },
      [](const Vec3& x) {
        return 2 * x[0] - 2 - 3 * (2 + x[0] * x[1] * x[1] - x[2] * x[2]);
      } });
}

struct ShiftSpread
{
  double MeanZ2 = 0.0;
  double MaxAbsZ = 0.0;
  double GradientMeanZ2 = 0.0;
  double GradientMaxAbsZ = 0.0;
  double WalkVariance = 0.0; // per walk, the value's, averaged over points
};

template <int DIM>
ShiftSpread SolveShifted(const Problem<DIM>& problem, const std::vector<Vec<DIM>>& points, const Field<DIM>& u,
  const std::function<Vec<DIM>(const Vec<DIM>&)>& gradient, int walks)
{
  BatchRequest request;
  request.WalksPerPoint = walks;
  request.Seed = 7;
  request.Derivatives.Gradient = true;
  const BatchEstimates e = problem.EstimateAll(AsProbe<DIM>(points), request);
  const SampleLayout& l = e.Summary.Layout;
  ShiftSpread s;
  const double n = static_cast<double>(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double z = (e.Value(i) - u(points[i])) / std::sqrt(e.ValueVariance(i));
    s.MeanZ2 += z * z / n;
    s.MaxAbsZ = std::max(s.MaxAbsZ, std::isfinite(z) ? std::abs(z) : 1e300);
    s.WalkVariance += e.ValueVariance(i) * walks / n;
    const Vec<DIM> g = gradient(points[i]);
    for (int k = 0; k < DIM; ++k)
    {
      const double zg =
        (e.Mean(i, l.Gradient + k) - g[k]) / std::sqrt(e.Variance(i, l.Gradient + k));
      s.GradientMeanZ2 += zg * zg / (n * DIM);
      s.GradientMaxAbsZ = std::max(s.GradientMaxAbsZ, std::isfinite(zg) ? std::abs(zg) : 1e300);
    }
  }
  return s;
}

template <int DIM>
void ExpectShiftCalibratedAndNarrower(const Boundary<DIM>& boundary, Equation equation, double c,
  const Field<DIM>& u, const std::function<Vec<DIM>(const Vec<DIM>&)>& gradient,
  const Field<DIM>& f, const std::vector<Vec<DIM>>& points, int degree, const char* name)
{
  WalkSettings settings;
  settings.Problem = equation;
  settings.ScreeningCoefficient = c;
  auto sources = std::make_shared<SourceSet<DIM>>();
  sources->MakeVolume = [f](double) { return std::make_unique<FunctionSource<DIM>>(f); };
  const Problem<DIM> plain(std::make_shared<const Boundary<DIM>>(boundary), settings, sources);
  const auto shifted = MakeShiftedProblem<DIM>(boundary, settings, sources.get(), degree);
  const ShiftSpread a = SolveShifted<DIM>(plain, points, u, gradient, 256);
  const ShiftSpread b = SolveShifted<DIM>(*shifted, points, u, gradient, 256);
  std::printf("  %s: plain walk variance %.4g (mean z^2 %.2f, gradient %.2f); shifted %.4g "
              "(mean z^2 %.2f, max |z| %.2f; gradient %.2f, max %.2f)\n",
    name, a.WalkVariance, a.MeanZ2, a.GradientMeanZ2, b.WalkVariance, b.MeanZ2, b.MaxAbsZ,
    b.GradientMeanZ2, b.GradientMaxAbsZ);
  EXPECT_LT(b.MaxAbsZ, 5.0) << name;
  EXPECT_GT(b.MeanZ2, 0.7) << name;
  EXPECT_LT(b.MeanZ2, 1.4) << name;
  EXPECT_LT(b.GradientMaxAbsZ, 5.0) << name;
  EXPECT_GT(b.GradientMeanZ2, 0.7) << name;
  EXPECT_LT(b.GradientMeanZ2, 1.4) << name;
  EXPECT_LT(b.WalkVariance, 0.5 * a.WalkVariance) << name;
}

// u = e^{0.8x} cos(0.6y) + |x|²/2 on an L of three unit cubes, each side
// cut 12 × 12, and points inside it.
struct ShiftLCase
{
  SimplexMesh<3> Mesh = MakeBlockShape<3>({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, 12);
  Field<3> U = [](const Vec3& x) {
    return std::exp(0.8 * x[0]) * std::cos(0.6 * x[1]) + 0.5 * x.squaredNorm();
  };
  std::function<Vec3(const Vec3&)> Gradient = [](const Vec3& x) {
    const double e = std::exp(0.8 * x[0]);
    return Vec3(0.8 * e * std::cos(0.6 * x[1]) + x[0], -0.6 * e * std::sin(0.6 * x[1]) + x[1], x[2]);
  };
  Field<3> F = [](const Vec3& x) {
    return std::exp(0.8 * x[0]) * std::cos(0.6 * x[1]) * (0.64 - 0.36) + 3.0;
  };
  std::vector<Vec3> Points(std::size_t count) const
  {
    std::vector<Vec3> points;
    for (const Vec3& p : RandomPointsInBox<3>(static_cast<int>(8 * count), 1.0, 11))
    {
      const Vec3 q = p + Vec3(1.0, 1.0, 0.5);
      const bool inL = q[2] > 0.05 && q[2] < 0.95 && q[0] > 0.05 && q[1] > 0.05 &&
        ((q[0] < 1.95 && q[1] < 0.95) || (q[0] < 0.95 && q[1] < 1.95));
      if (inL && points.size() < count)
      {
        points.push_back(q);
      }
    }
    return points;
  }
};

TEST(PolynomialShift, ShiftedWalksCalibratedAndNarrower3D)
{
  const ShiftLCase l;
  ExpectShiftCalibratedAndNarrower<3>(*ShiftExactBoundary(l.U, l.Mesh), Equation::Poisson, 0.0,
    l.U, l.Gradient, l.F, l.Points(150), 2, "3D L");
}

TEST(PolynomialShift, SphereCacheOfAShiftedProblemIsCalibrated)
{
  const ShiftLCase l;
  WalkSettings settings;
  settings.Problem = Equation::Poisson;
  auto sources = std::make_shared<SourceSet<3>>();
  const Field<3> f = l.F;
  sources->MakeVolume = [f](double) { return std::make_unique<FunctionSource<3>>(f); };
  const auto problem =
    MakeShiftedProblem<3>(*ShiftExactBoundary(l.U, l.Mesh), settings, sources.get(), 2);
  const std::vector<Vec3> points = l.Points(120);
  const std::vector<std::array<double, 3>> probe = AsProbe<3>(points);
  double z2 = 0.0, gz2 = 0.0, most = 0.0;
  int values = 0, gradients = 0;
  for (int k = 0; k < 6; ++k)
  {
    SphereCacheSettings cacheSettings;
    cacheSettings.SamplesPerSphere = 128;
    cacheSettings.Seed = static_cast<std::uint64_t>(40 + k);
    SphereCache<3> cache(*problem, cacheSettings);
    CacheEvaluation answer;
    ASSERT_TRUE(cache.Answer(*problem, probe, CacheDerivatives(true), answer));
    AddShiftToCacheAnswers<3>(
      *problem->GetPolynomialShift(), problem->GetBoundary(), probe, { 1.0, 0.0, 0.0 }, answer);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      if (answer.InShell[i] || answer.Outside[i])
      {
        continue;
      }
      const double z = (answer.Value[i] - l.U(points[i])) / std::sqrt(answer.ValueVariance[i]);
      z2 += z * z;
      most = std::max(most, std::abs(z));
      ++values;
      const Vec3 g = l.Gradient(points[i]);
      for (int a = 0; a < 3; ++a)
      {
        const double zg = (answer.Gradient[i * 3 + a] - g[a]) / std::sqrt(answer.GradientVariance[i * 3 + a]);
        gz2 += zg * zg;
        most = std::max(most, std::abs(zg));
        ++gradients;
      }
    }
  }
  std::printf("  sphere cache of the shifted L: %d values mean z^2 %.2f, %d gradient components "
              "%.2f, max |z| %.2f\n",
    values, z2 / values, gradients, gz2 / gradients, most);
  EXPECT_GE(values, 6 * 80);
  EXPECT_GT(z2 / values, 0.7);
  EXPECT_LT(z2 / values, 1.4);
  EXPECT_GT(gz2 / gradients, 0.7);
  EXPECT_LT(gz2 / gradients, 1.4);
  EXPECT_LT(most, 5.0);
}

TEST(PolynomialShift, ShiftedWalksCalibratedAndNarrower2D)
{
  // Screened, c = 2, in the unit disc: u = sin(2x) e^{y} + 1, f = Δu − 2u.
  const Field<2> u = [](const Vec2& x) { return std::sin(2 * x[0]) * std::exp(x[1]) + 1.0; };
  const auto gradient = [](const Vec2& x) {
    return Vec2(2 * std::cos(2 * x[0]) * std::exp(x[1]), std::sin(2 * x[0]) * std::exp(x[1]));
  };
  const Field<2> f = [u](const Vec2& x) {
    return -3.0 * std::sin(2 * x[0]) * std::exp(x[1]) - 2.0 * u(x);
  };
  const Boundary<2> boundary = MakeBoundary<2>(MakeCircle(4096), { u });
  ExpectShiftCalibratedAndNarrower<2>(boundary, Equation::ScreenedPoisson, 2.0, u, gradient, f,
    RandomPointsInBall<2>(200, 0.9, 13), 4, "2D disc, screened");
}
} // namespace
