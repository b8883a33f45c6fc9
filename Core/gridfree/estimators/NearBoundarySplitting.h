// Near-boundary splitting (WalkSettings::NearBoundarySplitting), the rule
// walk on spheres, walk on stars and the varying-coefficient walk share.
// From near the boundary most walks end at once, and the few that wander
// deep bring back what the rest never see; a walk whose reach (its distance to the absorbing boundary)
// grows to twice the largest it had goes on as two branches of half its
// weight, so that nearly every walk carries a share of the deep ones. Any
// rule that depends on the walk so far is unbiased.
#ifndef GRIDFREE_ESTIMATORS_NEAR_BOUNDARY_SPLITTING_H
#define GRIDFREE_ESTIMATORS_NEAR_BOUNDARY_SPLITTING_H

#include <algorithm>
#include <cmath>
#include <limits>

namespace gridfree
{
struct NearBoundarySplit
{
  // Branches split while their reach stays below this fraction of the
  // boundary's diagonal, at most kMaxSplits times. (A tenth left points
  // 0.17 from a unit sphere unsplit, and two of 4,800 with e^x data and
  // c = 1 missed their walks to the far side at |z| 5.3 and 6.2; with a
  // quarter none did, at 1.2 times the time.)
  static constexpr double kCeiling = 0.25;
  static constexpr int kMaxSplits = 16;
  // And at most this many branches per walk: outside a closed boundary (or
  // near a convex corner) a walk doubles its distance nearly surely, and
  // every level would double the branches.
  static constexpr int kMaxBranches = 32;

  // The reach up to which branches split (0: splitting off): kCeiling of
  // the diagonal, and for the screened equation no deeper than the
  // screening length 1/√c, beyond which what deep branches bring back is
  // damped by e^{−√c·depth}.
  static double Ceiling(bool on, double diagonal, double screening)
  {
    return on ? std::min(kCeiling * diagonal, 1.0 / std::sqrt(std::max(screening, 1e-300))) : 0.0;
  }

  // The reach at which a walk first splits: twice its first reach or the
  // scale given, whichever is larger (walks that go on from a derivative's
  // first ball start near the boundary and split only beyond twice the
  // scale of the point they estimate),
  // if that is below the ceiling; infinity otherwise, so that points
  // farther than half the ceiling from the boundary walk as without it.
  static double First(double reach, double scale, double ceiling)
  {
    const double start = 2.0 * std::max(reach, scale);
    return start <= ceiling ? start : std::numeric_limits<double>::infinity();
  }

  // The reach at which a branch splits next, after splitting at `next`.
  static double Next(double next, double ceiling)
  {
    return 2.0 * next <= ceiling ? 2.0 * next : std::numeric_limits<double>::infinity();
  }

  // One step of a branch at `reach` (the walk's first step when `first`,
  // which sets where it first splits: First, with `scale`): the branch
  // splits once for each doubling it made past `next`, while it has splits
  // left and the walk has fewer than kMaxBranches branches. Each split
  // updates next, left and branches, then calls split(), which halves the
  // branch's weight and sets the other half aside as a new branch in the
  // state they now hold.
  template <class Split>
  static void AtStep(double reach, bool first, double scale, double ceiling, double& next,
    int& left, int& branches, const Split& split)
  {
    if (first)
    {
      next = First(reach, scale, ceiling);
    }
    // (next is infinite once the branch may split no more, and so is the
    // reach of a walk on stars with no Dirichlet part: no split then.)
    while (reach >= next && next < std::numeric_limits<double>::infinity() && left > 0 &&
      branches < kMaxBranches)
    {
      ++branches;
      next = Next(next, ceiling);
      --left;
      split();
    }
  }
};
} // namespace gridfree

#endif
