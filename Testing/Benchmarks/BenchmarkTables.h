// What the benchmark executables share: timing of a body on 1 or many
// threads (TBB arenas), and Markdown table rows.
#ifndef GRIDFREE_BENCHMARKS_BENCHMARKTABLES_H
#define GRIDFREE_BENCHMARKS_BENCHMARKTABLES_H

#include "BenchmarkMeshes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace gridfree
{
namespace bench
{
using Clock = std::chrono::steady_clock;

inline double Seconds(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Calls body(i) for i in [0, count) on `threads` threads; returns calls/s.
template <typename Body>
inline double RatePerSecond(std::size_t count, int threads, const Body& body)
{
  tbb::task_arena arena(threads);
  const auto start = Clock::now();
  arena.execute([&] {
    tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
        {
          body(i);
        }
      });
  });
  return count / Seconds(start);
}

// How many calls of body fill about `seconds` on one thread: times doubling
// prefixes until one takes 50 ms, then extrapolates. Every measurement of a
// set uses the same count, so all contenders do exactly the same work.
template <typename Body>
std::size_t CountForSeconds(double seconds, std::size_t atMost, const Body& body)
{
  std::size_t chunk = 1;
  for (;;)
  {
    const auto start = Clock::now();
    for (std::size_t i = 0; i < chunk; ++i)
    {
      body(i);
    }
    const double elapsed = Seconds(start);
    if (elapsed >= 0.05 || chunk >= atMost)
    {
      const double rate = chunk / std::max(elapsed, 1e-9);
      return std::clamp<std::size_t>(static_cast<std::size_t>(rate * seconds), chunk, atMost);
    }
    chunk = std::min(2 * chunk, atMost);
  }
}

// ---------------------------------------------------------------- output

// A Markdown table row: the cells, left-aligned text first, "–" for
// negative numbers (no such measurement).
inline std::string Number(double v, const char* format = "%.0f")
{
  if (!(v >= 0.0))
  {
    return "–";
  }
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, v);
  return buffer;
}

inline std::string Ratio(double a, double b)
{
  return a > 0.0 && b > 0.0 ? Number(a / b, "%.1fx") : "–";
}

inline std::string Gain(double a, double b)
{
  return a > 0.0 && b > 0.0 ? Number(a / b, "%.2fx") : "–";
}

inline void PrintRow(const std::vector<std::string>& cells)
{
  std::string line = "|";
  for (const std::string& c : cells)
  {
    line += " " + c + " |";
  }
  std::puts(line.c_str());
  std::fflush(stdout);
}

inline void PrintHeader(const std::vector<std::string>& titles, int textColumns)
{
  PrintRow(titles);
  std::string rule = "|";
  for (std::size_t i = 0; i < titles.size(); ++i)
  {
    rule += static_cast<int>(i) < textColumns ? "---|" : "---:|";
  }
  std::puts(rule.c_str());
}

inline std::string Triangles(std::size_t n)
{
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i)
  {
    if (i > 0 && (digits.size() - i) % 3 == 0)
    {
      out += ',';
    }
    out += digits[i];
  }
  return out;
}
inline double HalfLongestSide(const TriangleMesh& mesh)
{
  const Box box = BoundsOf(mesh);
  return 0.5 * (box.Max - box.Min).maxCoeff();
}

inline std::string FileStem(const std::string& path)
{
  std::string name = path.substr(path.find_last_of("/\\") + 1);
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

} // namespace bench
} // namespace gridfree

#endif
