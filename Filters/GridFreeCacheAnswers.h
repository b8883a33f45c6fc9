// The cache estimators' part of a batch (GridFreePointEstimates): the
// problem's cache (GridFreeCacheSlot.h) — the boundary value cache
// (gridfree/cache/BoundaryValueCache.h) or the sphere cache
// (gridfree/cache/SphereCache.h) — built on first use or grown to the walks
// asked for, answers the probe points it can; the points in the shell near
// the boundary are left to pointwise walks, and points outside the closed
// boundary get NaN (the caches solve the interior problem). In
// target-error mode the cache's walks double where a point it answers is
// above the target, up to the most walks a point may take.
// Private to the GridFree::Filters module.
#ifndef GridFreeCacheAnswers_h
#define GridFreeCacheAnswers_h

#include "GridFreeCacheSlot.h"
#include "GridFreeProblemBuilder.h"
#include "GridFreeSolveSettings.h"

#include "vtkAlgorithm.h"

#include <gridfree/problem/PolynomialShiftFit.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
struct CacheAnswers
{
  bool Active = false; // false: the pointwise estimator
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
  // The relative standard error of an answer's variance (about √(2/dof)).
  double VarianceRelativeError = 0.0;
  // The cache's own figures for field data (name, value).
  std::vector<std::pair<std::string, double>> Figures;
};

