// The paper authors' closest-point library fcpw (its vectorized BVH, built on
// enoki) and their walk-on-spheres library zombie on top of it, beside the
// project's hierarchy in GridFreePeerBenchmark. Built only when their public
// sources are given at configure time (GRIDFREE_FCPW_SOURCE_DIR, and
// GRIDFREE_ZOMBIE_SOURCE_DIR with GRIDFREE_PCG32_INCLUDE_DIR for the walks;
// Testing/Benchmarks/CMakeLists.txt); nothing of theirs is in the project.
//
// fcpw fixes its SIMD width at compile time, so FcpwPeer.cxx is compiled
// twice, into one shared library per width (16 lanes for AVX-512, 8 for
// AVX2), each with hidden symbols but its factory: the two builds of fcpw's
// templates never meet. This interface uses plain types only (zombie's pcg32
// and the core's pcg-cpp share a name).
#ifndef GRIDFREE_BENCHMARKS_FCPWPEER_H
#define GRIDFREE_BENCHMARKS_FCPWPEER_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace gridfree
{
namespace bench
{
using PeerPoint = std::array<double, 3>;

struct PeerMesh
{
  std::vector<PeerPoint> Vertices;
  std::vector<std::array<std::int64_t, 3>> Triangles;
};

// A Laplace problem with a closed-form solution: u = Exact on the mesh.
struct PeerWalkProblem
{
  std::function<double(const PeerPoint&)> Exact;
};

struct PeerWalkResult
{
  double SetupSeconds = 0.0; // zombie's boundary handler: fcpw's scene and BVH
  double Seconds = 0.0;      // the walks
  double StepsPerWalk = 0.0;
  // Per point: the estimate of u and, with gradients, of ∇u.
  std::vector<double> Values;
  std::vector<PeerPoint> Gradients;
};

class FcpwPeer
{
public:
  virtual ~FcpwPeer() = default;

  // "fcpw w16" or "fcpw w8".
  virtual const char* Name() const = 0;
  // Filling fcpw's scene and building its vectorized BVH (surface-area
  // heuristic, as zombie builds it), one thread.
  virtual double BuildSeconds() const = 0;
  // Heap bytes the scene holds after the build (its copy of the mesh, the
  // primitives, the hierarchy), from the allocator's statistics.
  virtual std::size_t HeapBytes() const = 0;

  // fcpw's findClosestPoint: the distance (fcpw has no distance-only query);
  // with `point`, the closest point too.
  virtual double ClosestPoint(const PeerPoint& x, PeerPoint* point = nullptr) const = 0;
  // fcpw's intersect: the first hit t > 0 of origin + t·direction (unit).
  virtual bool Intersect(const PeerPoint& origin, const PeerPoint& direction, double& t) const = 0;

  // Whether this build has zombie's walk on spheres.
  virtual bool HasWalks() const = 0;
  // zombie's WalkOnSpheres<float, 3> on this fcpw build, on the mesh given to
  // the factory: `walks` walks per point, ε-shell `epsilon`, one thread,
  // pcg32 streams seeded per point so that runs repeat. With `gradient`, its
  // gradient estimator with its defaults (control variates and antithetic
  // pairs). The set-up (its own scene and BVH) is timed.
  virtual PeerWalkResult Walk(const PeerWalkProblem& problem, const std::vector<PeerPoint>& points,
    int walks, double epsilon, bool gradient) const = 0;
};

// The factories of the two builds. Their code is compiled for AVX-512 and
// AVX2 respectively: call one only where the CPU has that instruction set
// (FcpwPeerRunsHere).
std::unique_ptr<FcpwPeer> CreateFcpwPeerW16(const PeerMesh& mesh);
std::unique_ptr<FcpwPeer> CreateFcpwPeerW8(const PeerMesh& mesh);

inline bool FcpwPeerRunsHere(int width)
{
  return width == 16 ? __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl")
                     : __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
} // namespace bench
} // namespace gridfree

#endif
