// Samplers of the normalized Green's functions (FORMULAS.md §6) and of the
// unit ball: Kolmogorov-Smirnov tests against the radial CDF integrated from
// Value(), importance-sampling identities, and wrong samplers that must fail.
#include <gridfree/sampling/BallSampling.h>
#include <gridfree/greens/GreensFunctions.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

using namespace gridfree;

namespace
{
const int SampleCount = 20000;
// KS critical value at significance 0.001: 1.95/sqrt(N).
const double Critical = 1.95 / std::sqrt(double(SampleCount));

// ∫_a^b h with 8-point Gauss-Legendre.
double Panel(const std::function<double(double)>& h, double a, double b)
{
  static const double nodes[] = { 0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
    0.9602898564975363 };
  static const double weights[] = { 0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
    0.1012285362903763 };
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i)
  {
    sum += weights[i] * (h(mid - half * nodes[i]) + h(mid + half * nodes[i]));
  }
  return half * sum;
}

// ∫_0^b h on geometric panels [b 2^{-k-1}, b 2^{-k}], which follow the log
// and 1/r behaviour of G at the pole and the e^{-sr} peak of large z.
double FromZero(const std::function<double(double)>& h, double b)
{
  double sum = 0.0;
  for (int k = 0; k < 60; ++k)
  {
    sum += Panel(h, 0.5 * b, b);
    b *= 0.5;
  }
  return sum + Panel(h, 0.0, b);
}

// Radial density of SampleRadius, up to normalization: r^{n−1} G(r).
template <int DIM, class Kernel>
std::function<double(double)> RadialWeight(const Kernel& kernel)
{
  return [&kernel](double r) { return std::pow(r, DIM - 1) * kernel.Value(r); };
}

// KS statistic of radii against the CDF ∫_0^r h / ∫_0^R h, integrated piecewise
// between consecutive sorted samples.
double KolmogorovSmirnov(
  std::vector<double> radii, const std::function<double(double)>& h, double radius)
{
  std::sort(radii.begin(), radii.end());
  const double total = FromZero(h, radius);
  const double n = double(radii.size());
  double integral = 0.0;
  double previous = 0.0;
  double statistic = 0.0;
  for (std::size_t i = 0; i < radii.size(); ++i)
  {
    const double r = radii[i];
    integral = r > 2.0 * previous ? FromZero(h, r) : integral + Panel(h, previous, r);
    previous = r;
    const double cdf = integral / total;
    statistic = std::max({ statistic, (i + 1) / n - cdf, cdf - i / n });
  }
  return statistic;
}

std::vector<double> Draw(const std::function<double(RandomStream&)>& sampler, std::uint64_t seed)
{
  RandomStream rng(seed, 0);
  std::vector<double> values(SampleCount);
  for (double& v : values)
  {
    v = sampler(rng);
  }
  return values;
}

// Radii of a uniform point in the ball, a deliberately wrong sampler.
template <int DIM>
std::function<double(RandomStream&)> UniformInBallRadius(double radius)
{
  return [radius](RandomStream& rng) { return radius * SampleUnitBall<DIM>(rng).norm(); };
}

struct MeanEstimate
{
  double Mean = 0.0;
  double StandardError = 0.0;
};

MeanEstimate Estimate(const std::vector<double>& values)
{
  double sum = 0.0, squares = 0.0;
  for (const double v : values)
  {
    sum += v;
    squares += v * v;
  }
  const double n = double(values.size());
  const double mean = sum / n;
  return { mean, std::sqrt(std::max(0.0, squares / n - mean * mean) / (n - 1.0)) };
}

