// Bounding volume hierarchy for closest-point, distance and ray queries to a
// boundary made of segments (DIM = 2) or triangles (DIM = 3).
//
// Walk on spheres asks for the distance to the boundary at every step of every
// walk, so this is the hot loop of the whole estimator. Design choices:
//
// * Build: binned surface area heuristic on primitive centroids, O(n log n),
//   collapsed on the fly into a 4-wide tree (each node holds the boxes of up to
//   4 children) so that one SSE instruction sequence tests 4 boxes at once.
//   The builder partitions compact records (float boxes rounded outward and
//   an index, 28 bytes) in place, so each pass reads memory in order, and it
//   frees them before the primitives are copied: a 10M-triangle soup builds
//   in seconds with a peak of about the soup plus the finished hierarchy.
//   Subtrees of large ranges build as parallel tasks (TBB), each into a node
//   vector of its own appended in order: the same tree on any thread count.
// * A node fits in one cache line: child boxes are quantized to 8 bits per
//   side relative to the node box and decoded in float. Random queries over a
//   large mesh are bound by memory latency, so smaller nodes pay off.
// * Codes are rounded outward and the query point is rounded to a float
//   interval, so box distances computed in float are guaranteed LOWER bounds
//   after a small relative safety margin: pruning never discards the true
//   closest primitive.
// * Primitives are copied into leaf order with their vertex coordinates
//   inlined (no index indirection), so a leaf is one contiguous memory block.
//   Nodes and primitives live on huge pages where the system grants them
//   (HugePageAllocator.h): fewer page walks for random queries.
// * Leaves hold up to 8 primitives in whole groups of four slots (a leaf's
//   unused slots repeat its first primitive). Nearest searches first test a
//   leaf's groups in float, four primitives per SIMD instruction sequence
//   (eight, both groups at once, with AVX2 and AVX-512; BvhLeafFilter.h):
//   a rigorous lower bound skips the primitives proved
//   farther than the nearest one so far, so the exact tests, their answers
//   and their ties are those of an unfiltered search on every instruction
//   set. The SAH counts a leaf's cost in groups.
// * Primitive distances are computed in double with the kernels of
//   ClosestPointPrimitives.h. Triangles first get a plane-distance test (a
//   lower bound, with a margin for its own rounding) that rejects most of the
//   nearly equidistant triangles seen from deep inside a closed surface. The
//   answer is the exact minimum over all primitives: it equals brute force
//   up to the last-bit rounding of the kernels themselves.
// * Traversal is nearest child first with a small fixed stack; nearest
//   searches order a node's children by ranks counted without branches
//   (BvhChildOrder.h), in the order a stable sort gives. Distance()
//   tracks only the squared distance, and ClosestPoint() evaluates the
//   barycentric weights once, for the winning primitive. A walk passes a
//   NearestHint: the primitive nearest to its previous position is measured
//   first and bounds the search from the start, and the closest point at
//   the walk's end needs no search when its last query proved it.
// * Ray queries (Intersect, Occluded) reuse the same nodes: a float slab test
//   per 4 boxes whose intervals are widened for every rounding (it never
//   drops a box the ray enters), nearest child first, pruned by the best hit.
//   Primitive tests are watertight: the ray/triangle test of Woop, Benthin
//   and Wald (2013), with exact signs for the edge functions; in 2D, exact
//   orientation signs of the segment ends (RayKernels.h, ExactPredicates.h).
//   A leaf's float groups first skip the primitives whose projection along
//   the ray is proved to miss it (BvhLeafFilter.h); the hits are the same.
//
// * The searches are compiled for SSE2, AVX2 and AVX-512 and each hierarchy
//   runs the best its CPU supports (SimdDispatch.h); all give the same bits.
//
// Limitation: box distances are computed in float, so for coordinates beyond
// ~1e18 they may overflow to inf; the answer stays correct but pruning is lost.
// Queries are const and allocation free: one Bvh can serve many threads.
#ifndef GRIDFREE_GEOMETRY_BVH_H
#define GRIDFREE_GEOMETRY_BVH_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/geometry/BvhChildOrder.h>
#include <gridfree/geometry/BvhLeafFilter.h>
#include <gridfree/geometry/ClosestPointResult.h>
#include <gridfree/geometry/FloatRounding.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/geometry/HugePageAllocator.h>
#include <gridfree/geometry/RayKernels.h>
#include <gridfree/geometry/SimdDispatch.h>
#include <gridfree/math/Vector.h>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

