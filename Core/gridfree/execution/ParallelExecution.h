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
  std::atomic<bool> finished{ false };
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable wake;

  tbb::task_arena arena(ResolveThreadCount(threads));
  std::thread worker([&] {
    try
    {
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
    const double fraction = count ? double(done.load()) / double(count) : 1.0;
    if (progress && !cancelled && !progress(fraction))
    {
      cancelled = true;
    }
    lock.lock();
  }
  lock.unlock();
  worker.join();
  if (failure)
  {
    std::rethrow_exception(failure);
  }
  return !cancelled;
}
} // namespace gridfree

#endif
