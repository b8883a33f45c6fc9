// Streamlines of a solution's gradient (paper Sec. 5.2.6), traced together:
// every Runge–Kutta stage of every running line is one batch of estimates
// (LockstepStreamlines.h), so each batch uses the problem's whole thread
// pool. The caller estimates (a Problem's batch, or anything else that gives
// values and gradients at points); this file owns the lines, their steps and
// why each ended, with vtkStreamTracer's termination codes.
#ifndef gridfree_applications_GradientStreamlines_h
#define gridfree_applications_GradientStreamlines_h

#include <gridfree/applications/LockstepStreamlines.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace gridfree
{
using StreamPoint = std::array<double, 3>;

// What is known at one point of a line: u and ∇u (of the first solution
// component) with their variances, the distance to the boundary, whether
// the point is closer than ε (its gradient is one-sided or missing), and
// whether u is finite.
struct StreamEstimate
{
  double Value = 0.0;
  double ValueVariance = 0.0;
  StreamPoint Gradient = { 0.0, 0.0, 0.0 };
  StreamPoint GradientVariance = { 0.0, 0.0, 0.0 };
  double Distance = 0.0;
  bool NearBoundary = false;
  bool Valid = false;
};

// Why a line ended: vtkStreamTracer's codes, and one of ours.
enum class StreamEnd : int
{
  Running = 0,
  OutOfDomain = 1,     // u not finite, or the point left the box
  OutOfLength = 2,     // the next step would pass MaximumLength
  OutOfSteps = 3,      // MaximumSteps taken
  Stagnation = 4,      // |∇u| at most TerminalSpeed
  CloseToBoundary = 7, // closer than ε: the gradient is not the interior one
};

struct StreamlineSettings
{
  double StepLength = 0.01;   // absolute
  double MaximumLength = 1.0; // absolute
  int MaximumSteps = 2000;
  double TerminalSpeed = 1e-12;
  StreamIntegrator Integrator = StreamIntegrator::RungeKutta4;
  bool Forward = true;  // up the gradient
  bool Backward = true; // down it
  // Lines stay in this box (xmin, xmax, ymin, ymax, zmin, zmax) enlarged by
  // one step; without one, they stop only where a coordinate is not finite.
  bool HaveBox = false;
  std::array<double, 6> Box = { 0, 0, 0, 0, 0, 0 };
};

// One line: the seed it started from, its direction (+1 up the gradient,
// -1 down), its points with the estimates there, its length and its end.
struct Streamline
{
  std::size_t Seed = 0;
  double Sign = 1.0;
  std::vector<StreamPoint> Points;
  std::vector<StreamEstimate> Estimates;
  double Length = 0.0;
  StreamEnd Reason = StreamEnd::Running;
};

namespace detail
{
// Unit direction s·g/|g|; false where |g| is at most `terminal` or not finite.
inline bool UnitGradientDirection(
  const StreamEstimate& e, double sign, double terminal, StreamPoint& d)
{
  const double norm = std::sqrt(e.Gradient[0] * e.Gradient[0] + e.Gradient[1] * e.Gradient[1] +
    e.Gradient[2] * e.Gradient[2]);
  if (!(norm > terminal) || !std::isfinite(norm))
  {
    return false;
  }
  for (int k = 0; k < 3; ++k)
  {
    d[k] = sign * e.Gradient[k] / norm;
  }
  return true;
}
} // namespace detail

// Traces a line from every seed in each direction asked for, in lockstep.
//
// estimate(points, estimates) fills one StreamEstimate per point in one
// batch; false stops the tracing (an abort, or a failed batch the caller
// reports). progress(fraction) is called before each step; false stops it
// too (an abort). A step never leaves the empty ball around the line's
// point (half its radius), so no stage crosses the boundary: near it, steps
// shrink and the line ends within ε of it (CloseToBoundary).
//
// False when stopped; `lines` then holds what was traced, each line ended
// where it was (with the reason its last point gives, or OutOfSteps). A stop
// at the seeds leaves no lines.
template <class EstimateBatch, class Progress>
bool TraceGradientStreamlines(const std::vector<StreamPoint>& seeds,
  const StreamlineSettings& settings, EstimateBatch&& estimate, Progress&& progress,
  std::vector<Streamline>& lines)
{
  lines.clear();
  const double h = settings.StepLength;
  auto inBox = [&](const StreamPoint& p) {
    if (!settings.HaveBox)
    {
      return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    }
    for (int k = 0; k < 3; ++k)
    {
      if (!(p[k] >= settings.Box[2 * k] - h && p[k] <= settings.Box[2 * k + 1] + h))
      {
        return false;
      }
    }
    return true;
  };

  std::vector<StreamEstimate> seedEstimates;
  if (!estimate(seeds, seedEstimates))
  {
    return false;
  }
  for (std::size_t s = 0; s < seeds.size(); ++s)
  {
    for (double sign : { 1.0, -1.0 })
    {
      if ((sign > 0 && !settings.Forward) || (sign < 0 && !settings.Backward))
      {
        continue;
      }
      Streamline line;
      line.Seed = s;
      line.Sign = sign;
      line.Points.push_back(seeds[s]);
      line.Estimates.push_back(seedEstimates[s]);
      lines.push_back(std::move(line));
    }
  }

  // Whether a line can take a step from its last point: its direction there,
  // or its end with the reason.
  auto startStep = [&](Streamline& line, StreamPoint& d) {
    const StreamEstimate& e = line.Estimates.back();
    if (!e.Valid || !inBox(line.Points.back()))
    {
      line.Reason = StreamEnd::OutOfDomain;
    }
    else if (e.NearBoundary)
    {
      line.Reason = StreamEnd::CloseToBoundary;
    }
    else if (!detail::UnitGradientDirection(e, line.Sign, settings.TerminalSpeed, d))
    {
      line.Reason = StreamEnd::Stagnation;
    }
    else if (static_cast<int>(line.Points.size()) > settings.MaximumSteps)
    {
      line.Reason = StreamEnd::OutOfSteps;
    }
    else if (line.Length + h > settings.MaximumLength * (1.0 + 1e-12))
    {
      line.Reason = StreamEnd::OutOfLength;
    }
    return line.Reason == StreamEnd::Running;
  };
  auto stepOf = [&](const Streamline& line) {
    return std::min(h, 0.5 * line.Estimates.back().Distance);
  };

  bool stopped = false;
  for (int step = 0; step < settings.MaximumSteps && !stopped; ++step)
  {
    std::vector<std::size_t> running;
    std::vector<StreamPoint> from, first;
    std::vector<double> steps;
    for (std::size_t l = 0; l < lines.size(); ++l)
    {
      StreamPoint d;
      if (lines[l].Reason == StreamEnd::Running && startStep(lines[l], d))
      {
        running.push_back(l);
        from.push_back(lines[l].Points.back());
        first.push_back(d);
        steps.push_back(stepOf(lines[l]));
      }
    }
    if (running.empty())
    {
      break;
    }
    if (!progress(static_cast<double>(step) / settings.MaximumSteps))
    {
      stopped = true;
      break;
    }
    // A stage whose direction is undefined reuses the previous one.
    auto gradientDirections = [&](int, const std::vector<StreamPoint>& at,
                                const std::vector<StreamPoint>&,
                                std::vector<StreamPoint>& directions, std::vector<char>& defined) {
      std::vector<StreamEstimate> estimates;
      if (!estimate(at, estimates))
      {
        return false;
      }
      for (std::size_t r = 0; r < running.size(); ++r)
      {
        defined[r] =
          detail::UnitGradientDirection(estimates[r], lines[running[r]].Sign, 0.0, directions[r]);
      }
      return true;
    };
    std::vector<StreamPoint> combined;
    if (!LockstepStepDirections<StreamPoint, 3>(
          settings.Integrator, from, steps, first, gradientDirections, combined))
    {
      stopped = true;
      break;
    }
    std::vector<StreamPoint> next(running.size());
    for (std::size_t r = 0; r < running.size(); ++r)
    {
      for (int k = 0; k < 3; ++k)
      {
        next[r][k] = from[r][k] + steps[r] * combined[r][k];
      }
    }
    std::vector<StreamEstimate> atNext;
    if (!estimate(next, atNext))
    {
      stopped = true;
      break; // the lines end before the points of a stopped batch
    }
    for (std::size_t r = 0; r < running.size(); ++r)
    {
      Streamline& line = lines[running[r]];
      const StreamPoint& a = line.Points.back();
      const StreamPoint& b = next[r];
      line.Length += std::sqrt(
        (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
      line.Points.push_back(b);
      line.Estimates.push_back(atNext[r]);
    }
  }
  for (Streamline& line : lines)
  {
    if (line.Reason == StreamEnd::Running)
    {
      StreamPoint unused;
      if (startStep(line, unused))
      {
        line.Reason = StreamEnd::OutOfSteps;
      }
    }
  }
  return !stopped;
}
} // namespace gridfree

#endif
