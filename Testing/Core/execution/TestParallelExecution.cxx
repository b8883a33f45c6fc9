#include <gridfree/execution/ParallelExecution.h>

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

using gridfree::ParallelForWithProgress;

TEST(ParallelExecution, VisitsEveryIndexOnce)
{
  std::vector<std::atomic<int>> visits(10007);
  for (auto& v : visits)
  {
    v = 0;
  }
  const bool completed = ParallelForWithProgress(visits.size(), 2,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>&) {
      for (std::size_t i = begin; i < end; ++i)
      {
        ++visits[i];
      }
    },
    [](double) { return true; });
  EXPECT_TRUE(completed);
  for (auto& v : visits)
  {
    ASSERT_EQ(v.load(), 1);
  }
}

TEST(ParallelExecution, AbortStopsSoonAndReportsIt)
{
  std::atomic<std::size_t> processed{ 0 };
  int calls = 0;
  const auto start = std::chrono::steady_clock::now();
  const bool completed = ParallelForWithProgress(100000, 2,
    [&](std::size_t begin, std::size_t end, const std::atomic<bool>& cancel) {
      for (std::size_t i = begin; i < end && !cancel; ++i)
      {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ++processed;
      }
    },
    [&](double fraction) {
      EXPECT_GE(fraction, 0.0);
      EXPECT_LE(fraction, 1.0);
      return ++calls < 3; // abort at the third progress report
    },
    0.05);
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_FALSE(completed);
  EXPECT_LT(processed.load(), 100000u);
  EXPECT_LT(seconds, 1.0); // the whole loop would take ~50 s
}

TEST(ParallelExecution, ExceptionsReachTheCaller)
{
  EXPECT_THROW(ParallelForWithProgress(100, 2,
                 [](std::size_t, std::size_t, const std::atomic<bool>&) {
                   throw std::runtime_error("boom");
                 },
                 nullptr),
    std::runtime_error);
}

TEST(ParallelExecution, ZeroItemsIsFine)
{
  EXPECT_TRUE(ParallelForWithProgress(
    0, 0, [](std::size_t, std::size_t, const std::atomic<bool>&) {}, nullptr));
}
