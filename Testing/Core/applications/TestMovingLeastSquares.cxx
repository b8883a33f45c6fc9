#include <gridfree/applications/MovingLeastSquares.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using gridfree::MlsNeighbours;
using gridfree::MlsSettings;
using gridfree::MovingLeastSquares;
using gridfree::Vec;

namespace
{
// A quadratic in 3D with all ten terms, and its gradient.
double Quadratic(const Vec<3>& p)
{
  return 0.5 + 2.0 * p[0] - p[1] + 0.25 * p[2] + 1.5 * p[0] * p[0] - 0.7 * p[0] * p[1] +
    0.3 * p[1] * p[2] + 0.9 * p[2] * p[2] - 0.4 * p[1] * p[1] + 0.6 * p[0] * p[2];
}

Vec<3> QuadraticGradient(const Vec<3>& p)
{
  return Vec<3>(2.0 + 3.0 * p[0] - 0.7 * p[1] + 0.6 * p[2],
    -1.0 - 0.7 * p[0] + 0.3 * p[2] - 0.8 * p[1], 0.25 + 0.3 * p[1] + 1.8 * p[2] + 0.6 * p[0]);
}

struct Samples
{
  std::vector<Vec<3>> Positions;
  std::vector<double> Values, Gradients;

  MlsNeighbours<3> View(bool withGradients) const
  {
    MlsNeighbours<3> view;
    view.Count = static_cast<int>(this->Positions.size());
    view.Positions = this->Positions.data();
    view.Values = this->Values.data();
    view.Gradients = withGradients ? this->Gradients.data() : nullptr;
    return view;
  }
};

// Samples of Quadratic around `center`; planar (z = center z) if asked.
Samples Sample(const Vec<3>& center, int count, bool planar, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  Samples s;
  for (int i = 0; i < count; ++i)
  {
    Vec<3> p = center + Vec<3>(offset(rng), offset(rng), planar ? 0.0 : offset(rng));
    s.Positions.push_back(p);
    s.Values.push_back(Quadratic(p));
    const Vec<3> g = QuadraticGradient(p);
    s.Gradients.insert(s.Gradients.end(), { g[0], g[1], g[2] });
  }
  return s;
}
} // namespace

TEST(MovingLeastSquares, QuadraticsAreReproducedFromValuesAlone)
{
  const Vec<3> x(0.1, -0.3, 0.2);
  const Samples s = Sample(x, 16, false, 1);
  MovingLeastSquares<3> mls(MlsSettings{}, 1);
  double value, gradient[3];
  ASSERT_TRUE(mls.Fit(x, s.View(false), &value, gradient, nullptr));
  EXPECT_NEAR(value, Quadratic(x), 1e-10);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(gradient[a], QuadraticGradient(x)[a], 1e-8);
  }
}

TEST(MovingLeastSquares, GradientsLetFourSamplesFitAQuadratic)
{
  // Ten unknowns, four samples: only with Hermite rows (4 per sample). Three
  // would not do: gradient differences fix H·d1 and H·d2, and their
  // symmetry d2ᵀ H d1 = d1ᵀ H d2 makes one of those six equations redundant.
  const Vec<3> x(-0.2, 0.4, 0.0);
  const Samples s = Sample(x, 4, false, 2);
  MovingLeastSquares<3> withGradients(MlsSettings{}, 1);
  double value, gradient[3];
  ASSERT_TRUE(withGradients.Fit(x, s.View(true), &value, gradient, nullptr));
  EXPECT_NEAR(value, Quadratic(x), 1e-9);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(gradient[a], QuadraticGradient(x)[a], 1e-7);
  }

  // From the values alone the same four samples cannot fix the quadratic.
  MovingLeastSquares<3> valuesOnly(MlsSettings{}, 1);
  double rough, roughGradient[3];
  ASSERT_TRUE(valuesOnly.Fit(x, s.View(false), &rough, roughGradient, nullptr));
  EXPECT_GT((Vec<3>(roughGradient[0], roughGradient[1], roughGradient[2]) - QuadraticGradient(x))
              .norm(),
    1e-2);
}

