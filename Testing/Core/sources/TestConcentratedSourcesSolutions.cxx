// Point and curve sources (paper Sec. 4.2.2) against free-space solutions,
// and the variance of the volume-source sampling strategies (Sec. 4.2.1,
// Fig. 7) on a concentrated source.
//
// For Δu = Σ s_i δ_{z_i} (+ a curve source s δ_γ) the free-space solution is
// the superposition of fundamental solutions Φ (ΔΦ = δ): Φ = −1/(4π r) in
// 3D, ln(r)/(2π) in 2D. Inside the unit sphere with g = u on the boundary
// the estimate must match it.
#include <gridfree/sources/ConcentratedSources.h>
#include "EstimatorChecks.h"
#include "SourcePotentials.h"

#include <gtest/gtest.h>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
constexpr int Points = 400;

template <int DIM>
Vec<DIM> Point(double x, double y, double z)
{
  Vec<DIM> p;
  p[0] = x;
  p[1] = y;
  if (DIM == 3)
  {
    p[DIM - 1] = z;
  }
  return p;
}

// Probe points away from the sources (the estimate is exact there, but the
// walk's value is heavy-tailed close to a singularity).
template <int DIM>
std::vector<Vec<DIM>> PointsAwayFrom(
  const std::function<double(const Vec<DIM>&)>& distance, std::uint32_t seed)
{
  std::vector<Vec<DIM>> points;
  for (const Vec<DIM>& p : RandomPointsInBall<DIM>(4 * Points, 0.85, seed))
  {
    if (distance(p) > 0.25 && points.size() < std::size_t(Points))
    {
      points.push_back(p);
    }
  }
  return points;
}

template <int DIM>
void CheckPointSources(std::uint64_t seed)
{
  const std::vector<Vec<DIM>> z = { Point<DIM>(0.2, -0.1, 0.15), Point<DIM>(-0.3, 0.25, -0.1) };
  const std::vector<double> s = { 1.5, -0.8 };
  const Field<DIM> u = [&](const Vec<DIM>& x) {
    return s[0] * Fundamental<DIM>((x - z[0]).norm()) + s[1] * Fundamental<DIM>((x - z[1]).norm());
  };
  PointSources<DIM> sources;
  sources.Set(z, 1, s);
  ConcentratedSourceSet<DIM> set;
  set.Points = &sources;
  WalkSettings settings;
  settings.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  settings.Problem = Equation::Poisson;
  const auto points = PointsAwayFrom<DIM>(
    [&](const Vec<DIM>& x) { return std::min((x - z[0]).norm(), (x - z[1]).norm()); }, 90 + DIM);
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { u });
  ExpectCalibrated(
    CheckEstimator<DIM>(boundary, settings, points, { u }, 512, seed, nullptr, set)[0], Points);
}

template <int DIM>
void CheckCurveSource(std::uint64_t seed)
{
  const Vec<DIM> a = Point<DIM>(-0.4, -0.2, 0.1), b = Point<DIM>(0.35, 0.3, -0.15);
  const double sa = 2.0, sb = -1.0;
  // A polyline of 8 segments along the line, strengths per vertex.
  std::vector<Vec<DIM>> vertices;
  std::vector<double> strengths;
  std::vector<std::array<std::int64_t, 2>> segments;
  for (int k = 0; k <= 8; ++k)
  {
    vertices.push_back(a + (k / 8.0) * (b - a));
    strengths.push_back(sa + (k / 8.0) * (sb - sa));
    if (k > 0)
    {
      segments.push_back({ k - 1, k });
    }
  }
  CurveSources<DIM> curve;
  curve.Set(vertices, segments, 1, strengths);
  ConcentratedSourceSet<DIM> set;
  set.Curves = &curve;
  const Field<DIM> u = [&](const Vec<DIM>& x) { return CurvePotential<DIM>(x, a, b, sa, sb); };
  WalkSettings settings;
  settings.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  settings.Problem = Equation::Poisson;
  const auto points =
    PointsAwayFrom<DIM>([&](const Vec<DIM>& x) { return DistanceToSegment<DIM>(x, a, b); }, 95 + DIM);
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { u });
  ExpectCalibrated(
    CheckEstimator<DIM>(boundary, settings, points, { u }, 512, seed, nullptr, set)[0], Points);
}
// The gradient and Hessian estimators with a curve source (one sample of
// L·s(z)·∇G and L·s(z)·∇²G per first ball): every component calibrated.
template <int DIM>
void CheckCurveSourceDerivatives(std::uint64_t seed)
{
  const Vec<DIM> a = Point<DIM>(-0.4, -0.2, 0.1), b = Point<DIM>(0.35, 0.3, -0.15);
  const double sa = 2.0, sb = -1.0;
  CurveSources<DIM> curve;
  curve.Set({ a, b }, { std::array<std::int64_t, 2>{ 0, 1 } }, 1, { sa, sb });
  ConcentratedSourceSet<DIM> set;
  set.Curves = &curve;
  const Field<DIM> u = [&](const Vec<DIM>& x) { return CurvePotential<DIM>(x, a, b, sa, sb); };
  WalkSettings settings;
  settings.Epsilon = 1e-4 * 2.0 * std::sqrt(double(DIM));
  settings.Problem = Equation::Poisson;
  const auto points =
    PointsAwayFrom<DIM>([&](const Vec<DIM>& x) { return DistanceToSegment<DIM>(x, a, b); }, 97 + DIM);
  const Boundary<DIM> boundary = MakeBoundary<DIM>(UnitSphereMesh<DIM>(), { u });
  DerivativeRequest request;
  request.Gradient = request.Hessian = true;
  const SampleLayout layout =
    DerivativeWalkOnSpheres<DIM>(boundary, settings, request, nullptr, set).Layout();
  std::vector<SlotCheck<DIM>> checks = { { layout.Value, u } };
  for (int i = 0; i < DIM; ++i)
  {
    checks.push_back({ layout.Gradient + i, [&, i](const Vec<DIM>& x) {
                        Vec<DIM> g;
                        Mat<DIM> h;
                        CurvePotentialDerivatives<DIM>(x, a, b, sa, sb, g, h);
                        return g[i];
                      } });
    for (int j = i; j < DIM; ++j)
    {
      checks.push_back({ layout.Hessian + i * DIM + j, [&, i, j](const Vec<DIM>& x) {
                          Vec<DIM> g;
                          Mat<DIM> h;
                          CurvePotentialDerivatives<DIM>(x, a, b, sa, sb, g, h);
                          return h(i, j);
                        } });
    }
  }
  // In 3D a curve sample's G ~ 1/r makes later steps' values heavy-tailed
  // when a walk passes close to the curve; 2048 walks keep the sample
  // variance a reliable guide at 5 standard errors (with 1024, a change of
  // the step radii within their relaxation moved one Hessian entry's max |z|
  // from below 5 to 5.7).
  const auto run = RunDerivativeEstimator<DIM>(
    boundary, settings, request, points, DIM == 3 ? 2048 : 512, seed, nullptr, set);
  const auto calibrations = Calibrate<DIM>(run, points, checks);
  for (std::size_t k = 0; k < calibrations.size(); ++k)
  {
    SCOPED_TRACE("check " + std::to_string(k) + ", mean z² " +
      std::to_string(calibrations[k].MeanZ2) + ", max |z| " + std::to_string(calibrations[k].MaxAbsZ));
    ExpectCalibrated(calibrations[k], Points);
  }
}
} // namespace