// GRIDFREE_BVH_SCALAR selects the portable scalar box tests even where SSE2
// exists: the tests build the hierarchy both ways, each against brute force.
#if !defined(GRIDFREE_BVH_SCALAR) &&                                                          \
  (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define GRIDFREE_BVH_USE_SSE 1
#endif

namespace gridfree
{
namespace detail
{
/// The primitive of a DIM-dimensional boundary: segments in 2D, triangles in
/// 3D. Vertices are stored inline (DIM vertices of DIM coordinates).
template <int DIM>
struct BvhPrimitive;

template <>
struct BvhPrimitive<2>
{
  Vec2 V[2];
  double SquaredDistance(const Vec2& x, double /*bound2*/) const
  {
    // A line-distance early out (as for triangles) does not pay off here:
    // the segment kernel is barely more expensive than the test.
    return SquaredDistanceToSegment<2>(x, this->V[0], this->V[1]);
  }
  PrimitiveClosestPoint<2, 2> ClosestPoint(const Vec2& x) const
  {
    return ClosestPointOnSegment<2>(x, this->V[0], this->V[1]);
  }
};

template <>
struct BvhPrimitive<3>
{
  Vec3 V[3];
  double SquaredDistance(const Vec3& x, double bound2) const
  {
    return SquaredDistanceToTriangle(x, this->V[0], this->V[1], this->V[2], bound2);
  }
  PrimitiveClosestPoint<3, 3> ClosestPoint(const Vec3& x) const
  {
    return ClosestPointOnTriangle(x, this->V[0], this->V[1], this->V[2]);
  }
};

/// Float threshold T such that a float box distance d2f > T proves that the
/// exact box distance exceeds best2 (no primitive inside can be closer).
///
/// With outward-rounded boxes and a query interval [xlo, xhi], every gap
/// max(lo - xhi, xlo - hi, 0) is a lower bound before rounding; the float
/// subtraction, squares and sums then overestimate it by a factor of at most
/// (1 + 2^-24)^5. The threshold is inflated by 2^-19 (> 5 * 2^-24 plus its
/// own rounding) and kept >= FLT_MIN, below which the float arithmetic is no
/// longer relative.
inline float PruneThreshold(double best2)
{
  const float t = static_cast<float>(best2) * (1.0f + 0x1p-19f);
  return t > FLT_MIN ? t : FLT_MIN;
}

} // namespace detail

template <int DIM>
class Bvh
{
  static_assert(DIM == 2 || DIM == 3, "Bvh supports segments in 2D and triangles in 3D");

public:
  /// Vertex indices of one primitive: a segment in 2D, a triangle in 3D.
  using Primitive = std::array<std::int64_t, DIM>;

  /// Maximum number of primitives per leaf (the SAH below decides the
  /// size): two groups of the leaf filter (BvhLeafFilter.h). With the filter
  /// and a leaf cost counted in groups, leaves of up to 8 gave 45-65% more
  /// uniform closest-point queries per second than leaves of 3 tested one
  /// primitive at a time, and near-surface rates within 8%.
  static constexpr int kMaxLeafSize = 8;
  static_assert(kMaxLeafSize <= 8, "leaf counts are stored in 3 bits, minus one");

  /// Builds the hierarchy; O(n log n). Replaces any previous content. Throws
  /// std::out_of_range for a vertex index outside `vertices`.
  void Build(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives);

  bool Empty() const { return this->Primitives.empty(); }
  std::size_t NumberOfPrimitives() const { return this->Count; }

  /// Box of all vertices referenced by primitives (empty box if none).
  const BoundingBox<DIM>& Bounds() const { return this->Box; }

  /// Exact unsigned distance to the nearest primitive; inf if empty.
  double Distance(const Vec<DIM>& x) const { return std::sqrt(this->SquaredDistance(x)); }

  /// Exact squared distance to the nearest primitive; inf if empty.
  double SquaredDistance(const Vec<DIM>& x) const
  {
    double best2 = std::numeric_limits<double>::infinity();
    this->FindNearest(x, best2);
    return best2;
  }

  /// What a walk carries from one query to the next: the nearest primitive
  /// its last query found, and whether that query proved it nearest to the
  /// point it asked about. A walk's next position is one ball radius away,
  /// so the same primitive or a neighbour is usually nearest again: measured
  /// first, it bounds the search from the outset (a query started from a
  /// cached primitive near the walker). Answers stay exact, or within the
  /// relaxation, whatever the hint holds; only ties may resolve differently.
  /// A hint belongs to one hierarchy and one walk (one thread).
  struct NearestHint
  {
    std::int64_t Primitive = -1; // index in leaf order, -1 for none
    bool Exact = false;          // Primitive is a nearest one to Point
    Vec<DIM> Point = Vec<DIM>::Constant(std::numeric_limits<double>::quiet_NaN());
  };

  /// SquaredDistance, starting from and updating a hint.
  double SquaredDistance(const Vec<DIM>& x, NearestHint& hint) const
  {
    double best2;
    hint.Primitive = this->FindNearest(x, best2, nullptr, hint.Primitive);
    hint.Exact = true;
    hint.Point = x;
    return best2;
  }

  /// Closest point, its distance, the ORIGINAL index of its primitive (as
  /// passed to Build) and the barycentric weights of the primitive's vertices.
  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const
  {
    NearestHint none;
    return this->ClosestPoint(x, none);
  }

  /// ClosestPoint, starting from and updating a hint. When the hint's last
  /// query was at this very x and proved its primitive nearest (a walk that
  /// stops after an exact step radius), no search is needed.
  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x, NearestHint& hint) const;

  /// A lower bound L of the distance d with d / (1 + relaxation) <= L <= d,
  /// for the step radius of a walk. While the nearest distance found so far
  /// exceeds `exactBelow`, subtrees are skipped unless they could be closer
  /// than 1 / (1 + relaxation) of it; L is the smaller of the nearest
  /// distance found and the nearest skipped box. Deep inside a closed surface
  /// nearly every triangle is almost equidistant, and an exact answer must
  /// visit them all; the relaxed one stops after O(1 / relaxation²) boxes.
  /// `exact` tells whether L is the exact distance (no skipped box is nearer).
  /// With a hint, the search starts from its primitive and leaves in it the
  /// nearest one found (proved nearest when `exact`).
  double DistanceLowerBound(const Vec<DIM>& x, double relaxation, double exactBelow, bool& exact,
    NearestHint* hint = nullptr) const
  {
    Relaxation r;
    r.Shrink2 = 1.0 / ((1.0 + relaxation) * (1.0 + relaxation));
    r.ExactBelow2 = exactBelow * exactBelow;
    double best2 = std::numeric_limits<double>::infinity();
    const std::int64_t best = this->FindNearest(x, best2, &r, hint ? hint->Primitive : -1);
    // Float box distances may exceed the exact ones by (1 + 2^-24)^5 at most.
    const double pruned2 = static_cast<double>(r.MinPruned2) * (1.0 - 0x1p-19);
    exact = !(pruned2 < best2);
    if (hint)
    {
      hint->Primitive = best;
      hint->Exact = exact;
      hint->Point = x;
    }
    return std::sqrt(exact ? best2 : pruned2);
  }

  /// Nearest hit of the ray origin + t * direction with tMin <= t <= tMax;
  /// t is in units of direction, which need not have unit length. Box tests
  /// never discard a hit, and primitive tests are watertight: a ray through
  /// an edge or vertex shared by primitives of a closed boundary hits at
  /// least one of them. Primitives parallel to the ray (containing it
  /// included) and degenerate ones are never hit. No hit for a zero or
  /// non-finite ray or an empty window. The point is origin + t * direction.
  RayHit<DIM> Intersect(const Vec<DIM>& origin, const Vec<DIM>& direction,
    double tMax = std::numeric_limits<double>::infinity(), double tMin = 0.0) const;

  /// Whether any primitive is hit with tMin <= t <= tMax; stops at the first
  /// one found. Visibility between points a and b: Occluded(a, b - a,
  /// 1 - eps, eps), the small eps skipping primitives that a or b lie on.
  bool Occluded(const Vec<DIM>& origin, const Vec<DIM>& direction,
    double tMax = std::numeric_limits<double>::infinity(), double tMin = 0.0) const
  {
    double t = tMax;
    Vec<DIM> w;
    return this->template TraceRay<true>(origin, direction, tMin, t, w) >= 0;
  }

  /// Bytes held by the hierarchy: nodes, primitives in leaf order (with
  /// their vertices inlined, in double and in float groups of four) and the
  /// map back to the original indices.
  std::size_t MemoryBytes() const
  {
    return this->Nodes.capacity() * sizeof(Node) +
      this->Primitives.capacity() * sizeof(PrimitiveData) +
      this->Groups.capacity() * sizeof(detail::BvhLeafGroup<DIM>) +
      this->OriginalIds.capacity() * sizeof(std::uint32_t);
  }

  /// Instruction set the searches run with (see SimdDispatch.h): by default
  /// the best the CPU supports, lowered by GRIDFREE_SIMD. Every level gives
  /// bit-identical answers. Setting asks for a level; the one in effect
  /// (never above CpuSimdLevel()) is returned.
  SimdLevel SetSimdLevel(SimdLevel level)
  {
    this->Simd = level < CpuSimdLevel() ? level : CpuSimdLevel();
    return this->Simd;
  }
  SimdLevel GetSimdLevel() const { return this->Simd; }

  /// Checks the invariants that exact queries rely on: every decoded child box
  /// encloses the primitives below it (outward rounding), every primitive is
  /// in exactly one leaf slot and every group in one leaf, a leaf's unused
  /// slots repeat its first primitive, the float groups are the primitives
  /// rounded to nearest, and the depth fits the traversal stack. Meant for
  /// tests; O(n log n).
  bool Validate() const;

private:
  /// Child reference: internal node index, or a leaf (high bit set) holding
  /// its first group (bits 3..30; its primitives start at slot 4 * group)
  /// and its count minus one (bits 0..2).
  static constexpr std::uint32_t kLeafFlag = 0x80000000u;
  static constexpr std::uint32_t kEmptyChild = 0xffffffffu;
  static constexpr std::size_t kMaxPrimitives = std::size_t(1) << 28;

  /// Children per node, a multiple of the 4 SSE lanes. 8 was measured slower
  /// near the surface (deeper but smaller nodes win when latency bound).
  static constexpr int kWidth = 4;
  static_assert(kWidth % 4 == 0, "nodes are tested 4 children at a time");

  /// Below this tree level the builder switches from SAH to median splits,
  /// which bounds the depth (and the traversal stack) for any input: median
  /// splits at least halve the count per level, and counts are below 2^28.
  static constexpr int kMaxSahLevel = 32;
  static constexpr int kMaxDepth = kMaxSahLevel + 30;
  /// Each level pushes at most kWidth - 1 entries; one more slot above the
  /// top takes VisitRanked's writes of the children it does not push.
  static constexpr int kStackSize = (kWidth - 1) * kMaxDepth + 2;

  /// Node with kWidth children; 64 bytes, one cache line, for 4 children in
  /// 3D. Child boxes are quantized to 8 bits per side relative to the node
  /// box: Origin + q * Scale, with the codes rounded outward so decoded boxes
  /// always enclose the true ones. Coordinates are relative to Center (the
  /// middle of the whole boundary) so that float precision is not wasted on an
  /// offset. Unused slots hold kEmptyChild. Q[kLow] holds the low sides'
  /// codes and Q[kHigh] the high sides', so that a ray picks the side it
  /// enters through by index rather than by a branch.
  struct alignas(64) Node
  {
    float Origin[DIM];
    float Scale[DIM];
    std::uint8_t Q[2][DIM][kWidth];
    std::uint32_t Child[kWidth];
  };
  static constexpr int kLow = 0;
  static constexpr int kHigh = 1;

  using PrimitiveData = detail::BvhPrimitive<DIM>;

  // Builder state, alive only during Build().
  struct BuildRecord;
  /// Box and centroid box of a range of records, in float (the records'
  /// boxes are rounded outward, and float min / max is exact).
  struct RangeBounds
  {
    float Lo[DIM], Hi[DIM], CLo[DIM], CHi[DIM];
    void Reset()
    {
      for (int k = 0; k < DIM; ++k)
      {
        this->Lo[k] = this->CLo[k] = std::numeric_limits<float>::infinity();
        this->Hi[k] = this->CHi[k] = -std::numeric_limits<float>::infinity();
      }
    }
    void Add(const BuildRecord& p)
    {
      for (int k = 0; k < DIM; ++k)
      {
        this->Lo[k] = std::min(this->Lo[k], p.Lo[k]);
        this->Hi[k] = std::max(this->Hi[k], p.Hi[k]);
        const float c = p.Center(k);
        this->CLo[k] = std::min(this->CLo[k], c);
        this->CHi[k] = std::max(this->CHi[k], c);
      }
    }
  };
  struct Range
  {
    std::uint32_t Begin = 0;
    std::uint32_t End = 0;
    std::uint32_t Mid = 0; // split position when !Leaf
    bool Leaf = true;
    BoundingBox<DIM> Box;
    // Bounds of this range when already known (from the parent's partition,
    // which computes them for both sides while it moves the records), and
    // of the two sides of this range's split once Evaluate has made it.
    bool Known = false;
    RangeBounds Bounds;
    bool SplitKnown = false;
    RangeBounds SplitBounds[2];
  };
  /// One primitive while building: its box rounded outward to float (so it
  /// still encloses the primitive) and its index. The records themselves are
  /// partitioned, not an index permutation into separate arrays, so every
  /// pass over a range reads memory in order: with millions of shuffled soup
  /// triangles the permutation's random reads dominated the build. 28 bytes
  /// in 3D, against 76 for double boxes, centres and an index.
  struct BuildRecord
  {
    float Lo[DIM];
    float Hi[DIM];
    std::uint32_t Id;
    float Center(int axis) const { return 0.5f * (this->Lo[axis] + this->Hi[axis]); }
  };
  struct BuildState
  {
    std::vector<BuildRecord> Records;
  };

  void Evaluate(BuildState& s, Range& r, int level) const;
  /// Appends the subtree of a range that must split to `out`, depth first,
  /// and returns its root's index in `out`. Subtrees of large ranges are
  /// built in parallel (the ranges are disjoint) into vectors of their own
  /// and appended in order, so the tree is the same on any thread count.
  template <class NodeVector>
  std::uint32_t BuildNode(BuildState& s, const Range& r, int level, NodeVector& out) const;
  /// Ranges of at least this many primitives build their children's
  /// subtrees as parallel tasks.
  static constexpr std::uint32_t kParallelBuildSize = 1u << 12;
  /// Primitives per block of the builder's per-primitive loops.
  static constexpr std::size_t kBuildBlock = std::size_t(1) << 14;

  /// Runs two independent parts of the build, as parallel tasks.
  template <class A, class B>
  static void RunBoth(const A& a, const B& b)
  {
#if defined(__SANITIZE_THREAD__)
    // Debian's libtbb is not built with ThreadSanitizer (see BuildNode).
    a();
    b();
#else
    tbb::task_group tasks;
    tasks.run([&a] { a(); });
    b();
    tasks.wait();
#endif
  }

  /// body(block, begin, end) for the blocks of kBuildBlock primitives of
  /// [0, n), on all threads; each block writes only its own elements.
  template <class Body>
  static void ForEachBlock(std::size_t n, const Body& body)
  {
    const std::size_t blocks = (n + kBuildBlock - 1) / kBuildBlock;
    auto run = [&](std::size_t block)
    { body(block, block * kBuildBlock, std::min(n, (block + 1) * kBuildBlock)); };
#if defined(__SANITIZE_THREAD__)
    // Debian's libtbb is not built with ThreadSanitizer (see BuildNode).
    for (std::size_t block = 0; block < blocks; ++block)
    {
      run(block);
    }
#else
    if (blocks == 1)
    {
      run(0);
      return;
    }
    tbb::parallel_for(std::size_t(0), blocks, run);
#endif
  }
  void EncodeBoxes(Node& node, const Range* kids, int count) const;

  /// Brings a child's data towards the cache: a node, or a leaf's float
  /// groups (which every search reads first) and its primitives in double.
  void Prefetch(std::uint32_t ref) const
  {
#ifdef GRIDFREE_BVH_USE_SSE
    const char* p;
    std::size_t bytes;
    if (ref & kLeafFlag)
    {
      const std::uint32_t group = (ref & ~kLeafFlag) >> 3;
      const std::uint32_t count = (ref & 7u) + 1;
      const char* g = reinterpret_cast<const char*>(this->Groups.data() + group);
      const std::size_t gBytes = (count + 3) / 4 * sizeof(detail::BvhLeafGroup<DIM>);
      for (std::size_t off = 0; off < gBytes; off += 64)
      {
        _mm_prefetch(g + off, _MM_HINT_T0);
      }
      _mm_prefetch(g + gBytes - 1, _MM_HINT_T0);
      p = reinterpret_cast<const char*>(this->Primitives.data() + 4 * std::size_t(group));
      bytes = count * sizeof(PrimitiveData);
    }
    else
    {
      p = reinterpret_cast<const char*>(this->Nodes.data() + ref);
      bytes = sizeof(Node);
    }
    for (std::size_t off = 0; off < bytes; off += 64)
    {
      _mm_prefetch(p + off, _MM_HINT_T0);
    }
    _mm_prefetch(p + bytes - 1, _MM_HINT_T0); // data may straddle one more line
#else
    (void)ref;
#endif
  }

#ifdef GRIDFREE_BVH_USE_SSE
  /// Decoded bounds along axis k of the 4 child boxes of group g.
  static void DecodeAxis(const Node& node, int k, int g, __m128& lo, __m128& hi)
  {
    DecodeSides(node, k, g, kLow, lo, hi);
  }

  /// Decoded bounds along axis k of the 4 child boxes of group g: first the
  /// side `first` (kLow or kHigh), then the other one.
  static void DecodeSides(
    const Node& node, int k, int g, int first, __m128& firstSide, __m128& otherSide)
  {
    const __m128i zero = _mm_setzero_si128();
    auto codes = [&](const std::uint8_t* q) { // 4 bytes -> 4 floats
      std::int32_t bits;
      std::memcpy(&bits, q, 4);
      const __m128i b = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero);
      return _mm_cvtepi32_ps(_mm_unpacklo_epi16(b, zero));
    };
    const __m128 origin = _mm_set1_ps(node.Origin[k]);
    const __m128 scale = _mm_set1_ps(node.Scale[k]);
    firstSide = _mm_add_ps(origin, _mm_mul_ps(codes(node.Q[first][k] + 4 * g), scale));
    otherSide = _mm_add_ps(origin, _mm_mul_ps(codes(node.Q[first ^ 1][k] + 4 * g), scale));
  }
#endif

  /// Decoded child boxes of a node, with the same arithmetic as the queries.
  static void DecodeBoxes(const Node& node, float (&lo)[DIM][kWidth], float (&hi)[DIM][kWidth])
  {
    for (int k = 0; k < DIM; ++k)
    {
#ifdef GRIDFREE_BVH_USE_SSE
      for (int g = 0; g < kWidth / 4; ++g)
      {
        __m128 l, h;
        DecodeAxis(node, k, g, l, h);
        _mm_storeu_ps(lo[k] + 4 * g, l);
        _mm_storeu_ps(hi[k] + 4 * g, h);
      }
#else
      for (int c = 0; c < kWidth; ++c)
      {
        lo[k][c] = node.Origin[k] + node.Q[kLow][k][c] * node.Scale[k];
        hi[k][c] = node.Origin[k] + node.Q[kHigh][k][c] * node.Scale[k];
      }
#endif
    }
  }

#ifdef GRIDFREE_BVH_USE_SSE
  /// Float lower bounds of the squared distances from the query interval,
  /// broadcast per axis in qlo and qhi, to the 4 child boxes of group g.
  static __m128 BoxDistances(const Node& node, int g, const __m128* qlo, const __m128* qhi)
  {
    __m128 d2 = _mm_setzero_ps();
    for (int k = 0; k < DIM; ++k)
    {
      __m128 lo, hi;
      DecodeAxis(node, k, g, lo, hi);
      const __m128 gap = _mm_max_ps(
        _mm_max_ps(_mm_sub_ps(lo, qhi[k]), _mm_sub_ps(qlo[k], hi)), _mm_setzero_ps());
      d2 = _mm_add_ps(d2, _mm_mul_ps(gap, gap));
    }
    return d2;
  }
#else
  /// Float lower bounds of the squared distances from the query interval
  /// [xlo, xhi] to the child boxes; returns the mask of those <= threshold.
  static int BoxDistances(
    const Node& node, const float* xlo, const float* xhi, float threshold, float* dist2)
  {
    float lo[DIM][kWidth], hi[DIM][kWidth];
    DecodeBoxes(node, lo, hi);
    int mask = 0;
    for (int c = 0; c < kWidth; ++c)
    {
      float sum = 0.0f;
      for (int k = 0; k < DIM; ++k)
      {
        // Same NaN rule as maxps (the second operand): a NaN box bound (from
        // coordinates beyond the float range) gives a gap of 0, never a prune.
        auto maxps = [](float a, float b) { return a > b ? a : b; };
        const float gap = maxps(maxps(lo[k][c] - xhi[k], xlo[k] - hi[k][c]), 0.0f);
        sum += gap * gap;
      }
      dist2[c] = sum;
      mask |= (sum <= threshold) << c;
    }
    return mask;
  }
#endif

  /// A child to visit and its sort key: a lower bound of its squared
  /// distance (closest points) or of its entry parameter (rays).
  struct Entry
  {
    std::uint32_t Ref;
    float Key;
  };

  /// Index of the lowest set bit of a nonzero mask.
  static int CountTrailingZeros(int mask) { return detail::LowestSetBit(mask); }

  /// Number of set bits of a mask of children.
  static int PopCount(int mask)
  {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_popcount(static_cast<unsigned>(mask));
#else
    int n = 0;
    for (; mask; mask &= mask - 1)
    {
      ++n;
    }
    return n;
#endif
  }

  /// Nearest searches and rays, for a mask of two or more non-empty children:
  /// all are prefetched (random queries over a large mesh are bound by memory
  /// latency, so the misses should overlap), the nearest by key is returned,
  /// and the others are pushed farthest first, in the order of a stable sort,
  /// ranked without branches (BvhChildOrder.h). The nearest child comes from
  /// the ranks directly, not through the stack, so the next node's address
  /// does not wait for the pushes. (An insertion sort's loops over nearly
  /// equal keys were mispredicted about 9 times per ray, too.)
  std::uint32_t VisitRanked(
    const Node& node, int mask, const float* keys, Entry* stack, int& top) const
  {
    static_assert(kWidth == 4, "children are ranked 4 at a time");
    int rank[kWidth];
    const int nearest = detail::RankFourChildren(mask, keys, rank);
    const std::uint32_t ref = node.Child[nearest];
    this->Prefetch(ref);
    // Rank 1 goes on top, the farthest lowest. All four slots are written,
    // without a branch (a loop over the mask was mispredicted about twice
    // per ray): the nearest child and the children outside the mask, all of
    // rank 0, land on the slot above the new top.
    const int last = top + PopCount(mask) - 1;
    for (int c = 0; c < kWidth; ++c)
    {
      stack[last - rank[c]] = Entry{ node.Child[c], keys[c] };
    }
    for (int j = last - 1; j >= top; --j)
    {
      this->Prefetch(stack[j].Ref);
    }
    top = last;
    return ref;
  }

  /// Box of the primitives below a child reference; false if an invariant of
  /// Validate() fails in that subtree.
  bool ValidateSubtree(std::uint32_t ref, int depth, std::vector<char>& seenGroups,
    std::vector<char>& seenIds, BoundingBox<DIM>& content) const;

  /// State of a relaxed nearest search (see DistanceLowerBound).
  struct Relaxation
  {
    double Shrink2 = 1.0;                                      // 1 / (1 + relaxation)²
    double ExactBelow2 = std::numeric_limits<double>::infinity(); // relax only above this
    float MinPruned2 = std::numeric_limits<float>::infinity();    // nearest skipped box
  };

  /// Index (into Primitives) of the nearest primitive, -1 if empty; best2
  /// returns its squared distance. With a relaxation, the nearest primitive
  /// found while skipping boxes that are not much nearer (see above). A valid
  /// `start` (index into Primitives) is measured first: its distance bounds
  /// the search from the outset.
  std::int64_t FindNearest(const Vec<DIM>& x, double& best2, Relaxation* relax = nullptr,
    std::int64_t start = -1) const
  {
#ifdef GRIDFREE_SIMD_DISPATCH
    if (this->Simd == SimdLevel::Avx512)
    {
      return this->FindNearestAvx512(x, best2, relax, start);
    }
    if (this->Simd == SimdLevel::Avx2)
    {
      return this->FindNearestAvx2(x, best2, relax, start);
    }
#endif
    return this->FindNearestBaseline(x, best2, relax, start);
  }
  /// The search; Wide (for the AVX2 and AVX-512 paths) filters a leaf's two
  /// groups in eight lanes at once, with the same bits.
  template <bool Wide = false>
  std::int64_t FindNearestBaseline(
    const Vec<DIM>& x, double& best2, Relaxation* relax, std::int64_t start) const;
#ifdef GRIDFREE_SIMD_DISPATCH
  GRIDFREE_TARGET_AVX2 std::int64_t FindNearestAvx2(
    const Vec<DIM>& x, double& best2, Relaxation* relax, std::int64_t start) const
  {
    return this->template FindNearestBaseline<true>(x, best2, relax, start);
  }
  GRIDFREE_TARGET_AVX512 std::int64_t FindNearestAvx512(
    const Vec<DIM>& x, double& best2, Relaxation* relax, std::int64_t start) const
  {
    return this->template FindNearestBaseline<true>(x, best2, relax, start);
  }
#endif

  /// The ray in node coordinates, for the float box tests of RayBoxes: per
  /// axis the float bounds of the (shifted) origin to subtract from the near
  /// and far planes, the float reciprocal of the (scaled) direction, and
  /// whether the near plane is the upper one (negative direction).
  struct RayBoxQuery
  {
    float NearOrigin[DIM];
    float FarOrigin[DIM];
    float InvDirection[DIM];
    int NearSide[DIM]; // kHigh where the direction is negative, else kLow
  };

  /// Float slab test of the ray against the child boxes: entry receives lower
  /// bounds of the entry parameters, and the mask marks the non-empty
  /// children whose interval [entry, exit] can meet [tMin, tMax]. (Empty
  /// slots are left out explicitly: where a node's scale is zero, or along an
  /// axis the ray does not move on, an inverted box's slabs need not be
  /// empty.)
  ///
  /// The origin bounds enclose the exact origin and the decoded boxes the
  /// exact ones, so before rounding each slab interval contains the exact
  /// one. The subtraction, the reciprocal and the product add a relative
  /// error below 2^-22 (and an absolute one below FLT_MIN when subnormal), so
  /// moving both ends outward by 2^-20 relative plus FLT_MIN makes the test
  /// conservative. An axis with no direction has an infinite reciprocal: its
  /// slab gives +-inf, or NaN (0 * inf) when the origin bound lies exactly in
  /// a box face; maxps / minps return their second operand on NaN, so such an
  /// axis does not constrain the interval, as it should not.
  static int RayBoxes(
    const Node& node, const RayBoxQuery& q, float tMin, float tMax, float* entry)
  {
#ifdef GRIDFREE_BVH_USE_SSE
    const __m128 down = _mm_set1_ps(1.0f - 0x1p-20f);
    const __m128 up = _mm_set1_ps(1.0f + 0x1p-20f);
    const __m128 tiny = _mm_set1_ps(FLT_MIN);
    int mask = 0;
    for (int g = 0; g < kWidth / 4; ++g)
    {
      __m128 tNear = _mm_set1_ps(tMin);
      __m128 tFar = _mm_set1_ps(tMax);
      for (int k = 0; k < DIM; ++k)
      {
        // The side is picked by index: the sign of the direction changes
        // from ray to ray, so a branch on it would be mispredicted often.
        __m128 nearSide, farSide;
        DecodeSides(node, k, g, q.NearSide[k], nearSide, farSide);
        const __m128 inv = _mm_set1_ps(q.InvDirection[k]);
        const __m128 n = _mm_mul_ps(_mm_sub_ps(nearSide, _mm_set1_ps(q.NearOrigin[k])), inv);
        const __m128 f = _mm_mul_ps(_mm_sub_ps(farSide, _mm_set1_ps(q.FarOrigin[k])), inv);
        tNear = _mm_max_ps(n, tNear);
        tFar = _mm_min_ps(f, tFar);
      }
      tNear = _mm_sub_ps(_mm_min_ps(_mm_mul_ps(tNear, down), _mm_mul_ps(tNear, up)), tiny);
      tFar = _mm_add_ps(_mm_max_ps(_mm_mul_ps(tFar, up), _mm_mul_ps(tFar, down)), tiny);
      _mm_storeu_ps(entry + 4 * g, tNear);
      const __m128 empty = _mm_castsi128_ps(_mm_cmpeq_epi32(
        _mm_loadu_si128(reinterpret_cast<const __m128i*>(node.Child + 4 * g)),
        _mm_set1_epi32(-1)));
      mask |= _mm_movemask_ps(_mm_andnot_ps(empty, _mm_cmple_ps(tNear, tFar))) << (4 * g);
    }
    return mask;
#else
    float lo[DIM][kWidth], hi[DIM][kWidth];
    DecodeBoxes(node, lo, hi);
    int mask = 0;
    for (int c = 0; c < kWidth; ++c)
    {
      float tNear = tMin;
      float tFar = tMax;
      for (int k = 0; k < DIM; ++k)
      {
        const bool negative = q.NearSide[k] == kHigh;
        const float n =
          ((negative ? hi[k][c] : lo[k][c]) - q.NearOrigin[k]) * q.InvDirection[k];
        const float f =
          ((negative ? lo[k][c] : hi[k][c]) - q.FarOrigin[k]) * q.InvDirection[k];
        tNear = n > tNear ? n : tNear; // NaN leaves the bound unchanged
        tFar = f < tFar ? f : tFar;
      }
      tNear = std::min(tNear * (1.0f - 0x1p-20f), tNear * (1.0f + 0x1p-20f)) - FLT_MIN;
      tFar = std::max(tFar * (1.0f + 0x1p-20f), tFar * (1.0f - 0x1p-20f)) + FLT_MIN;
      entry[c] = tNear;
      mask |= (tNear <= tFar && node.Child[c] != kEmptyChild) << c;
    }
    return mask;
#endif
  }

  /// Index (into Primitives) of the nearest primitive hit with t in
  /// [tMin, t] (t holds tMax on entry and the hit on return; w its weights),
  /// or of the first one found if AnyHit; -1 if none.
  template <bool AnyHit>
  std::int64_t TraceRay(const Vec<DIM>& origin, const Vec<DIM>& direction, double tMin,
    double& t, Vec<DIM>& w) const
  {
#ifdef GRIDFREE_SIMD_DISPATCH
    if (this->Simd == SimdLevel::Avx512)
    {
      return this->template TraceRayAvx512<AnyHit>(origin, direction, tMin, t, w);
    }
    if (this->Simd == SimdLevel::Avx2)
    {
      return this->template TraceRayAvx2<AnyHit>(origin, direction, tMin, t, w);
    }
#endif
    return this->template TraceRayBaseline<AnyHit>(origin, direction, tMin, t, w);
  }
  /// The traversal; Wide (for the AVX2 and AVX-512 paths) filters a leaf's
  /// two groups in eight lanes at once, with the same bits.
  template <bool AnyHit, bool Wide = false>
  std::int64_t TraceRayBaseline(const Vec<DIM>& origin, const Vec<DIM>& direction, double tMin,
    double& t, Vec<DIM>& w) const;
#ifdef GRIDFREE_SIMD_DISPATCH
  template <bool AnyHit>
  GRIDFREE_TARGET_AVX2 std::int64_t TraceRayAvx2(const Vec<DIM>& origin,
    const Vec<DIM>& direction, double tMin, double& t, Vec<DIM>& w) const
  {
    return this->template TraceRayBaseline<AnyHit, true>(origin, direction, tMin, t, w);
  }
  template <bool AnyHit>
  GRIDFREE_TARGET_AVX512 std::int64_t TraceRayAvx512(const Vec<DIM>& origin,
    const Vec<DIM>& direction, double tMin, double& t, Vec<DIM>& w) const
  {
    return this->template TraceRayBaseline<AnyHit, true>(origin, direction, tMin, t, w);
  }
#endif

  SimdLevel Simd = DefaultSimdLevel(); // instruction set of the searches
  // The two arrays every search reads; huge pages where the system grants
  // them (HugePageAllocator.h).
  std::vector<Node, HugePageAllocator<Node>> Nodes;
  std::vector<PrimitiveData, HugePageAllocator<PrimitiveData>> Primitives; // in leaf order
  // The same primitives in float, four per group (BvhLeafFilter.h): nearest
  // searches read these first and test in double only what they cannot skip.
  std::vector<detail::BvhLeafGroup<DIM>, HugePageAllocator<detail::BvhLeafGroup<DIM>>> Groups;
  double VertexMargin = 0.0; // bound of the float vertices' displacement
  std::vector<std::uint32_t> OriginalIds; // leaf order -> index given to Build (< 2^28)
  BoundingBox<DIM> Box;
  Vec<DIM> Center = Vec<DIM>::Zero(); // origin of the node coordinates
  std::size_t Count = 0;              // primitives given to Build
};
} // namespace gridfree

// The member functions, by job (each file includes this one).
#include <gridfree/geometry/bvh/BvhBuild.h>
#include <gridfree/geometry/bvh/BvhNearest.h>
#include <gridfree/geometry/bvh/BvhRays.h>
#include <gridfree/geometry/bvh/BvhValidate.h>

#endif
