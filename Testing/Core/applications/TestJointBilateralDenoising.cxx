#include <gridfree/applications/JointBilateralDenoising.h>

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using gridfree::DenoiseInput;
using gridfree::DenoiseSettings;

namespace
{
// Standard normal numbers from mt19937_64 by Box–Muller: unlike those of
// std::normal_distribution, whose method each standard library chooses, the
// same numbers everywhere (up to the last bits of log and cos).
class Normal
{
public:
  explicit Normal(std::uint64_t seed)
    : Engine(seed)
  {
  }
  double operator()()
  {
    const double u1 = this->Uniform();
    const double u2 = this->Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

private:
  // In (0, 1): never 0, so the logarithm is finite.
  double Uniform() { return (static_cast<double>(this->Engine() >> 11) + 0.5) * 0x1.0p-53; }
  std::mt19937_64 Engine;
};

// An n × n grid of unit spacing, point (x, y) at index y * n + x, and its
// neighbours within `radius` listed row by row.
struct Grid
{
  int N;
  double Radius;

  std::size_t Count() const { return static_cast<std::size_t>(this->N) * this->N; }
  int X(std::size_t i) const { return static_cast<int>(i % this->N); }
  int Y(std::size_t i) const { return static_cast<int>(i / this->N); }

  template <class Visit>
  void operator()(std::size_t i, const Visit& visit) const
  {
    const int r = static_cast<int>(this->Radius);
    const int x = this->X(i), y = this->Y(i);
    for (int dy = -r; dy <= r; ++dy)
    {
      for (int dx = -r; dx <= r; ++dx)
      {
        const int xj = x + dx, yj = y + dy;
        const double d2 = dx * dx + dy * dy;
        if (xj >= 0 && xj < this->N && yj >= 0 && yj < this->N && d2 <= this->Radius * this->Radius)
        {
          visit(static_cast<std::size_t>(yj) * this->N + xj, d2);
        }
      }
    }
  }
};

DenoiseSettings GridSettings(double sigma, double guideSigma = 0.0, double varianceScale = 1.0)
{
  DenoiseSettings s;
  s.SpatialSigma = sigma;
  s.NeighbourRadius = gridfree::kDenoiseRadiusInSigmas * sigma;
  s.VarianceScale = varianceScale;
  s.GuideSigma = guideSigma;
  return s;
}

struct Result
{
  std::vector<double> Values;
  std::vector<double> Variances;
};

Result Denoise(const Grid& grid, const std::vector<double>& values,
  const std::vector<double>* variances, const std::vector<double>* guide,
  const DenoiseSettings& settings)
{
  DenoiseInput in;
  in.Count = grid.Count();
  in.Components = 1;
  in.Values = values.data();
  in.Variances = variances ? variances->data() : nullptr;
  in.GuideComponents = guide ? 1 : 0;
  in.Guide = guide ? guide->data() : nullptr;
  Result out{ std::vector<double>(values.size()), std::vector<double>(values.size()) };
  gridfree::JointBilateralDenoise(in, settings, grid, out.Values.data(), out.Variances.data());
  return out;
}

double Rmse(const std::vector<double>& a, const std::vector<double>& b)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    sum += (a[i] - b[i]) * (a[i] - b[i]);
  }
  return std::sqrt(sum / a.size());
}

// A smooth field on a 64 × 64 grid with Gaussian noise of standard
// deviation `sigma` and its (exact) variance.
struct NoisyField
{
  Grid G{ 64, 5.0 };
  std::vector<double> Exact, Noisy, Variance;

  NoisyField(double sigma, std::uint64_t seed)
  {
    Normal normal(seed);
    for (std::size_t i = 0; i < this->G.Count(); ++i)
    {
      const double x = this->G.X(i), y = this->G.Y(i);
      this->Exact.push_back(std::sin(x / 20.0) * std::cos(y / 25.0) + 0.01 * x);
      this->Noisy.push_back(this->Exact.back() + sigma * normal());
      this->Variance.push_back(sigma * sigma);
    }
  }
};
} // namespace

