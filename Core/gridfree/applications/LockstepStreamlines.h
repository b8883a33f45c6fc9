// Curves traced together, one explicit Runge–Kutta step at a time, every
// stage one batch of direction estimates for all of them. Walk-on-spheres
// estimates are cheapest in batches (one problem, many points, all threads),
// so both curve tracers of the project step this way: the streamlines of a
// solution's gradient (paper Sec. 5.2.6) and the separatrices of a cross
// field (Sec. 6.6). The caller keeps each curve's state, its stopping tests
// and its step size; this integrator owns the stages and their weights.
#ifndef gridfree_applications_LockstepStreamlines_h
#define gridfree_applications_LockstepStreamlines_h

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace gridfree
{
enum class StreamIntegrator
{
  Heun = 0,        // two stages
  RungeKutta4 = 1, // four stages
};

inline int StageCount(StreamIntegrator method)
{
  return method == StreamIntegrator::RungeKutta4 ? 4 : 2;
}

// The combined direction of one step of every curve q, which then moves to
// x[q] + h[q]·direction[q]: Heun's (k1 + k2)/2 or the classical Runge–Kutta
// (k1 + 2k2 + 2k3 + k4)/6, where k1[q] is the caller's direction at x[q]
// and stage s is estimated at x + c_s·h·k_{s−1} (Heun: c = 1; RK4: c = 1/2,
// 1/2, 1). `Vec` is any type with N components read and written by [].
//
// estimate(stage, points, previous, directions, defined) estimates stage
// `stage`'s directions at `points`, one per curve, in one batch; `previous`
// holds each curve's direction of the stage before (a cross field's
// estimate picks the branch nearest to it). A curve whose direction is not
// `defined` at its stage point keeps the previous stage's. Where Heun's two
// stages cancel (|k1 + k2| ≤ 1e-12) the step falls back to Euler's k1.
// False, at once, when `estimate` returns false (an abort).
template <class Vec, int N, class Estimate>
bool LockstepStepDirections(StreamIntegrator method, const std::vector<Vec>& x,
  const std::vector<double>& h, const std::vector<Vec>& k1, Estimate&& estimate,
  std::vector<Vec>& direction)
{
  const int stages = StageCount(method);
  const std::size_t n = x.size();
  std::vector<std::vector<Vec>> k(static_cast<std::size_t>(stages));
  k[0] = k1;
  std::vector<Vec> where(n);
  std::vector<char> defined(n);
  for (int stage = 1; stage < stages; ++stage)
  {
    const double factor = stages == 2 ? 1.0 : (stage == 3 ? 1.0 : 0.5);
    const std::vector<Vec>& previous = k[static_cast<std::size_t>(stage - 1)];
    for (std::size_t q = 0; q < n; ++q)
    {
      const double step = factor * h[q];
      for (int i = 0; i < N; ++i)
      {
        where[q][i] = x[q][i] + step * previous[q][i];
      }
    }
    std::vector<Vec>& current = k[static_cast<std::size_t>(stage)];
    current = previous;
    std::fill(defined.begin(), defined.end(), 0);
    if (!estimate(stage, where, previous, current, defined))
    {
      return false;
    }
    for (std::size_t q = 0; q < n; ++q)
    {
      if (!defined[q])
      {
        current[q] = previous[q];
      }
    }
  }
  direction.resize(n);
  for (std::size_t q = 0; q < n; ++q)
  {
    if (stages == 2)
    {
      double sum2 = 0.0;
      for (int i = 0; i < N; ++i)
      {
        const double s = k[0][q][i] + k[1][q][i];
        sum2 += s * s;
      }
      const bool cancel = !(std::sqrt(sum2) > 1e-12);
      for (int i = 0; i < N; ++i)
      {
        direction[q][i] = cancel ? k[0][q][i] : 0.5 * (k[0][q][i] + k[1][q][i]);
      }
    }
    else
    {
      for (int i = 0; i < N; ++i)
      {
        direction[q][i] =
          (k[0][q][i] + 2.0 * k[1][q][i] + 2.0 * k[2][q][i] + k[3][q][i]) / 6.0;
      }
    }
  }
  return true;
}
} // namespace gridfree

#endif