TEST(CurveSourceSolutions, GradientAndHessian3D)
{
  CheckCurveSourceDerivatives<3>(804);
}

TEST(CurveSourceSolutions, GradientAndHessian2D)
{
  CheckCurveSourceDerivatives<2>(805);
}

TEST(PointSourceSolutions, FreeSpaceSuperposition3D)
{
  CheckPointSources<3>(800);
}

TEST(PointSourceSolutions, FreeSpaceSuperposition2D)
{
  CheckPointSources<2>(801);
}

TEST(CurveSourceSolutions, FreeSpaceLinearStrength3D)
{
  CheckCurveSource<3>(802);
}

TEST(CurveSourceSolutions, FreeSpaceLinearStrength2D)
{
  CheckCurveSource<2>(803);
}

// Paper Fig. 7: per-walk variance of the three volume-source strategies on a
// concentrated source (a narrow Gaussian), averaged over probe points.
// Prints the figures; Green's-function sampling beats uniform sampling, and
// multiple importance sampling is never much worse than the better of them.
TEST(SourceSamplingVariance, ConcentratedSource3D)
{
  const Vec3 center(0.3, -0.1, 0.2);
  const double sigma = 0.08;
  FunctionSource<3> f(
    [&](const Vec3& x) { return std::exp(-(x - center).squaredNorm() / (sigma * sigma)); });
  const Boundary<3> boundary =
    MakeBoundary<3>(MakeIcosphere(4), { [](const Vec3&) { return 0.0; } });
  const auto points = RandomPointsInBall<3>(40, 0.8, 99);
  double variance[3] = { 0, 0, 0 };
  for (const SourceSampling sampling :
    { SourceSampling::Uniform, SourceSampling::GreensFunction, SourceSampling::MultipleImportance })
  {
    WalkSettings settings;
    settings.Epsilon = 1e-4 * 2.0 * std::sqrt(3.0);
    settings.Problem = Equation::Poisson;
    settings.Sampling = sampling;
    WalkOnSpheresEstimator<3> estimator(boundary, settings, &f);
    RunningStatistics stats(1);
    for (const Vec3& p : points)
    {
      stats.Reset();
      WalkCounters counters;
      estimator.EstimatePoint(p.data(), 900, 0, 1024, stats, counters);
      variance[int(sampling)] += stats.SampleVariance(0) / points.size();
    }
  }
  std::printf("concentrated source, per-walk variance: uniform %.4g, Green's function %.4g, "
              "MIS %.4g; uniform/Green %.2f, MIS/min %.2f\n",
    variance[0], variance[1], variance[2], variance[0] / variance[1],
    variance[2] / std::min(variance[0], variance[1]));
  EXPECT_LT(variance[1], variance[0]);
  EXPECT_LT(variance[2], 2.0 * std::min(variance[0], variance[1]));
}
