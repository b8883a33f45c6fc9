#include <gridfree/applications/AdaptiveSamplingRounds.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

using gridfree::AdaptiveSamples;
using gridfree::AdaptiveSamplingEnd;
using gridfree::AdaptiveSamplingSettings;
using gridfree::Point3;
using gridfree::SampleAdaptively;
using gridfree::SampleBatch;

namespace
{
std::vector<Point3> RoundsGrid(int n)
{
  std::vector<Point3> points;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      points.push_back({ i / double(n - 1), j / double(n - 1), 0.25 });
    }
  }
  return points;
}

double RoundsDistance2(const Point3& a, const Point3& b)
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]);
}

// The k nearest samples by brute force (ties: lower index), all visible.
struct NearestSamples
{
  struct Scratch
  {
  };
  std::vector<Point3> Samples;
  int Rounds = 0;
  void SetSamples(const std::vector<Point3>& samples)
  {
    this->Samples = samples;
    ++this->Rounds;
  }
  void Find(const Point3& x, int k, Scratch&, std::vector<std::size_t>& ids) const
  {
    ids.resize(this->Samples.size());
    std::iota(ids.begin(), ids.end(), std::size_t(0));
    std::stable_sort(ids.begin(), ids.end(), [&](std::size_t a, std::size_t b) {
      return RoundsDistance2(x, this->Samples[a]) < RoundsDistance2(x, this->Samples[b]);
    });
    ids.resize(std::min<std::size_t>(ids.size(), static_cast<std::size_t>(k)));
  }
};

// Exact u and ∇u (zero variances) at the candidates asked for.
template <class Field>
auto ExactEstimate(const std::vector<Point3>& candidates, Field field, int& batches)
{
  return [&candidates, field, &batches](const std::vector<std::size_t>& ids, SampleBatch& batch) {
    ++batches;
    batch = SampleBatch();
    batch.Components = 1;
    for (std::size_t id : ids)
    {
      double u = 0.0;
      std::array<double, 3> g = { 0.0, 0.0, 0.0 };
      field(candidates[id], u, g);
      batch.Values.push_back(u);
      batch.ValueVariances.push_back(0.0);
      for (int a = 0; a < 3; ++a)
      {
        batch.Gradients.push_back(g[a]);
        batch.GradientVariances.push_back(0.0);
      }
    }
    return true;
  };
}

auto keepGoing = [](double) { return true; };

// u = |x − 0.5|, a kink along x = 0.5.
void Kink(const Point3& x, double& u, std::array<double, 3>& g)
{
  u = std::abs(x[0] - 0.5);
  g = { x[0] >= 0.5 ? 1.0 : -1.0, 0.0, 0.0 };
}
} // namespace

// A linear u is predicted exactly by every neighbour: no round adds a
// sample, and the first ones are the spread subset.
TEST(AdaptiveSamplingRounds, LinearFieldNeedsNoRefinement)
{
  const std::vector<Point3> candidates = RoundsGrid(40);
  int batches = 0;
  auto estimate = ExactEstimate(
    candidates,
    [](const Point3& x, double& u, std::array<double, 3>& g) {
      u = 2.0 * x[0] - x[1];
      g = { 2.0, -1.0, 0.0 };
    },
    batches);
  NearestSamples neighbours;
  AdaptiveSamplingSettings settings;
  settings.InitialSamples = 49;
  settings.MaximumSamples = 400;
  AdaptiveSamples samples;
  EXPECT_EQ(SampleAdaptively(candidates, settings, estimate, neighbours, keepGoing, samples),
    AdaptiveSamplingEnd::Done);
  EXPECT_EQ(samples.RoundsDone, 0);
  EXPECT_EQ(batches, 1);
  EXPECT_EQ(samples.Size(), gridfree::SpreadSubset(candidates, 49).size());
}