// Two points by hand: the weight is the product of the three terms of the
// header, and the result the weighted mean with its fixed-weight variance.
TEST(JointBilateralDenoising, TwoPointsFollowTheFormula)
{
  const double u[2] = { 1.0, 1.5 }, v[2] = { 0.04, 0.09 }, a[2] = { 0.2, 0.25 };
  const double d2 = 0.7 * 0.7;
  DenoiseSettings s;
  s.SpatialSigma = 0.5;
  s.VarianceScale = 1.5;
  s.GuideSigma = 0.1;
  DenoiseInput in;
  in.Count = 2;
  in.Values = u;
  in.Variances = v;
  in.GuideComponents = 1;
  in.Guide = a;
  auto pair = [&](std::size_t i, const auto& visit) { visit(1 - i, d2); };
  double value[2], variance[2];
  gridfree::JointBilateralDenoise(in, s, pair, value, variance);

  const double range = ((u[0] - u[1]) * (u[0] - u[1]) - (v[0] + std::min(v[0], v[1]))) /
    (s.VarianceScale * s.VarianceScale * (v[0] + v[1]));
  const double w = std::exp(-d2 / (2 * 0.25)) * std::exp(-0.05 * 0.05 / (2 * 0.01)) *
    std::exp(-std::max(0.0, range));
  EXPECT_NEAR(value[0], (u[0] + w * u[1]) / (1 + w), 1e-14);
  EXPECT_NEAR(variance[0], (v[0] + w * w * v[1]) / ((1 + w) * (1 + w)), 1e-15);
  // Seen from point 1 the subtracted variance is v1 + min(v0, v1): another
  // weight, so the filter is not symmetric.
  const double range1 = ((u[0] - u[1]) * (u[0] - u[1]) - (v[1] + std::min(v[0], v[1]))) /
    (s.VarianceScale * s.VarianceScale * (v[0] + v[1]));
  const double w1 = std::exp(-d2 / (2 * 0.25)) * std::exp(-0.05 * 0.05 / (2 * 0.01)) *
    std::exp(-std::max(0.0, range1));
  EXPECT_NEAR(value[1], (u[1] + w1 * u[0]) / (1 + w1), 1e-14);
}

// The noise of a smooth field falls: the error against the noise-free field
// is at most half the input's. k = 2: the range distance of single points is
// as noisy as they are, and with k = 1 it keeps much of a point's own noise
// (it favours the neighbours that happen to be close to it).
TEST(JointBilateralDenoising, SmoothFieldErrorAtLeastHalves)
{
  const double sigma = 0.1;
  NoisyField f(sigma, 2020);
  const Result out = Denoise(f.G, f.Noisy, &f.Variance, nullptr, GridSettings(2.0, 0.0, 2.0));
  const double before = Rmse(f.Noisy, f.Exact);
  const double after = Rmse(out.Values, f.Exact);
  EXPECT_NEAR(before, sigma, 0.05 * sigma);
  EXPECT_LE(after, 0.5 * before);
}

// With weights that do not depend on the noise (the range term made
// negligible by a huge k) the filter is linear, and the propagated variance
// is the variance of the noise it lets through: the difference between the
// filtered noisy field and the filtered exact one.
TEST(JointBilateralDenoising, PropagatedVarianceIsTheNoiseLeft)
{
  const double sigma = 0.1;
  NoisyField f(sigma, 2021);
  const DenoiseSettings linear = GridSettings(2.0, 0.0, 1e3);
  const Result noisy = Denoise(f.G, f.Noisy, &f.Variance, nullptr, linear);
  const Result exact = Denoise(f.G, f.Exact, &f.Variance, nullptr, linear);
  double noiseLeft = 0.0, meanVariance = 0.0;
  const double n = static_cast<double>(f.G.Count());
  for (std::size_t i = 0; i < f.G.Count(); ++i)
  {
    noiseLeft += (noisy.Values[i] - exact.Values[i]) * (noisy.Values[i] - exact.Values[i]) / n;
    meanVariance += noisy.Variances[i] / n;
  }
  EXPECT_LT(meanVariance, 0.05 * sigma * sigma);
  EXPECT_GT(noiseLeft, 0.8 * meanVariance);
  EXPECT_LT(noiseLeft, 1.25 * meanVariance);
}

