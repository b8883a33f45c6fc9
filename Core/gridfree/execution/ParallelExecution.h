// Parallel loop over probe points with progress reporting and abort.
//
// The work runs on TBB worker threads while the calling thread stays free to
// report progress and poll for an abort request a few times a second: VTK's
// progress events and ParaView's abort button both live on the calling thread,
// and must not be touched from workers.
#ifndef GRIDFREE_EXECUTION_PARALLEL_EXECUTION_H
#define GRIDFREE_EXECUTION_PARALLEL_EXECUTION_H

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace gridfree
{
// Number of threads a request of `requested` (0 = all) resolves to.
inline int ResolveThreadCount(int requested)
{
  const int available = tbb::info::default_concurrency();
  return requested <= 0 ? available : requested;
}

// TBB sizes its pool of worker threads when its first arena is made: had
// that one a single thread (NumberOfThreads = 1), later arenas of more
// threads would get no workers, and TBB would print "The request for N
// workers is ignored" on stderr. So the first arena made is one of every
// thread, kept for the life of the process.
inline void PrepareThreadPool()
{
  static tbb::task_arena* const everyThread = [] {
    auto* arena = new tbb::task_arena(tbb::task_arena::automatic);
    arena->initialize();
    return arena;
  }();
  (void)everyThread;
}

namespace detail
{
// Runs work() on a thread of its own while the calling thread calls poll()
// about every `pollSeconds` until work is done; exceptions thrown by work
// are rethrown here.
inline void RunPolling(const std::function<void()>& work, const std::function<void()>& poll,
  double pollSeconds)
{
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable wake;
  bool finished = false;
  std::thread worker([&] {
    try
    {
      work();
    }
    catch (...)
    {
      failure = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      finished = true;
    }
    wake.notify_all();
  });
  const auto interval = std::chrono::duration<double>(pollSeconds);
  std::unique_lock<std::mutex> lock(mutex);
  while (!finished)
  {
    wake.wait_for(lock, interval);
    if (finished)
    {
      break;
    }
    lock.unlock();
    poll();
    lock.lock();
  }
  lock.unlock();
  worker.join();
  if (failure)
  {
    std::rethrow_exception(failure);
  }
}
} // namespace detail

// Calls body(begin, end) on disjoint sub-ranges covering [0, count), on
// `threads` threads (0 = all). progress(fraction) is called on the calling
// thread about every `pollSeconds`; when it returns false the loop is
// cancelled: bodies not yet started are skipped and ParallelForWithProgress
// returns false. A body may also poll the returned cancel flag it is passed.
// Exceptions thrown by a body are rethrown here.
inline bool ParallelForWithProgress(std::size_t count, int threads,
  const std::function<void(std::size_t, std::size_t, const std::atomic<bool>&)>& body,
  const std::function<bool(double)>& progress, double pollSeconds = 0.1,
  std::size_t grain = 4)
{
  std::atomic<std::size_t> done{ 0 };
  std::atomic<bool> cancelled{ false };
  PrepareThreadPool();
  tbb::task_arena arena(ResolveThreadCount(threads));
  detail::RunPolling(
    [&] {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
          [&](const tbb::blocked_range<std::size_t>& r) {
            if (cancelled.load(std::memory_order_relaxed))
            {
              return;
            }
            body(r.begin(), r.end(), cancelled);
            done.fetch_add(r.size(), std::memory_order_relaxed);
          });
      });
    },
    [&] {
      const double fraction = count ? double(done.load()) / double(count) : 1.0;
      if (progress && !cancelled && !progress(fraction))
      {
        cancelled = true;
      }
    },
    pollSeconds);
  return !cancelled;
}

// Runs work() on a thread of its own while the calling thread calls
// waiting(seconds since the start) about every `pollSeconds` until it is
// done: for work that can be neither split nor cancelled, such as building a
// boundary's hierarchy, during which the caller's progress reports (and with
// them a GUI's window) must go on. Exceptions thrown by work are rethrown
// here.
inline void RunWhileReporting(const std::function<void()>& work,
  const std::function<void(double)>& waiting, double pollSeconds = 0.1)
{
  const auto start = std::chrono::steady_clock::now();
  detail::RunPolling(work,
    [&] {
      if (waiting)
      {
        waiting(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
    },
    pollSeconds);
}
} // namespace gridfree

#endif
