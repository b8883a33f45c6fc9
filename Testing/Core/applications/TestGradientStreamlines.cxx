#include <gridfree/applications/GradientStreamlines.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using gridfree::StreamEnd;
using gridfree::StreamEstimate;
using gridfree::StreamIntegrator;
using gridfree::Streamline;
using gridfree::StreamlineSettings;
using gridfree::StreamPoint;
using gridfree::TraceGradientStreamlines;

namespace
{
// Exact estimates of u inside the unit ball (ε = 1e-3), one batch at a time.
template <class Gradient>
struct ExactBall
{
  Gradient Of;
  int Batches = 0;
  bool operator()(const std::vector<StreamPoint>& points, std::vector<StreamEstimate>& out)
  {
    ++this->Batches;
    out.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const StreamPoint& p = points[i];
      StreamEstimate& e = out[i];
      e.Value = 0.0;
      e.Gradient = this->Of(p);
      e.Distance = 1.0 - std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      e.NearBoundary = e.Distance < 1e-3;
      e.Valid = true;
    }
    return true;
  }
};

template <class Gradient>
ExactBall<Gradient> Exact(Gradient of)
{
  return ExactBall<Gradient>{ of };
}

auto tracing = [](double) { return true; };
} // namespace

// u = x: straight lines both ways to the sphere, ended within ε of it, the
// steps shrinking to half the distance so that no stage leaves the ball.
TEST(GradientStreamlines, StraightLinesEndCloseToTheBoundary)
{
  StreamlineSettings settings;
  settings.StepLength = 0.1;
  settings.MaximumLength = 10.0;
  auto estimate = Exact([](const StreamPoint&) { return StreamPoint{ 1.0, 0.0, 0.0 }; });
  std::vector<Streamline> lines;
  ASSERT_TRUE(TraceGradientStreamlines({ { 0.0, 0.0, 0.0 } }, settings, estimate, tracing, lines));
  ASSERT_EQ(lines.size(), 2u);
  for (const Streamline& line : lines)
  {
    EXPECT_EQ(line.Reason, StreamEnd::CloseToBoundary);
    const StreamPoint& end = line.Points.back();
    EXPECT_NEAR(end[0], line.Sign, 1e-3);
    EXPECT_GT(line.Sign * end[0], 1.0 - 1e-3);
    EXPECT_LT(line.Sign * end[0], 1.0);
    EXPECT_EQ(end[1], 0.0);
    EXPECT_NEAR(line.Length, 1.0, 1e-3);
    EXPECT_EQ(line.Points.size(), line.Estimates.size());
  }
}

// u = (x² − y²)/2: ∇u = (x, −y), whose lines are the hyperbolas xy = c;
// fourth-order steps keep c to 1e-9 along half a unit of length, Heun's to
// a much looser bound, and the line ends at its maximum length.
TEST(GradientStreamlines, HyperbolasKeepTheirInvariant)
{
  for (StreamIntegrator method : { StreamIntegrator::RungeKutta4, StreamIntegrator::Heun })
  {
    StreamlineSettings settings;
    settings.StepLength = 0.01;
    settings.MaximumLength = 0.5;
    settings.Integrator = method;
    settings.Backward = false;
    auto estimate = Exact([](const StreamPoint& p) { return StreamPoint{ p[0], -p[1], 0.0 }; });
    std::vector<Streamline> lines;
    ASSERT_TRUE(
      TraceGradientStreamlines({ { 0.1, 0.5, 0.0 } }, settings, estimate, tracing, lines));
    ASSERT_EQ(lines.size(), 1u);
    const Streamline& line = lines[0];
    EXPECT_EQ(line.Reason, StreamEnd::OutOfLength);
    EXPECT_LE(line.Length, 0.5 * (1.0 + 1e-12));
    EXPECT_GT(line.Length, 0.5 - 0.01);
    double drift = 0.0;
    for (const StreamPoint& p : line.Points)
    {
      drift = std::max(drift, std::abs(p[0] * p[1] - 0.05));
    }
    EXPECT_LT(drift, method == StreamIntegrator::RungeKutta4 ? 1e-9 : 1e-5);
    EXPECT_LT(line.Points.back()[1], 0.3); // up the gradient: y falls as x grows
  }
}

// A zero gradient stagnates at once; points outside the box end the line;
// the direction setting picks the lines.
TEST(GradientStreamlines, EndsAndDirections)
{
  StreamlineSettings settings;
  settings.StepLength = 0.05;
  settings.Forward = false;
  auto flat = Exact([](const StreamPoint&) { return StreamPoint{ 0.0, 0.0, 0.0 }; });
  std::vector<Streamline> lines;
  ASSERT_TRUE(TraceGradientStreamlines(
    { { 0.0, 0.0, 0.0 }, { 0.2, 0.0, 0.0 } }, settings, flat, tracing, lines));
  ASSERT_EQ(lines.size(), 2u);
  for (const Streamline& line : lines)
  {
    EXPECT_EQ(line.Sign, -1.0);
    EXPECT_EQ(line.Reason, StreamEnd::Stagnation);
    EXPECT_EQ(line.Points.size(), 1u);
  }

  settings.Forward = true;
  settings.Backward = false;
  settings.HaveBox = true;
  settings.Box = { -0.3, 0.3, -1, 1, -1, 1 };
  auto up = Exact([](const StreamPoint&) { return StreamPoint{ 1.0, 0.0, 0.0 }; });
  ASSERT_TRUE(TraceGradientStreamlines({ { 0.0, 0.0, 0.0 } }, settings, up, tracing, lines));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].Reason, StreamEnd::OutOfDomain);
  // The first point beyond the box enlarged by a step.
  EXPECT_GT(lines[0].Points.back()[0], 0.35 - 1e-12);
  EXPECT_LE(lines[0].Points.back()[0], 0.4 + 1e-12);
}

// An abort at a step keeps the lines as they were, each ended; a failure at
// the seeds leaves none; the number of batches is one per stage.
TEST(GradientStreamlines, StopsAndBatches)
{
  StreamlineSettings settings;
  settings.StepLength = 0.01;
  settings.MaximumLength = 10.0;
  auto estimate = Exact([](const StreamPoint&) { return StreamPoint{ 0.0, 1.0, 0.0 }; });
  int calls = 0;
  auto stopAtThree = [&calls](double) { return ++calls <= 3; };
  std::vector<Streamline> lines;
  EXPECT_FALSE(TraceGradientStreamlines(
    { { 0.0, 0.0, 0.0 }, { 0.1, 0.0, 0.0 } }, settings, estimate, stopAtThree, lines));
  ASSERT_EQ(lines.size(), 4u);
  for (const Streamline& line : lines)
  {
    EXPECT_EQ(line.Points.size(), 4u); // the seed and three steps
    EXPECT_NE(line.Reason, StreamEnd::Running);
  }
  // One batch at the seeds, then four stages (RK4) and the new points: four
  // batches per step.
  EXPECT_EQ(estimate.Batches, 1 + 3 * 4);

  auto failing = [](const std::vector<StreamPoint>&, std::vector<StreamEstimate>&) {
    return false;
  };
  EXPECT_FALSE(
    TraceGradientStreamlines({ { 0.0, 0.0, 0.0 } }, settings, failing, tracing, lines));
  EXPECT_TRUE(lines.empty());
}
