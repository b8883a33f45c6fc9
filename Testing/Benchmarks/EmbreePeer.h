// Embree as a reference beside our BVH: the same triangles in an Embree
// scene, answering closest-point queries through rtcPointQuery and tracing
// rays with rtcIntersect1 (the speed of light of a tuned hierarchy).
//
// Closest points: Embree's traversal hands each candidate triangle to a
// callback, which computes the exact distance with the same double-precision
// kernel our BVH uses and shrinks the query radius. The comparison therefore
// measures the hierarchy and its traversal, not the triangle kernel.
//
// All queries are const and keep their state on the stack (one query context
// per call), so one peer can serve many threads.
#ifndef GRIDFREE_BENCHMARKS_EMBREEPEER_H
#define GRIDFREE_BENCHMARKS_EMBREEPEER_H

#include <gridfree/math/Vector.h>

#include <embree3/rtcore.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gridfree
{
namespace bench
{
class EmbreePeer
{
public:
  // Builds the scene (binned SAH, Embree's default quality for static
  // scenes, the same kind of builder as ours). Throws std::runtime_error on
  // an Embree error.
  EmbreePeer(
    const std::vector<Vec3>& vertices, const std::vector<std::array<std::int64_t, 3>>& triangles);
  ~EmbreePeer();
  EmbreePeer(const EmbreePeer&) = delete;
  EmbreePeer& operator=(const EmbreePeer&) = delete;

  static std::string Version();

  // Wall time of filling Embree's buffers and committing the scene.
  double BuildSeconds() const { return this->BuildTime; }
  // Bytes Embree holds for the committed scene (its hierarchy plus its own
  // float vertex and index buffers), as reported by its memory monitor.
  std::size_t MemoryBytes() const { return static_cast<std::size_t>(this->Bytes.load()); }

  struct Closest
  {
    double Distance;
    std::int64_t Triangle;
    Vec3 Point;
  };
  // Exact distance to the nearest triangle (inf for an empty scene).
  double Distance(const Vec3& x) const;
  // Distance, triangle and closest point.
  Closest ClosestPoint(const Vec3& x) const;

  // First hit of the ray origin + t·direction, t > 0: true and t, or false.
  bool Intersect(const Vec3& origin, const Vec3& direction, float& t) const;

private:
  struct QueryState;
  static bool PointQueryCallback(RTCPointQueryFunctionArguments* args);
  static bool MemoryMonitor(void* self, ssize_t bytes, bool post);
  void Nearest(QueryState& state) const;

  // Triangles with their vertices inline, in Embree's primitive order, for
  // the callback: one memory block per candidate instead of four.
  std::vector<std::array<Vec3, 3>> Triangles;
  // Largest coordinate magnitude, for the rounding margin of the radius.
  double MaxAbsCoordinate = 0.0;
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  double BuildTime = 0.0;
  std::atomic<long long> Bytes{ 0 };
};
} // namespace bench
} // namespace gridfree

#endif