TEST(MovingLeastSquares, PlanarSamplesGiveTheInPlaneFunction)
{
  // A slice's samples: the normal curvature is unobservable and must not
  // break the fit (minimum-norm solution), the in-plane values are exact.
  const Vec<3> x(0.3, 0.1, -0.25);
  const Samples s = Sample(x, 12, true, 3);
  for (bool withGradients : { false, true })
  {
    MovingLeastSquares<3> mls(MlsSettings{}, 1);
    double value, gradient[3];
    ASSERT_TRUE(mls.Fit(x, s.View(withGradients), &value, gradient, nullptr));
    EXPECT_NEAR(value, Quadratic(x), 1e-9) << "gradients " << withGradients;
    EXPECT_NEAR(gradient[0], QuadraticGradient(x)[0], 1e-7);
    EXPECT_NEAR(gradient[1], QuadraticGradient(x)[1], 1e-7);
    if (withGradients)
    {
      // The normal derivative is linear in the plane: known from the data.
      EXPECT_NEAR(gradient[2], QuadraticGradient(x)[2], 1e-7);
    }
  }
}

TEST(MovingLeastSquares, DegreeOneReproducesLinearFunctionsIn2D)
{
  std::vector<Vec<2>> positions = { { 0.0, 0.0 }, { 1.0, 0.1 }, { 0.2, 0.9 }, { 0.8, 0.7 } };
  std::vector<double> values;
  for (const auto& p : positions)
  {
    values.push_back(3.0 - 2.0 * p[0] + 0.5 * p[1]);
  }
  MlsNeighbours<2> view;
  view.Count = 4;
  view.Positions = positions.data();
  view.Values = values.data();
  MlsSettings settings;
  settings.Degree = 1;
  MovingLeastSquares<2> mls(settings, 1);
  const Vec<2> x(0.4, 0.45);
  double value, gradient[2];
  ASSERT_TRUE(mls.Fit(x, view, &value, gradient, nullptr));
  EXPECT_NEAR(value, 3.0 - 2.0 * 0.4 + 0.5 * 0.45, 1e-12);
  EXPECT_NEAR(gradient[0], -2.0, 1e-12);
  EXPECT_NEAR(gradient[1], 0.5, 1e-12);
}

TEST(MovingLeastSquares, ReportedVarianceIsTheSpreadOfTheFit)
{
  // Noisy data with known variances, fitted many times: the spread of the
  // fitted value must match the variance the fit reports (z² near 1).
  const Vec<3> x(0.0, 0.0, 0.0);
  const Samples clean = Sample(x, 10, false, 4);
  const int n = static_cast<int>(clean.Positions.size());
  std::vector<double> valueVariance(n), gradientVariance(3 * n);
  for (int i = 0; i < n; ++i)
  {
    valueVariance[i] = 0.01 * (1 + i % 3);
    for (int a = 0; a < 3; ++a)
    {
      gradientVariance[3 * i + a] = 0.2 * (1 + (i + a) % 2);
    }
  }
  MovingLeastSquares<3> mls(MlsSettings{}, 1);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int trials = 4000;
  double sum = 0.0, sumSquares = 0.0, reported = 0.0;
  for (int t = 0; t < trials; ++t)
  {
    Samples noisy = clean;
    for (int i = 0; i < n; ++i)
    {
      noisy.Values[i] += std::sqrt(valueVariance[i]) * normal(rng);
      for (int a = 0; a < 3; ++a)
      {
        noisy.Gradients[3 * i + a] += std::sqrt(gradientVariance[3 * i + a]) * normal(rng);
      }
    }
    MlsNeighbours<3> view = noisy.View(true);
    view.ValueVariances = valueVariance.data();
    view.GradientVariances = gradientVariance.data();
    double value, variance;
    ASSERT_TRUE(mls.Fit(x, view, &value, nullptr, &variance));
    sum += value;
    sumSquares += value * value;
    reported = variance; // the same for every trial: it depends on positions only
  }
  const double mean = sum / trials;
  const double observed = sumSquares / trials - mean * mean;
  // Relative standard error of a variance from 4000 normal draws: about 2.2%.
  EXPECT_NEAR(observed / reported, 1.0, 0.1);
  EXPECT_NEAR(mean, Quadratic(x), 5.0 * std::sqrt(reported / trials));
}

TEST(MovingLeastSquares, NoNeighbourGivesNaN)
{
  MovingLeastSquares<3> mls(MlsSettings{}, 2);
  MlsNeighbours<3> empty;
  double value[2], gradient[6], variance[2];
  EXPECT_FALSE(mls.Fit(Vec<3>::Zero(), empty, value, gradient, variance));
  EXPECT_TRUE(std::isnan(value[0]) && std::isnan(value[1]));
  EXPECT_TRUE(std::isnan(gradient[5]) && std::isnan(variance[1]));
}
