// Whether a point's reported variance (its error bar) can be trusted,
// judged from its own walks (Documentation/UserGuide.md, "Error bars you can
// trust").
//
// The variance of the mean, s²/N, is itself estimated from the walks. When
// walk values are heavy-tailed (rare walks far larger than the rest), a
// point that has not yet seen those walks reports a mean that is too small
// and a variance that is far too small: |z| reaches tens. Measured on
// held-out problems (Testing/Core/statistics/TestErrorBarReliability.cxx), the points
// with |z| > 5 are those whose large walks are *not yet seen*; the kurtosis
// of the walks seen (the variance's own relative standard error, reported
// as VarianceRelativeError) does not single them out: it is as large at
// near-boundary points of smooth Laplace problems (up to 0.9 at 128 walks)
// as at the wrong points of heavy-tailed ones (from 0.06). Three signs do:
//
//  1. Uneven walk weights (screened equation). A screened walk carries the
//     weight W = Π C_k (E[W] is the solution for g = 1). When the weights'
//     coefficient of variation sd(W)/mean(W) exceeds 0.5 (the walks count
//     as fewer than 80% as many equal-weight walks), the value rests on the
//     walks that kept their weight, and a straight path to where g is
//     large, not yet seen, can dominate it. This is a property of the point
//     and the screening (√c times the distance to the boundary), not of the
//     walk count: at 4,096 walks such points still showed |z| up to 175, so
//     more walks do not lift the flag. Light screening (c = 4 on the unit
//     sphere) stays below 0.34; every wrong point of the strongly screened
//     cases (c = 100, 400, Yukawa data) is above 0.7.
//  2. No spread, or the spread of one walk: every walk gave the same value
//     although the walks took steps and the data are not constant (a walk
//     can reach other values, it just has not yet): its variance 0 is no
//     error bar; or all walks but one did, which the walks' skewness shows,
//     M3²/M2³ = G1²/N > 0.5 (near 1 − 3/N for one odd walk, 1/2 for two).
//     Data that jump, read with few walks (a diffusion-curves image at 64
//     walks), give both: with one walk of 64 on the far side of a jump
//     where 8 were due, |z| reached 6.8. Ordinary skewed walk values stay
//     below 0.22 (smooth Laplace and mild screening, 128 and 256 walks); the
//     normal approximation's rule of thumb (N > 25·G1²) is far stricter, so
//     this flags only a spread made by a single walk. More walks lift it.
//  3. The spread of few walks, where the walk values are known to be
//     bounded (below): a spread made by two walks (M3²/M2³ > 0.4; two equal
//     odd walks give about 1/2), or walks seen that are small beside what
//     one walk could bring (D/(s√N) > 3, below). Data that jump, read with
//     32 to 128 walks (g = sign(y) on the unit circle, 300 points, ten
//     seeds), missed at points whose spread two walks made: plain walks
//     that saw 2 walks across the jump where 9 were due (the Wald interval
//     of a proportion read from two successes), and with near-boundary
//     splitting walks whose branches brought back small shares of the far
//     side (two walks with an eighth each) where whole walks were due. With
//     walking on (BatchRequest::WalkOnWhereUnreliable) their misses went
//     from 1, 2, 0 to none (plain) and from 6, 7, 1 to 1, 1, 0 (splitting)
//     at 32, 64, 128 walks (on ten held-out point sets from 8, 4, 2 to
//     5, 3, 2 with splitting; plain walks kept their one miss: what is
//     left looks ordinary, Documentation/ErrorBars.md). Ordinary walk
//     values stay far below both: of
//     the smooth Laplace and mildly screened cases of the tests, none is
//     flagged. Where the values are not known to be bounded it is not used:
//     strongly screened walks with guided steps, calibrated, reach 0.4 at
//     1 or 2 of 150 points.
//
// Uneven weights are harmless when the values a walk can take are bounded
// and the bound is near: a walk the point has not seen yet can move its
// mean by at most D/N, D the farthest a walk value can lie from the mean,
// which is D/(s√N) standard errors. Where that is at most MaxUnseenShift
// (2) for every component, rule 1 does not flag: a 2D screened problem with
// I0(kr) data (c = 9) had right error bars (mean z² 0.91) at the 93 of 300
// points rule 1 flagged, all with D/(s√N) ≤ 0.8, while the wrong points of
// the exponential and Yukawa data above have D/(s√N) in the hundreds.
//
// The bound: the plain screened walk with Dirichlet data in [g_min, g_max]
// and a volume source in [f_min, f_max] sampled by G gives values
// W·g + (1 − W)·v, with v within the steady values [−f_max/c, −f_min/c]
// (Problem::SteadyRange; f's range as the source states it, else as its
// samples on the source map's grid show it) and W the weight the walk
// kept (0 ≤ W ≤ 1; g taken with 0, for walks cut short). W is at most the first ball's C,
// which every walk of the point shares (WalkCounters::WeightReach): deep in
// a strongly screened domain no walk, seen or not, can bring back much of
// g, and the bound shrinks with that C. (The CT head's bioheat solve with
// the brain's constants flagged 1,415 of its 1,539 points without the
// source's range, 427 of 1,500 (300 points, five seeds) with it but W ≤ 1,
// and none with W ≤ C; the error bars were right at all of them.) The value's
// control variate (derivative walks) may move a sample beyond these bounds
// by C·|b̄|: the slack CheckErrorBar is given (WalkCounters::
// ValueControlReach, the largest seen).
//
// A point is unreliable when any holds. What it does not catch: a tail
// that no walk of the point has reached yet while the walks seen still
// differ in the ordinary way (a narrow peak in g reached by one walk in
// thousands; a source much narrower than the domain, unless sampled by
// its density (SourceSampling::SourceDensity): mean z² 2.4–3.2 below
// 1,024 walks, 1.2 at 4,096; rarely, a
// near-boundary point that saw one far walk where a dozen were due). Nothing in such a point's walks tells it apart; more
// walks, or two seeds compared, are the remedy there.
#ifndef GRIDFREE_STATISTICS_ERROR_BAR_RELIABILITY_H
#define GRIDFREE_STATISTICS_ERROR_BAR_RELIABILITY_H

