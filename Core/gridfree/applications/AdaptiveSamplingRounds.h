// Adaptive sampling's rounds (paper Sec. 5.2.2), built on its two decisions
// (AdaptiveSampling.h): well-spread first samples, then rounds that score
// every candidate by how badly its neighbours' Taylor expansions disagree
// there, and sample the worst ones, spread apart, in one batch per round.
// The caller estimates (a Problem's batch, or anything that gives values and
// gradients) and finds each candidate's neighbours among the samples (with
// or without visibility through the boundary); the rounds, the scores, the
// choice and the bookkeeping are here.
#ifndef GRIDFREE_APPLICATIONS_ADAPTIVE_SAMPLING_ROUNDS_H
#define GRIDFREE_APPLICATIONS_ADAPTIVE_SAMPLING_ROUNDS_H

#include <gridfree/applications/AdaptiveSampling.h>
#include <gridfree/execution/ParallelExecution.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace gridfree
{
struct AdaptiveSamplingSettings
{
  std::size_t InitialSamples = 64;
  std::size_t MaximumSamples = 1024;
  // A candidate is sampled where the disagreement's standard deviation
  // exceeds Threshold (times the first samples' range of each component
  // when ThresholdIsRelative).
  double Threshold = 0.05;
  bool ThresholdIsRelative = true;
  int Neighbours = 8;
  int MaximumRounds = 8;
  int Threads = 0; // 0: all
};

// One batch's numbers, as the caller's estimate fills them: per point in
// order, per solution component, the value and its variance, and the
// gradient (3 axes) and its variance.
struct SampleBatch
{
  int Components = 1;
  std::vector<double> Values, ValueVariances;       // points × nc
  std::vector<double> Gradients, GradientVariances; // points × nc × 3
};

// The samples so far, in the order they were estimated.
struct AdaptiveSamples
{
  int Components = 0;
  std::vector<Point3> Positions;
  std::vector<std::size_t> CandidateIds;
  std::vector<int> Rounds;     // 0 for the first samples
  std::vector<double> Scores;  // the disagreement ratio that chose it (NaN in round 0)
  std::vector<double> Values, ValueVariances, Gradients, GradientVariances; // as SampleBatch
  int RoundsDone = 0;

  std::size_t Size() const { return this->Positions.size(); }

  // The refinement test's data of sample s, component c.
  TaylorNeighbour Neighbour(std::size_t s, int c) const
  {
    const std::size_t nc = static_cast<std::size_t>(this->Components);
    TaylorNeighbour n;
    n.Position = this->Positions[s];
    n.Value = this->Values[s * nc + c];
    n.ValueVariance = this->ValueVariances[s * nc + c];
    for (int a = 0; a < 3; ++a)
    {
      n.Gradient[a] = this->Gradients[(s * nc + c) * 3 + a];
      n.GradientVariance[a] = this->GradientVariances[(s * nc + c) * 3 + a];
    }
    return n;
  }
};

enum class AdaptiveSamplingEnd
{
  Done,              // the budget, the rounds, or every candidate predicted well enough
  Stopped,           // an abort or a failed batch, after the first samples
  StoppedAtFirst,    // the same, before the first samples were estimated
  NoFiniteCandidate, // nothing to sample
};

namespace detail
{
// The candidates within a radius of a point (distance² ≤ radius², as VTK's
// point locators count them), from a uniform grid of about one candidate
// per cell over the dimensions the candidates span.
class CandidateGrid
{
public:
  explicit CandidateGrid(const std::vector<Point3>& points)
    : Points(points)
  {
    Point3 lo = { kInf, kInf, kInf }, hi = { -kInf, -kInf, -kInf };
    std::size_t finite = 0;
    for (const Point3& p : points)
    {
      if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
      {
        ++finite;
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = std::min(lo[k], p[k]);
          hi[k] = std::max(hi[k], p[k]);
        }
      }
    }
    if (finite == 0)
    {
      return;
    }
    double volume = 1.0;
    int spanned = 0;
    for (int k = 0; k < 3; ++k)
    {
      if (hi[k] > lo[k])
      {
        volume *= hi[k] - lo[k];
        ++spanned;
      }
    }
    this->Origin = lo;
    this->Cell = spanned == 0 ? 1.0 : std::pow(volume / static_cast<double>(finite), 1.0 / spanned);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const Point3& p = points[i];
      if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
      {
        this->Cells[GridCell(p, this->Origin, this->Cell)].push_back(i);
      }
    }
  }

  template <class Visit>
  void WithinRadius(const Point3& x, double radius, Visit&& visit) const
  {
    if (this->Cells.empty() || !(radius >= 0.0))
    {
      return;
    }
    const Point3 lo = { x[0] - radius, x[1] - radius, x[2] - radius };
    const Point3 hi = { x[0] + radius, x[1] + radius, x[2] + radius };
    const auto first = GridCell(lo, this->Origin, this->Cell);
    const auto last = GridCell(hi, this->Origin, this->Cell);
    const double r2 = radius * radius;
    std::array<std::int64_t, 3> c;
    for (c[0] = first[0]; c[0] <= last[0]; ++c[0])
    {
      for (c[1] = first[1]; c[1] <= last[1]; ++c[1])
      {
        for (c[2] = first[2]; c[2] <= last[2]; ++c[2])
        {
          const auto found = this->Cells.find(c);
          if (found == this->Cells.end())
          {
            continue;
          }
          for (std::size_t i : found->second)
          {
            const Point3& p = this->Points[i];
            const double d2 = (p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) +
              (p[2] - x[2]) * (p[2] - x[2]);
            if (d2 <= r2)
            {
              visit(i);
            }
          }
        }
      }
    }
  }

private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::vector<Point3>& Points;
  Point3 Origin = { 0.0, 0.0, 0.0 };
  double Cell = 1.0;
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::size_t>, CellHash> Cells;
};