// SampleOffset d against two identities with finite variance:
//   E[Integral·f(d)] = ∫_B f G for f = 1 + a·d + (b·d)², where
//     ∫_B f G = Integral + |b|²/n · |S|∫ r^{n+1} G dr (odd part vanishes);
//   E[w(d)/Density(|d|)] = ∫_B w = |B|·2/(n+2) for w = 1 − |d|²/R².
// (w = 1 gives E[1/Density] = |B|, but 1/G ~ 1/(R − r) makes its variance
// diverge logarithmically, so its standard error would not mean anything.)
// The second identity is only informative for small z: its variance grows
// like e^{z}, as samples concentrate within ~1/s of the pole.
template <int DIM, class Kernel>
void CheckOffsets(const Kernel& kernel, std::uint64_t seed, bool checkVolume)
{
  const double radius = kernel.Radius();
  const Vec<DIM> a = Vec<DIM>::LinSpaced(0.5, 1.5) / radius;
  const Vec<DIM> b = Vec<DIM>::LinSpaced(1.0, -0.5) / radius;
  RandomStream rng(seed, 1);
  std::vector<double> source(SampleCount), volume(SampleCount);
  for (int i = 0; i < SampleCount; ++i)
  {
    const Vec<DIM> d = kernel.SampleOffset(rng);
    const double r = d.norm();
    ASSERT_TRUE(r > 0.0 && r < radius);
    const double bd = b.dot(d);
    source[i] = kernel.Integral() * (1.0 + a.dot(d) + bd * bd);
    volume[i] = (1.0 - r * r / (radius * radius)) / kernel.Density(r);
  }
  const std::function<double(double)> second = [&kernel](double r) {
    return std::pow(r, DIM + 1) * kernel.Value(r);
  };
  const double exactSource =
    kernel.Integral() + b.squaredNorm() / DIM * UnitSphereArea<DIM>() * FromZero(second, radius);
  const MeanEstimate s = Estimate(source);
  EXPECT_LT(std::abs(s.Mean - exactSource), 5.0 * s.StandardError);
  // The estimates are not vacuous: 5 standard errors are a few percent at most.
  EXPECT_LT(5.0 * s.StandardError, 0.05 * exactSource);
  if (checkVolume)
  {
    const double exactVolume = UnitBallVolume<DIM>() * std::pow(radius, DIM) * 2.0 / (DIM + 2.0);
    const MeanEstimate v = Estimate(volume);
    EXPECT_LT(std::abs(v.Mean - exactVolume), 5.0 * v.StandardError);
    EXPECT_LT(5.0 * v.StandardError, 0.05 * exactVolume);
  }
}

template <int DIM>
void CheckHarmonicSampling()
{
  const double radius = 1.3;
  const HarmonicGreensFunction<DIM> g(radius);
  const auto h = RadialWeight<DIM>(g);
  const double statistic =
    KolmogorovSmirnov(Draw([&g](RandomStream& rng) { return g.SampleRadius(rng); }, 11), h, radius);
  EXPECT_LT(statistic, Critical);
  EXPECT_GT(
    KolmogorovSmirnov(Draw(UniformInBallRadius<DIM>(radius), 11), h, radius), 5.0 * Critical);
  // The normalization the CDF uses is Integral() itself.
  EXPECT_NEAR(UnitSphereArea<DIM>() * FromZero(h, radius) / g.Integral(), 1.0, 1e-12);
  CheckOffsets<DIM>(g, 12, true);
}

template <int DIM>
void CheckYukawaSampling()
{
  const double radius = 1.3;
  for (const double z : { 0.5, 1.4, 3.0, 11.0, 50.0, 800.0 })
  {
    SCOPED_TRACE(::testing::Message() << "z = " << z);
    const double c = (z / radius) * (z / radius);
    const YukawaGreensFunction<DIM> g(radius, c);
    const auto h = RadialWeight<DIM>(g);
    const auto seed = std::uint64_t(z * 10.0);
    const double statistic = KolmogorovSmirnov(
      Draw([&g](RandomStream& rng) { return g.SampleRadius(rng); }, seed), h, radius);
    EXPECT_LT(statistic, Critical);
    EXPECT_GT(KolmogorovSmirnov(Draw(UniformInBallRadius<DIM>(radius), seed), h, radius), Critical);
    if (z >= 3.0)
    {
      // The harmonic proposal without its rejection step is detectably wrong.
      const HarmonicGreensFunction<DIM> harmonic(radius);
      EXPECT_GT(KolmogorovSmirnov(
                  Draw([&harmonic](RandomStream& rng) { return harmonic.SampleRadius(rng); }, seed),
                  h, radius),
        Critical);
    }
    // 8-point panels: looser than the 16-point check in TestGreensFunctions.
    EXPECT_NEAR(UnitSphereArea<DIM>() * FromZero(h, radius) / g.Integral(), 1.0, 1e-10);
    CheckOffsets<DIM>(g, seed + 1, z <= 3.0);
  }
}
} // namespace