#include <gridfree/statistics/RunningStatistics.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gridfree
{
struct ErrorBarRule
{
  // Above this coefficient of variation of the walk weights (screened
  // equation), the walks that carry the value are too few.
  double MaxWeightVariation = 0.5;
  // Above this M3²/M2³, the spread is made by a single walk.
  double MaxSkewShare = 0.5;
  // The values one walk can give, per value component (empty: unknown), as
  // W·g + (1 − W)·v: g in [WalkLow, WalkHigh] (0 included), v in
  // [SteadyLow, SteadyHigh] (empty: v = 0, no sources); and the largest
  // shift of the mean, in standard errors, that one walk not yet seen may
  // make for uneven weights not to flag (see above).
  std::vector<double> WalkLow, WalkHigh;
  std::vector<double> SteadyLow, SteadyHigh;
  double MaxUnseenShift = 2.0;
  // Where those bounds are known, the spread of few walks (sign 3 above):
  // above this M3²/M2³ the spread is two walks' (two equal odd walks give
  // about 1/2, three 1/3), and above this unseen shift the walks seen are
  // small beside what one walk could bring.
  double MaxBoundedSkewShare = 0.4;
  double MaxBoundedUnseenShift = 3.0;
};

struct ErrorBarCheck
{
  // The variance's relative standard error, the largest over the value's
  // components (0 when all walks agree; NaN below 4 walks). Reported, not
  // used to flag (see above).
  double VarianceRelativeError = 0.0;
  // The coefficient of variation of the walk weights, sd(W)/mean(W): 0
  // without weights (unscreened equations), +inf when every walk lost its
  // weight.
  double WeightVariation = 0.0;
  // Every walk gave the same value although it could have given another.
  bool NoSpread = false;
  // The largest M3²/M2³ over the value's components (RunningStatistics::
  // SkewShare); above MaxSkewShare the spread is one walk's.
  double SkewShare = 0.0;
  // The largest shift of the mean one walk not yet seen can make, in
  // standard errors (D/(s√N), the largest over the value's components);
  // +inf when the walk values are not known to be bounded.
  double UnseenWalkShift = std::numeric_limits<double>::infinity();
  // The weights are uneven and no bound of the walk values clears them: one
  // of the reasons for Reliable = false.
  bool UnevenWeights = false;
  // The walk values are bounded and their spread is that of few walks:
  // another (sign 3 above).
  bool FewWalksSpread = false;
  bool Reliable = true;
};

// The range [low, high] of W·g + (1 − W)·v over W in [0, weightReach], g
// in [WalkLow, WalkHigh] and v in [SteadyLow, SteadyHigh] of component c
// (linear in W: its ends are the extremes).
inline void WalkValueRange(const ErrorBarRule& rule, int c, double weightReach, double& low,
  double& high)
{
  const std::size_t k = static_cast<std::size_t>(c);
  const bool steady = rule.SteadyLow.size() > k && rule.SteadyHigh.size() > k;
  const double vLow = steady ? rule.SteadyLow[k] : 0.0;
  const double vHigh = steady ? rule.SteadyHigh[k] : 0.0;
  const double w = std::min(std::max(weightReach, 0.0), 1.0);
  low = std::min(vLow, w * rule.WalkLow[k] + (1.0 - w) * vLow);
  high = std::max(vHigh, w * rule.WalkHigh[k] + (1.0 - w) * vHigh);
}

// Checks one point's statistics (`slack`: how far beyond the rule's walk
// value bounds a value sample may lie, for control variates;
// `weightReach`: the largest weight a walk of the point can keep, see
// above): the value's components are slots
// valueSlot .. valueSlot + valueComponents − 1 (they must keep higher sums:
// RunningStatistics' tailComponents), the walk weight is at weightSlot (−1:
// none). `spreadPossible`: the walks took steps and the data are not
// constant, so identical walks mean that others were not yet seen. A
// measure that cannot be computed (NaN values, fewer than 4 walks) does not
// make a point unreliable.
inline ErrorBarCheck CheckErrorBar(const RunningStatistics& stats, int valueSlot,
  int valueComponents, int weightSlot, bool spreadPossible,
  const ErrorBarRule& rule = ErrorBarRule(), double slack = 0.0, double weightReach = 1.0)
{
  ErrorBarCheck check;
  double worst = std::numeric_limits<double>::quiet_NaN();
  double skew = 0.0;
  bool noSpread = valueComponents > 0 && stats.SampleCount() >= 2;
  for (int c = 0; c < valueComponents; ++c)
  {
    const double e = stats.VarianceRelativeError(valueSlot + c);
    if (std::isnan(worst) || e > worst)
    {
      worst = e;
    }
    const double share = stats.SkewShare(valueSlot + c);
    skew = share > skew ? share : skew;
    noSpread = noSpread && stats.SpreadIsRoundOff(valueSlot + c);
  }
  check.VarianceRelativeError = worst;
  check.SkewShare = skew;
  check.NoSpread = spreadPossible && noSpread;
  if (weightSlot >= 0 && stats.SampleCount() >= 4)
  {
    const double mean = stats.GetMean(weightSlot);
    const double sd = std::sqrt(stats.SampleVariance(weightSlot));
    check.WeightVariation = mean > 0.0
      ? sd / mean
      : (mean == 0.0 ? std::numeric_limits<double>::infinity()
                     : std::numeric_limits<double>::quiet_NaN());
  }
  const bool bounded = static_cast<int>(rule.WalkLow.size()) == valueComponents &&
    static_cast<int>(rule.WalkHigh.size()) == valueComponents && valueComponents > 0;
  if (bounded && stats.SampleCount() >= 2)
  {
    double shift = 0.0;
    const double n = static_cast<double>(stats.SampleCount());
    for (int c = 0; c < valueComponents; ++c)
    {
      const double mean = stats.GetMean(valueSlot + c);
      double low = 0.0, high = 0.0;
      WalkValueRange(rule, c, weightReach, low, high);
      const double far = std::max(high - mean, mean - low) + slack;
      const double spread = std::sqrt(stats.SampleVariance(valueSlot + c) * n);
      const double s = far > 0.0 ? far / spread : 0.0;
      shift = std::isnan(s) ? std::numeric_limits<double>::infinity() : std::max(shift, s);
    }
    check.UnseenWalkShift = shift;
  }
  check.UnevenWeights = check.WeightVariation > rule.MaxWeightVariation &&
    !(check.UnseenWalkShift <= rule.MaxUnseenShift);
  check.FewWalksSpread = bounded && spreadPossible && stats.SampleCount() >= 4 &&
    (check.SkewShare > rule.MaxBoundedSkewShare ||
      (std::isfinite(check.UnseenWalkShift) &&
        check.UnseenWalkShift > rule.MaxBoundedUnseenShift));
  check.Reliable = !check.NoSpread && !(check.SkewShare > rule.MaxSkewShare) &&
    !check.UnevenWeights && !check.FewWalksSpread;
  return check;
}
} // namespace gridfree

#endif