inline void AppendSamples(AdaptiveSamples& samples, const std::vector<Point3>& candidates,
  const std::vector<std::size_t>& ids, int round, const std::vector<double>& scores,
  const SampleBatch& batch)
{
  if (samples.Size() == 0)
  {
    samples.Components = batch.Components;
  }
  const std::size_t nc = static_cast<std::size_t>(samples.Components);
  for (std::size_t i = 0; i < ids.size(); ++i)
  {
    samples.Positions.push_back(candidates[ids[i]]);
    samples.CandidateIds.push_back(ids[i]);
    samples.Rounds.push_back(round);
    samples.Scores.push_back(scores[i]);
    for (std::size_t c = 0; c < nc; ++c)
    {
      samples.Values.push_back(batch.Values[i * nc + c]);
      samples.ValueVariances.push_back(batch.ValueVariances[i * nc + c]);
      for (std::size_t a = 0; a < 3; ++a)
      {
        samples.Gradients.push_back(batch.Gradients[(i * nc + c) * 3 + a]);
        samples.GradientVariances.push_back(batch.GradientVariances[(i * nc + c) * 3 + a]);
      }
    }
  }
}
} // namespace detail

// Samples `candidates` adaptively into `samples`.
//
// estimate(ids, batch) estimates at the candidates `ids` (in that order) in
// one batch; false stops the sampling (an abort, or a failure the caller
// reports), and those candidates are not added.
// neighbours.SetSamples(positions) is called before each round's scoring;
// neighbours.Find(x, k, scratch, ids) then gives (from several threads at
// once, each with its own `typename Neighbours::Scratch`) the indices of up
// to k samples near x, nearest first; it may leave out samples it cannot
// see. progress(fraction) is called before each round and polled during
// the scoring; false stops the sampling.
template <class Estimate, class Neighbours, class Progress>
AdaptiveSamplingEnd SampleAdaptively(const std::vector<Point3>& candidates,
  const AdaptiveSamplingSettings& settings, Estimate&& estimate, Neighbours& neighbours,
  Progress&& progress, AdaptiveSamples& samples)
{
  samples = AdaptiveSamples();
  const std::size_t budget = settings.MaximumSamples;
  const std::size_t count = candidates.size();

  // Round 0: well-spread first samples.
  std::vector<std::size_t> first =
    SpreadSubset(candidates, std::min<std::size_t>(settings.InitialSamples, budget));
  if (first.size() > budget)
  {
    first.resize(budget);
  }
  if (first.empty())
  {
    return AdaptiveSamplingEnd::NoFiniteCandidate;
  }
  SampleBatch batch;
  if (!estimate(first, batch))
  {
    return AdaptiveSamplingEnd::StoppedAtFirst;
  }
  detail::AppendSamples(samples, candidates, first, 0,
    std::vector<double>(first.size(), std::numeric_limits<double>::quiet_NaN()), batch);
  const int nc = samples.Components;

  // The threshold's scale: the first samples' range per component.
  std::vector<double> threshold2(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c)
  {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t s = 0; s < samples.Size(); ++s)
    {
      const double v = samples.Values[s * nc + c];
      if (std::isfinite(v))
      {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    const double range = hi > lo ? hi - lo : 1.0;
    const double scale = settings.ThresholdIsRelative ? range : 1.0;
    threshold2[static_cast<std::size_t>(c)] =
      (settings.Threshold * scale) * (settings.Threshold * scale);
  }

  const detail::CandidateGrid grid(candidates);
  std::vector<char> sampled(count, 0);
  for (std::size_t id : samples.CandidateIds)
  {
    sampled[id] = 1;
  }
  const int k = settings.Neighbours;
  for (int round = 1; round <= settings.MaximumRounds && samples.Size() < budget; ++round)
  {
    if (!progress(static_cast<double>(samples.Size()) / static_cast<double>(budget)))
    {
      return AdaptiveSamplingEnd::Stopped;
    }
    neighbours.SetSamples(samples.Positions);
    // Each candidate's worst ratio of disagreement to threshold over the
    // components, and its distance to the nearest sample.
    std::vector<double> score(count, 0.0);
    std::vector<double> nearest(count, 0.0);
    auto test = [&](std::size_t from, std::size_t to, const std::atomic<bool>& cancel) {
      typename std::decay_t<Neighbours>::Scratch scratch;
      std::vector<std::size_t> ids;
      std::vector<TaylorNeighbour> data;
      for (std::size_t i = from; i < to && !cancel.load(std::memory_order_relaxed); ++i)
      {
        if (sampled[i])
        {
          continue;
        }
        const Point3& x = candidates[i];
        neighbours.Find(x, k, scratch, ids);
        double worst = ids.empty() ? std::numeric_limits<double>::infinity() : 0.0;
        for (int c = 0; c < nc && !ids.empty(); ++c)
        {
          data.clear();
          for (std::size_t id : ids)
          {
            data.push_back(samples.Neighbour(id, c));
          }
          const double excess = TaylorDisagreement(x, data.data(), static_cast<int>(data.size()));
          const double t2 = threshold2[static_cast<std::size_t>(c)];
          const double ratio =
            t2 > 0.0 ? excess / t2 : (excess > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
          worst = std::max(worst, ratio); // NaN (NaN samples) never refines
        }
        score[i] = worst;
        if (!ids.empty())
        {
          const Point3& y = samples.Positions[ids.front()];
          nearest[i] = std::sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
            (x[2] - y[2]) * (x[2] - y[2]));
        }
      }
    };
    if (!ParallelForWithProgress(count, settings.Threads, test,
          [&progress, &samples, budget](double) {
            return progress(static_cast<double>(samples.Size()) / static_cast<double>(budget));
          },
          0.1, 256))
    {
      return AdaptiveSamplingEnd::Stopped;
    }

    // Candidates that need a sample, worst first (ties: lower index), each
    // keeping the others within half its distance to the nearest sample
    // out of this round; at most as many as there are samples (and the
    // budget allows).
    std::vector<std::size_t> needy;
    for (std::size_t i = 0; i < count; ++i)
    {
      if (score[i] > 1.0)
      {
        needy.push_back(i);
      }
    }
    std::stable_sort(
      needy.begin(), needy.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
    const std::size_t room = std::min(budget - samples.Size(), samples.Size());
    std::vector<char> blocked(count, 0);
    std::vector<std::size_t> chosen;
    std::vector<double> chosenScores;
    for (std::size_t c : needy)
    {
      if (chosen.size() >= room)
      {
        break;
      }
      if (blocked[c])
      {
        continue;
      }
      chosen.push_back(c);
      chosenScores.push_back(score[c]);
      grid.WithinRadius(candidates[c], 0.5 * nearest[c], [&blocked](std::size_t j) { blocked[j] = 1; });
    }
    if (chosen.empty())
    {
      break; // every candidate is predicted well enough
    }
    if (!estimate(chosen, batch))
    {
      return AdaptiveSamplingEnd::Stopped;
    }
    detail::AppendSamples(samples, candidates, chosen, round, chosenScores, batch);
    for (std::size_t id : chosen)
    {
      sampled[id] = 1;
    }
    samples.RoundsDone = round;
  }
  return AdaptiveSamplingEnd::Done;
}
} // namespace gridfree

#endif
