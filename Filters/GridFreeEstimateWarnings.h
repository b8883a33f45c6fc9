// What the user hears of a batch of estimates: the warnings it ends with (an
// abort and what each point holds, points short of the target, error bars
// that cannot be trusted, NaN results, escaped or truncated walks, ...),
// the projected time of a long solve, and the Debug summary. Only the
// counts a batch found go in; the wording is here, in one place.
// Private to the GridFree::Filters module.
#ifndef GridFreeEstimateWarnings_h
#define GridFreeEstimateWarnings_h

#include <array>
#include <cstdint>
#include <functional>
#include <string>

class vtkAlgorithm;

namespace gridfree
{
// The counts a batch's warnings quote.
struct BatchFindings
{
  std::string Name; // of the solution arrays
  std::int64_t Points = 0;
  int WalksPerPoint = 0;
  int MaxSteps = 0;
  double Target = 0.0; // the target standard error (0: a fixed walk count)
  // Walks per point taken from kept sums: a refinement, which repeats no
  // warning its first solve gave.
  int ResumedWalksPerPoint = 0;
  bool Completed = true;
  double Seconds = 0.0;
  bool Biharmonic = false;
  bool AnyDerivative = false;
  bool UnboundedSource = false;
  // After an abort: points with all their walks, and points with none.
  std::uint64_t PointsFinished = 0;
  std::uint64_t PointsWithoutWalks = 0;
  std::uint64_t BackFaceHits = 0;
  // Points outside the closed boundary with the polynomial control variate (NaN).
  std::uint64_t PointsOutsideShift = 0;
  std::int64_t PointsShortOfTarget = 0;
  std::uint64_t UnreliableErrorBars = 0;
  // Fixed-count mode: how far unreliable points may walk on (a factor of
  // WalksPerPoint; 1: not at all), and how many did.
  int WalkOnWhereUnreliable = 1;
  std::uint64_t PointsWalkedOn = 0;
  std::int64_t UnevenWeights = 0;
  std::int64_t OneWalkSpread = 0;
  // Finite probe points whose results are NaN anyway (overflowed walks).
  std::int64_t NanResults = 0;
  // The walks' totals.
  std::uint64_t Walks = 0;
  std::uint64_t WalksRun = 0;
  std::uint64_t Steps = 0;
  std::uint64_t Escaped = 0;
  std::uint64_t Truncated = 0;
  std::uint64_t Returns = 0;
  // Points with derivatives, one-sided derivatives, none (DerivativeStatus).
  std::array<std::uint64_t, 3> StatusCounts{ 0, 0, 0 };
};

// Which of the warnings the caller wants (PointEstimateRun's).
struct BatchWarningChoice
{
  bool ShortOfTarget = true;
  bool UnreliableErrorBars = true;
};

// "3 minutes", "5 hours", "2 days": a projected solve time for a message.
std::string DescribeDuration(double seconds);

// The warning of a batch projected to take `projected` seconds.
std::string LongSolveWarning(double projected, std::int64_t points, int walksPerPoint);

// Hands each warning the batch deserves to `warn`, in the order a user
// reads them (an abort's alone); the derivatives' one-sided points go to
// `self`'s debug output.
void WarnAboutBatch(vtkAlgorithm* self, const BatchFindings& found,
  const BatchWarningChoice& choice, const std::function<void(const std::string&)>& warn);

// The run's summary line on `self`'s debug output, when its Debug is on.
void DebugSummary(vtkAlgorithm* self, const BatchFindings& found);
} // namespace gridfree

#endif