TEST(GreensFunctionSampling, HarmonicRadiusAndOffsets2D)
{
  CheckHarmonicSampling<2>();
}

TEST(GreensFunctionSampling, HarmonicRadiusAndOffsets3D)
{
  CheckHarmonicSampling<3>();
}

TEST(GreensFunctionSampling, YukawaRadiusAndOffsets2D)
{
  CheckYukawaSampling<2>();
}

TEST(GreensFunctionSampling, YukawaRadiusAndOffsets3D)
{
  CheckYukawaSampling<3>();
}

namespace
{
template <int DIM>
void CheckUnitBall()
{
  RandomStream rng(3, 0);
  std::vector<double> volumeFraction(SampleCount), wrong(SampleCount);
  Vec<DIM> sum = Vec<DIM>::Zero();
  for (int i = 0; i < SampleCount; ++i)
  {
    const Vec<DIM> p = SampleUnitBall<DIM>(rng);
    ASSERT_LT(p.norm(), 1.0);
    sum += p;
    volumeFraction[i] = std::pow(p.norm(), DIM);
    wrong[i] = std::pow(SampleUnitSphere<DIM>(rng).norm() * rng.NextDouble(), DIM);
  }
  // |p|^n is uniform on [0, 1) for a uniform point in the unit ball.
  const std::function<double(double)> uniform = [](double) { return 1.0; };
  EXPECT_LT(KolmogorovSmirnov(volumeFraction, uniform, 1.0), Critical);
  EXPECT_GT(KolmogorovSmirnov(wrong, uniform, 1.0), 5.0 * Critical);
  // E[p] = 0 with per-component variance E|p|²/n = 1/(n + 2).
  const double standardError = std::sqrt(1.0 / (DIM + 2.0) / SampleCount);
  for (int i = 0; i < DIM; ++i)
  {
    EXPECT_LT(std::abs(sum[i] / SampleCount), 5.0 * standardError);
  }
  EXPECT_DOUBLE_EQ(UnitBallVolume<DIM>(), DIM == 2 ? M_PI : 4.0 * M_PI / 3.0);
  EXPECT_DOUBLE_EQ(UnitSphereArea<DIM>(), DIM == 2 ? 2.0 * M_PI : 4.0 * M_PI);
}
} // namespace

TEST(BallSampling, UniformInUnitBall2D)
{
  CheckUnitBall<2>();
}

TEST(BallSampling, UniformInUnitBall3D)
{
  CheckUnitBall<3>();
}

namespace
{
// A ball whose radius or coefficient is NaN or infinite (a walk whose
// position overflowed) fails every acceptance test of the rejection
// sampler: it must give up with a NaN radius, never loop forever.
template <int DIM>
void CheckInvalidBallsEnd()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::pair<double, double> cases[] = { { nan, 1.0 }, { 1.0, nan }, { nan, nan },
    { inf, 1.0 }, { inf, inf }, { 1.0, inf } };
  RandomStream rng(5, 0);
  for (const auto& c : cases)
  {
    const YukawaGreensFunction<DIM> g(c.first, c.second);
    for (int i = 0; i < 100; ++i)
    {
      // Returning at all is the test (a hang fails by ctest's timeout); a
      // NaN radius cannot give a radius in a ball.
      const double r = g.SampleRadius(rng);
      if (std::isnan(c.first))
      {
        EXPECT_TRUE(std::isnan(r)) << "R " << c.first << " c " << c.second << " r " << r;
      }
    }
  }
  // A valid ball never hits the cap: 10⁵ draws, all inside the ball.
  const YukawaGreensFunction<DIM> valid(0.5, 3.0);
  for (int i = 0; i < 100000; ++i)
  {
    const double r = valid.SampleRadius(rng);
    ASSERT_TRUE(r > 0.0 && r < 0.5) << r;
  }
}
} // namespace

TEST(GreensFunctionSampling, InvalidBallsEndWithNaN2D)
{
  CheckInvalidBallsEnd<2>();
}

TEST(GreensFunctionSampling, InvalidBallsEndWithNaN3D)
{
  CheckInvalidBallsEnd<3>();
}