// A step in the guide (0 left, 1 right) with a value step of 10 under noise
// of standard deviation 5: too noisy for the range term alone (k = 2) to see
// the edge, which the guide keeps sharp.
TEST(JointBilateralDenoising, GuideKeepsAStepEdge)
{
  const Grid g{ 48, 5.0 };
  const double sigma = 5.0, step = 10.0;
  Normal normal(7);
  std::vector<double> exact, noisy, variance, guide;
  for (std::size_t i = 0; i < g.Count(); ++i)
  {
    const bool right = g.X(i) >= 24;
    guide.push_back(right ? 1.0 : 0.0);
    exact.push_back(right ? step : 0.0);
    noisy.push_back(exact.back() + sigma * normal());
    variance.push_back(sigma * sigma);
  }
  const Result guided = Denoise(g, noisy, &variance, &guide, GridSettings(2.0, 0.1, 2.0));
  const Result unguided = Denoise(g, noisy, &variance, &guide, GridSettings(2.0, 0.0, 2.0));

  // Mean error and root mean square error of the column x on either side of
  // the edge.
  auto columnError = [&](const Result& r, int x, double& mean, double& rms) {
    mean = rms = 0.0;
    for (int y = 0; y < g.N; ++y)
    {
      const std::size_t i = static_cast<std::size_t>(y) * g.N + x;
      mean += (r.Values[i] - exact[i]) / g.N;
      rms += (r.Values[i] - exact[i]) * (r.Values[i] - exact[i]) / g.N;
    }
    rms = std::sqrt(rms);
  };
  for (int x : { 23, 24 })
  {
    double guidedMean, guidedRms, unguidedMean, unguidedRms;
    columnError(guided, x, guidedMean, guidedRms);
    columnError(unguided, x, unguidedMean, unguidedRms);
    // Guided: no bias beyond the noise left, and well below the input noise.
    EXPECT_LT(std::abs(guidedMean), 0.1 * step) << "column " << x;
    EXPECT_LT(guidedRms, 0.4 * sigma) << "column " << x;
    // Unguided: the two sides bleed into each other.
    EXPECT_GT(std::abs(unguidedMean), 0.2 * step) << "column " << x;
    EXPECT_GT(unguidedRms, 1.5 * guidedRms) << "column " << x;
  }
}

// Zero variance means exact values: neighbours with other values are
// excluded and equal ones leave the value as it is, so nothing changes, bit
// for bit, and the variance stays 0.
TEST(JointBilateralDenoising, ExactValuesAreKept)
{
  const Grid g{ 20, 5.0 };
  std::vector<double> values, variance(g.Count(), 0.0);
  for (std::size_t i = 0; i < g.Count(); ++i)
  {
    // A plateau of 0.1 (not exactly representable: a plain weighted mean
    // would round) next to a ramp of values that all differ.
    values.push_back(g.X(i) < 10 ? 0.1 : 0.1 + 1e-6 * static_cast<double>(i));
  }
  const Result out = Denoise(g, values, &variance, nullptr, GridSettings(3.0));
  for (std::size_t i = 0; i < g.Count(); ++i)
  {
    EXPECT_EQ(out.Values[i], values[i]) << i;
    EXPECT_EQ(out.Variances[i], 0.0) << i;
  }
}

// Without variances there is no range term: a plain (guided) Gaussian
// filter, whose output variance is unknown.
TEST(JointBilateralDenoising, NoVariancesMeansNoRangeTerm)
{
  const Grid g{ 16, 5.0 };
  std::vector<double> values;
  for (std::size_t i = 0; i < g.Count(); ++i)
  {
    values.push_back(g.X(i) < 8 ? 0.0 : 1000.0); // an edge the range term would keep
  }
  const Result out = Denoise(g, values, nullptr, nullptr, GridSettings(2.0));
  const std::size_t left = 3 * g.N + 7, right = 3 * g.N + 8;
  EXPECT_GT(out.Values[left], 100.0);
  EXPECT_LT(out.Values[right], 900.0);
  EXPECT_TRUE(std::isnan(out.Variances[left]));
}