// A kink (u = |x − 0.5|) is where the predictions disagree: the refined
// samples gather along it, never twice at one candidate, within the budget.
TEST(AdaptiveSamplingRounds, RefinesAlongAKink)
{
  const std::vector<Point3> candidates = RoundsGrid(61);
  int batches = 0;
  auto estimate = ExactEstimate(
    candidates,
    Kink,
    batches);
  NearestSamples neighbours;
  AdaptiveSamplingSettings settings;
  settings.InitialSamples = 36;
  settings.MaximumSamples = 300;
  settings.Threshold = 0.01;
  settings.MaximumRounds = 6;
  AdaptiveSamples samples;
  EXPECT_EQ(SampleAdaptively(candidates, settings, estimate, neighbours, keepGoing, samples),
    AdaptiveSamplingEnd::Done);
  EXPECT_GE(samples.RoundsDone, 3);
  EXPECT_LE(samples.Size(), 300u);
  EXPECT_EQ(batches, 1 + samples.RoundsDone);
  // One neighbour search per round, and one more for a round that found
  // nothing left to refine.
  EXPECT_GE(neighbours.Rounds, samples.RoundsDone);
  EXPECT_LE(neighbours.Rounds, samples.RoundsDone + 1);
  std::size_t refined = 0;
  double late = 0.0, lateOffset = 0.0;
  for (std::size_t s = 0; s < samples.Size(); ++s)
  {
    if (samples.Rounds[s] > 0)
    {
      ++refined;
      // The first rounds' neighbourhoods straddle the kink from afar (eight
      // neighbours among 36 samples); later rounds close in on it.
      const double offset = std::abs(samples.Positions[s][0] - 0.5);
      if (samples.Rounds[s] >= 3)
      {
        EXPECT_LT(offset, 0.15) << "sample " << s;
        late += 1.0;
        lateOffset += offset;
      }
      EXPECT_GT(samples.Scores[s], 1.0);
      // Never two samples of one candidate.
      EXPECT_EQ(std::count(samples.CandidateIds.begin(), samples.CandidateIds.end(),
                  samples.CandidateIds[s]),
        1);
    }
    else
    {
      EXPECT_TRUE(std::isnan(samples.Scores[s]));
    }
  }
  EXPECT_GT(refined, 20u);
  ASSERT_GT(late, 0.0);
  EXPECT_LT(lateOffset / late, 0.1);
}

// Stops: a failed first batch adds nothing; an abort before a round keeps
// the samples so far; no finite candidate is said.
TEST(AdaptiveSamplingRounds, Stops)
{
  const std::vector<Point3> candidates = RoundsGrid(20);
  NearestSamples neighbours;
  AdaptiveSamplingSettings settings;
  AdaptiveSamples samples;
  auto failing = [](const std::vector<std::size_t>&, SampleBatch&) { return false; };
  EXPECT_EQ(SampleAdaptively(candidates, settings, failing, neighbours, keepGoing, samples),
    AdaptiveSamplingEnd::StoppedAtFirst);
  EXPECT_EQ(samples.Size(), 0u);

  int batches = 0;
  auto kink = ExactEstimate(
    candidates,
    Kink,
    batches);
  auto never = [](double) { return false; };
  settings.InitialSamples = 16;
  EXPECT_EQ(SampleAdaptively(candidates, settings, kink, neighbours, never, samples),
    AdaptiveSamplingEnd::Stopped);
  EXPECT_EQ(samples.Size(), gridfree::SpreadSubset(candidates, 16).size());

  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(SampleAdaptively(std::vector<Point3>{ { nan, 0.0, 0.0 } }, settings, kink, neighbours,
              keepGoing, samples),
    AdaptiveSamplingEnd::NoFiniteCandidate);
}

// The candidate grid finds exactly the points within a radius (distance² ≤
// radius²), on a plane and in a volume, including radius 0.
TEST(AdaptiveSamplingRounds, CandidateGridMatchesBruteForce)
{
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (bool flat : { true, false })
  {
    std::vector<Point3> points(2000);
    for (Point3& p : points)
    {
      p = { unit(random), unit(random), flat ? 0.5 : unit(random) };
    }
    points.push_back(points[7]); // a duplicate
    const gridfree::detail::CandidateGrid grid(points);
    for (int q = 0; q < 200; ++q)
    {
      const Point3& x = points[static_cast<std::size_t>(q) * 10];
      const double radius = q % 5 == 0 ? 0.0 : 0.4 * std::abs(unit(random));
      std::vector<std::size_t> found;
      grid.WithinRadius(x, radius, [&found](std::size_t i) { found.push_back(i); });
      std::sort(found.begin(), found.end());
      std::vector<std::size_t> expected;
      for (std::size_t i = 0; i < points.size(); ++i)
      {
        if (RoundsDistance2(points[i], x) <= radius * radius)
        {
          expected.push_back(i);
        }
      }
      EXPECT_EQ(found, expected) << "query " << q << (flat ? " (flat)" : "");
    }
  }
}