namespace detail
{
inline BoundaryCacheSettings BoundaryCacheSettingsOf(const SolveSettings& s)
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

inline SphereCacheSettings SphereCacheSettingsOf(const SolveSettings& s)
{
  SphereCacheSettings c;
  c.SamplesPerSphere = std::max(s.WalksPerSphere, 4);
  c.ShellDistance = std::max(s.CacheShellDistance, 1e-6);
  c.SourceSamples = std::max(s.CacheSourceSamples, 2);
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

// The boundary value cache into `slot`: built, reused or grown, then asked.
template <int DIM>
bool AnswerFromBoundaryCache(const Problem<DIM>& problem, CacheSlot& slot, const SolveSettings& s,
  const std::vector<std::array<double, 3>>& points, const CacheDerivatives& want, double target,
  bool keepGrown, const BatchProgressCallback& progress, CacheAnswers& out)
{
  if (want.Hessian || want.Directional)
  {
    throw std::invalid_argument(
      "it gives the value and the gradient, not the Hessian or a directional derivative");
  }
  const bool gradient = want.Gradient;
  std::shared_ptr<BoundaryValueCache<DIM>>& cache = slot.BoundaryCache<DIM>();
  const BoundaryCacheSettings settings = BoundaryCacheSettingsOf(s);
  // A fixed-count solve asking for fewer walks than the cache holds gets
  // a cache of that many (the bits of a fresh solve); a target-error
  // solve keeps a cache grown for an earlier target.
  if (cache && target <= 0.0 && !keepGrown &&
    cache->WalksPerCachePoint() > settings.WalksPerCachePoint)
  {
    cache.reset();
  }
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
  // Target-error mode: double the cache's walks while an answered point is
  // above the target (the walks' noise is most of the cache's error).
  const int most = std::max(s.WalksPerPoint, settings.WalksPerCachePoint);
  while (target > 0.0 && LargestAnsweredVariance(out.Answers) > target * target &&
    cache->WalksPerCachePoint() < most)
  {
    if (!cache->Refine(problem, std::min(2 * cache->WalksPerCachePoint(), most), progress))
    {
      return false;
    }
    out.WalksRun += cache->Walks();
    cache->Evaluate(points, gradient, out.Answers);
  }
  out.VarianceRelativeError = std::sqrt(2.0 / static_cast<double>(std::max<std::size_t>(cache->Size() / 2, 1)));
  out.Figures = { { "CachePoints", static_cast<double>(cache->Size()) },
    { "WalksPerCachePoint", static_cast<double>(cache->WalksPerCachePoint()) } };
  return true;
}

// The sphere cache into `slot`: made, then asked (it makes the spheres the
// points need, and grows them to a target).
template <int DIM>
bool AnswerFromSphereCache(const Problem<DIM>& problem, CacheSlot& slot, const SolveSettings& s,
  const std::vector<std::array<double, 3>>& points, const CacheDerivatives& want, double target,
  bool keepGrown, const BatchProgressCallback& progress, CacheAnswers& out)
{
  std::shared_ptr<SphereCache<DIM>>& cache = slot.Spheres<DIM>();
  const SphereCacheSettings settings = SphereCacheSettingsOf(s);
  // More walks per sphere top the spheres up as points need them; a
  // fixed-count solve asking for fewer than a sphere holds gets a cache of
  // that many (the bits of a fresh solve); a target-error solve keeps
  // spheres grown for an earlier target.
  if (cache && target <= 0.0 && !keepGrown && cache->MostSamples() > settings.SamplesPerSphere)
  {
    cache.reset();
  }
  if (!cache)
  {
    cache = std::make_shared<SphereCache<DIM>>(problem, settings);
  }
  cache->SetSamplesPerSphere(std::max(cache->SamplesPerSphere(), settings.SamplesPerSphere));
  const int most = std::max(s.WalksPerPoint, settings.SamplesPerSphere);
  const bool done =
    cache->Answer(problem, points, want, out.Answers, target * target, most, progress);
  out.WalksRun += cache->Walks();
  if (!done)
  {
    return false;
  }
  out.VarianceRelativeError =
    std::sqrt(2.0 / static_cast<double>(std::max(settings.SamplesPerSphere - 1, 1)));
  out.Figures = { { "CacheSpheres", static_cast<double>(cache->SphereCount()) },
    { "CacheWalks", static_cast<double>(cache->TotalWalks()) } };
  return true;
}
} // namespace detail

// Fills `out` for `points` from the cache the settings choose: builds it
// into the problem's slot (or reuses or grows the one there), asks it and
// splits the points. A fixed-count solve gets the bits of a fresh cache
// (one grown past its walks is built anew) unless `keepGrown` (the rounds
// of a time budget). False after an error (reported on `self`) or an abort
// (the slot keeps what was run, and the next batch continues from it).
template <int DIM>
bool AnswerFromCache(vtkAlgorithm* self, const BuiltProblem& built, const SolveSettings& s,
  const std::vector<std::array<double, 3>>& points, const CacheDerivatives& want, double target,
  bool keepGrown, const BatchProgressCallback& progress, CacheAnswers& out)
{
  const auto start = std::chrono::steady_clock::now();
  const Problem<DIM>& problem = built.Get<DIM>();
  const bool spheres = s.Estimator == Estimator::SphereCache;
  try
  {
    const bool done = spheres
      ? detail::AnswerFromSphereCache<DIM>(
          problem, *built.Caches, s, points, want, target, keepGrown, progress, out)
      : detail::AnswerFromBoundaryCache<DIM>(
          problem, *built.Caches, s, points, want, target, keepGrown, progress, out);
    if (!done)
    {
      return false;
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << "Estimator " << (spheres ? "Sphere Cache" : "Boundary Cache")
                                  << ": " << e.what()
                                  << ". Choose the Pointwise Walks estimator for this problem.");
    built.Caches->BoundaryCache<DIM>().reset();
    built.Caches->Spheres<DIM>().reset();
    return false;
  }
  if (const PolynomialShift<DIM>* shift = problem.GetPolynomialShift())
  {
    // The cache holds w = u − P (its problem's boundary and source are w's).
    AddShiftToCacheAnswers<DIM>(
      *shift, problem.GetBoundary(), points, s.DerivativeDirection, out.Answers);
  }
  out.Active = true;
  const int nc = built.Components;
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
    else if (std::isfinite(points[i][0]) && std::isfinite(points[i][1]) &&
      std::isfinite(points[i][2]))
    {
      out.Walked.push_back(i);
      out.WalkedPoints.push_back(points[i]);
    }
    // (Points with NaN or infinite coordinates, and those a mixed problem
    // found outside, stay NaN: StartPoints counted them.)
  }
  out.Seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}
} // namespace gridfree

#endif