// NaN or infinite values and NaN or negative variances stay where they are:
// such a point keeps its input, and its neighbours come out bit for bit as
// if it did not exist.
TEST(JointBilateralDenoising, BadEstimatesStayLocal)
{
  NoisyField f(0.1, 3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t nanValue = 10 * 64 + 10, infValue = 30 * 64 + 31, nanVariance = 50 * 64 + 5,
                    negativeVariance = 20 * 64 + 40;
  std::vector<double> values = f.Noisy, variances = f.Variance;
  values[nanValue] = nan;
  values[infValue] = std::numeric_limits<double>::infinity();
  variances[nanVariance] = nan;
  variances[negativeVariance] = -1.0;
  const std::vector<std::size_t> bad = { nanValue, infValue, nanVariance, negativeVariance };
  auto isBad = [&](std::size_t j) { return std::find(bad.begin(), bad.end(), j) != bad.end(); };

  const Result out = Denoise(f.G, values, &variances, nullptr, GridSettings(2.0));
  // The same without the bad points in anybody's neighbourhood.
  auto withoutBad = [&](std::size_t i, const auto& visit) {
    f.G(i, [&](std::size_t j, double d2) {
      if (!isBad(j))
      {
        visit(j, d2);
      }
    });
  };
  DenoiseInput in;
  in.Count = f.G.Count();
  in.Values = values.data();
  in.Variances = variances.data();
  std::vector<double> reference(in.Count), referenceVariance(in.Count);
  gridfree::JointBilateralDenoise(
    in, GridSettings(2.0), withoutBad, reference.data(), referenceVariance.data());

  EXPECT_TRUE(std::isnan(out.Values[nanValue]));
  EXPECT_TRUE(std::isinf(out.Values[infValue]));
  EXPECT_EQ(out.Values[nanVariance], values[nanVariance]);
  EXPECT_TRUE(std::isnan(out.Variances[nanVariance]));
  EXPECT_EQ(out.Values[negativeVariance], values[negativeVariance]);
  EXPECT_EQ(out.Variances[negativeVariance], -1.0);
  for (std::size_t i = 0; i < in.Count; ++i)
  {
    if (!isBad(i))
    {
      ASSERT_TRUE(std::isfinite(out.Values[i])) << i;
      ASSERT_EQ(out.Values[i], reference[i]) << i;
      ASSERT_EQ(out.Variances[i], referenceVariance[i]) << i;
    }
  }
}

// A multi-component value averages the components' range distances: one
// component's edge stops the averaging of all of them.
TEST(JointBilateralDenoising, ComponentsShareTheirWeights)
{
  const Grid g{ 16, 5.0 };
  std::vector<double> values, variances;
  for (std::size_t i = 0; i < g.Count(); ++i)
  {
    values.push_back(1.0);                      // flat
    values.push_back(g.X(i) < 8 ? 0.0 : 100.0); // a sharp edge
    variances.push_back(0.01);
    variances.push_back(0.01);
  }
  DenoiseInput in;
  in.Count = g.Count();
  in.Components = 2;
  in.Values = values.data();
  in.Variances = variances.data();
  std::vector<double> out(values.size()), outVariance(values.size());
  gridfree::JointBilateralDenoise(in, GridSettings(2.0), g, out.data(), outVariance.data());
  const std::size_t edge = 8 * g.N + 7; // left of the edge
  EXPECT_EQ(out[2 * edge + 1], 0.0);
  // The flat component averaged only over the left side's points: its
  // variance fell, but less than at a point with more of them around.
  const std::size_t centre = 8 * g.N + 3;
  EXPECT_LT(outVariance[2 * edge], 0.5 * 0.01);
  EXPECT_GT(outVariance[2 * edge], outVariance[2 * centre]);
}

// Every point is computed on its own: one or two threads give the same bits.
TEST(JointBilateralDenoising, SameResultForAnyThreadCount)
{
  NoisyField f(0.2, 11);
  std::vector<double> guide;
  for (std::size_t i = 0; i < f.G.Count(); ++i)
  {
    guide.push_back(f.G.X(i) < 40 ? 0.0 : 1.0);
  }
  Result one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = Denoise(f.G, f.Noisy, &f.Variance, &guide, GridSettings(2.0, 0.2));
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = Denoise(f.G, f.Noisy, &f.Variance, &guide, GridSettings(2.0, 0.2));
  }
  EXPECT_EQ(one.Values, two.Values);
  EXPECT_EQ(one.Variances, two.Variances);
}

// Degenerate settings give no smoothing instead of 0/0: σs = 0 keeps only
// the point itself, and an empty input is fine.
TEST(JointBilateralDenoising, DegenerateSettingsAreSafe)
{
  NoisyField f(0.1, 5);
  const Result out = Denoise(f.G, f.Noisy, &f.Variance, nullptr, GridSettings(0.0));
  EXPECT_EQ(out.Values, f.Noisy);
  EXPECT_EQ(out.Variances, f.Variance);

  DenoiseInput empty;
  gridfree::JointBilateralDenoise(
    empty, DenoiseSettings(), [](std::size_t, const auto&) {}, nullptr, nullptr);
}
