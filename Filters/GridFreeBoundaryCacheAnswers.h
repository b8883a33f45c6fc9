// The Boundary Cache estimator's part of a batch (GridFreePointEstimates):
// the problem's boundary value cache (gridfree/cache/BoundaryValueCache.h),
// built on first use or grown to the walks asked for, answers the probe
// points it can; the points in the shell near the boundary are left to
// pointwise walks, and points outside the closed boundary get NaN (the
// cache solves the interior problem). In target-error mode the cache's
// walks double until every point it answers meets the target, or until
// they reach the most walks a point may take.
// Private to the GridFree::Filters module.
#ifndef GridFreeBoundaryCacheAnswers_h
#define GridFreeBoundaryCacheAnswers_h

#include "GridFreeBoundaryCacheSlot.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"

#include "vtkAlgorithm.h"

#include <gridfree/cache/BoundaryValueCache.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <vector>

namespace gridfree
{
template <int DIM>
struct BoundaryCacheAnswers
{
  const BoundaryValueCache<DIM>* Cache = nullptr; // null: the pointwise estimator
  CacheEvaluation Answers; // per probe point, NaN where not answered
  // The probe points left to walks (the shell, non-finite points), by
  // index, and their coordinates.
  std::vector<std::size_t> Walked;
  std::vector<std::array<double, 3>> WalkedPoints;
  std::int64_t Answered = 0;
  std::int64_t Outside = 0;
  // Answered points whose standard error is above the target after the
  // cache grew as far as it may.
  std::int64_t ShortOfTarget = 0;
  // The cache's walks run by this batch (0: reused as it was) and the
  // seconds its building, growing and evaluation took.
  std::uint64_t WalksRun = 0;
  double Seconds = 0.0;

  bool Active() const { return this->Cache != nullptr; }
};

namespace detail
{
inline BoundaryCacheSettings CacheSettingsOf(const SolveSettings& s)
{
  BoundaryCacheSettings c;
  c.CachePoints = static_cast<std::size_t>(std::max(s.CachePoints, 2));
  c.VolumePoints = static_cast<std::size_t>(std::max(s.CacheVolumePoints, 2));
  c.WalksPerCachePoint = std::max(s.WalksPerCachePoint, 2);
  c.Offset = s.CacheOffset;
  c.ShellDistance = s.CacheShellDistance;
  c.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(s.Seed));
  c.Threads = s.NumberOfThreads;
  return c;
}

// The largest variance of a value over the points the cache answers.
inline double LargestAnsweredVariance(const CacheEvaluation& e)
{
  double largest = 0.0;
  for (double v : e.ValueVariance)
  {
    largest = std::isfinite(v) ? std::max(largest, v) : largest;
  }
  return largest;
}
} // namespace detail

// Fills `out` for `points`: builds the cache into the problem's slot (or
// reuses or grows the one there), evaluates it and splits the points.
// False after an error (reported on `self`) or an abort (the slot keeps
// the walks run, and the next batch continues them).
template <int DIM>
bool AnswerFromBoundaryCache(vtkAlgorithm* self, const BuiltProblem& built,
  const SolveSettings& s, const std::vector<std::array<double, 3>>& points, bool gradient,
  double target, const BatchProgressCallback& progress, BoundaryCacheAnswers<DIM>& out)
{
  const auto start = std::chrono::steady_clock::now();
  const Problem<DIM>& problem = built.Get<DIM>();
  std::shared_ptr<BoundaryValueCache<DIM>>& cache = built.CacheSlot->template Get<DIM>();
  const BoundaryCacheSettings settings = detail::CacheSettingsOf(s);
  // A fixed-count solve asking for fewer walks than the cache holds gets
  // a cache of that many (the bits of a fresh solve); a target-error
  // solve keeps a cache grown for an earlier target.
  if (cache && target <= 0.0 && cache->WalksPerCachePoint() > settings.WalksPerCachePoint)
  {
    cache.reset();
  }
  try
  {
    if (!cache)
    {
      cache = std::make_shared<BoundaryValueCache<DIM>>(problem, settings, progress);
      out.WalksRun += cache->Walks();
    }
    else if (cache->WalksPerCachePoint() < settings.WalksPerCachePoint || !cache->Complete())
    {
      cache->Refine(problem, settings.WalksPerCachePoint, progress);
      out.WalksRun += cache->Walks();
    }
    if (!cache->Complete())
    {
      return false; // aborted
    }
    cache->Evaluate(points, gradient, out.Answers);
    // Target-error mode: double the cache's walks while an answered point
    // is above the target (the walks' noise is most of the cache's error).
    const int most = std::max(s.WalksPerPoint, settings.WalksPerCachePoint);
    while (target > 0.0 && detail::LargestAnsweredVariance(out.Answers) > target * target &&
      cache->WalksPerCachePoint() < most)
    {
      if (!cache->Refine(problem, std::min(2 * cache->WalksPerCachePoint(), most), progress))
      {
        return false;
      }
      out.WalksRun += cache->Walks();
      cache->Evaluate(points, gradient, out.Answers);
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << "Estimator Boundary Cache: " << e.what()
                                  << ". Choose the Pointwise Walks estimator for this problem.");
    cache.reset();
    return false;
  }
  out.Cache = cache.get();
  const int nc = cache->SolutionComponents();
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (out.Answers.Outside[i])
    {
      ++out.Outside;
    }
    else if (std::isfinite(out.Answers.Value[i * static_cast<std::size_t>(nc)]))
    {
      ++out.Answered;
      bool above = false;
      for (int c = 0; c < nc && target > 0.0; ++c)
      {
        above = above || out.Answers.ValueVariance[i * nc + c] > target * target;
      }
      out.ShortOfTarget += above ? 1 : 0;
    }
    else
    {
      out.Walked.push_back(i);
      out.WalkedPoints.push_back(points[i]);
    }
  }
  out.Seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}
} // namespace gridfree

#endif
