// Bounding volume hierarchy for closest-point and distance queries to a
// boundary made of segments (DIM = 2) or triangles (DIM = 3).
//
// Walk on spheres asks for the distance to the boundary at every step of every
// walk, so this is the hot loop of the whole estimator. Design choices:
//
// * Build: binned surface area heuristic on primitive centroids, O(n log n),
//   collapsed on the fly into a 4-wide tree (each node holds the boxes of up to
//   4 children) so that one SSE instruction sequence tests 4 boxes at once.
// * A node fits in one cache line: child boxes are quantized to 8 bits per
//   side relative to the node box and decoded in float. Random queries over a
//   large mesh are bound by memory latency, so smaller nodes pay off.
// * Codes are rounded outward and the query point is rounded to a float
//   interval, so box distances computed in float are guaranteed LOWER bounds
//   after a small relative safety margin: pruning never discards the true
//   closest primitive.
// * Primitives are copied into leaf order with their vertex coordinates
//   inlined (no index indirection), so a leaf is one contiguous memory block.
// * Primitive distances are computed in double with the kernels of
//   ClosestPointPrimitives.h. Triangles first get a plane-distance test (a
//   lower bound, with a margin for its own rounding) that rejects most of the
//   nearly equidistant triangles seen from deep inside a closed surface. The
//   answer is the exact minimum over all primitives: it equals brute force
//   up to the last-bit rounding of the kernels themselves.
// * Traversal is nearest child first with a small fixed stack; Distance()
//   tracks only the squared distance, and ClosestPoint() evaluates the
//   barycentric weights once, for the winning primitive.
//
// Limitation: box distances are computed in float, so for coordinates beyond
// ~1e18 they may overflow to inf; the answer stays correct but pruning is lost.
// Queries are const and allocation free: one Bvh can serve many threads.
#ifndef GRIDFREE_CORE_GEOMETRY_BVH_H
#define GRIDFREE_CORE_GEOMETRY_BVH_H

#include "Geometry/BoundingBox.h"
#include "Geometry/ClosestPointPrimitives.h"
#include "Vector.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#include <emmintrin.h>
#define GRIDFREE_BVH_USE_SSE 1
#endif

namespace gridfree
{
template <int DIM>
struct ClosestPointResult
{
  Vec<DIM> point = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
  double distance = std::numeric_limits<double>::infinity();
  std::int64_t primitive = -1;
  Vec<DIM> barycentric = Vec<DIM>::Zero();
};

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

/// Largest float <= v (directed rounding without touching the FPU mode).
inline float FloatDown(double v)
{
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v)
  {
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  }
  return f;
}

/// Smallest float >= v.
inline float FloatUp(double v)
{
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v)
  {
    f = std::nextafter(f, std::numeric_limits<float>::infinity());
  }
  return f;
}

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

  /// Maximum number of primitives per leaf. Small leaves suit distance
  /// queries, whose primitive tests cost more than a 4-wide box test.
  static constexpr int kMaxLeafSize = 4;
  static_assert(kMaxLeafSize <= 7, "leaf counts are stored in 3 bits");

  /// Builds the hierarchy; O(n log n). Replaces any previous content. Throws
  /// std::out_of_range for a vertex index outside `vertices`.
  void Build(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives);

  bool Empty() const { return this->Primitives.empty(); }
  std::size_t NumberOfPrimitives() const { return this->Primitives.size(); }

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

  /// Closest point, its distance, the ORIGINAL index of its primitive (as
  /// passed to Build) and the barycentric weights of the primitive's vertices.
  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const;

  /// Checks the invariants that exact queries rely on: every decoded child box
  /// encloses the primitives below it (outward rounding), every primitive is
  /// in exactly one leaf of 1..kMaxLeafSize primitives, and the depth fits the
  /// traversal stack. Meant for tests; O(n log n).
  bool Validate() const;

private:
  /// Child reference: internal node index, or a leaf (high bit set) holding
  /// a start offset into Primitives (bits 3..30) and a count (bits 0..2).
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
  /// Each level pushes at most kWidth - 1 entries.
  static constexpr int kStackSize = (kWidth - 1) * kMaxDepth + 1;

  /// Node with kWidth children; 64 bytes, one cache line, for 4 children in
  /// 3D. Child boxes are quantized to 8 bits per side relative to the node
  /// box: Origin + q * Scale, with the codes rounded outward so decoded boxes
  /// always enclose the true ones. Coordinates are relative to Center (the
  /// middle of the whole boundary) so that float precision is not wasted on an
  /// offset. Unused slots hold kEmptyChild.
  struct alignas(64) Node
  {
    float Origin[DIM];
    float Scale[DIM];
    std::uint8_t QLo[DIM][kWidth];
    std::uint8_t QHi[DIM][kWidth];
    std::uint32_t Child[kWidth];
  };

  using PrimitiveData = detail::BvhPrimitive<DIM>;

  // Builder state, alive only during Build().
  struct Range
  {
    std::uint32_t Begin = 0;
    std::uint32_t End = 0;
    std::uint32_t Mid = 0; // split position when !Leaf
    bool Leaf = true;
    BoundingBox<DIM> Box;
  };
  struct BuildState
  {
    std::vector<BoundingBox<DIM>> Boxes; // per original primitive
    std::vector<Vec<DIM>> Centers;       // box centers, used for binning
    std::vector<std::uint32_t> Order;    // permutation being partitioned
  };

  void Evaluate(BuildState& s, Range& r, int level) const;
  std::uint32_t BuildNode(BuildState& s, const Range& r, int level);
  void EncodeBoxes(Node& node, const Range* kids, int count) const;

  void Prefetch(std::uint32_t ref) const
  {
#ifdef GRIDFREE_BVH_USE_SSE
    const char* p;
    std::size_t bytes;
    if (ref & kLeafFlag)
    {
      p = reinterpret_cast<const char*>(this->Primitives.data() + ((ref & ~kLeafFlag) >> 3));
      bytes = (ref & 7u) * sizeof(PrimitiveData);
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
    const __m128i zero = _mm_setzero_si128();
    auto codes = [&](const std::uint8_t* q) { // 4 bytes -> 4 floats
      std::int32_t bits;
      std::memcpy(&bits, q, 4);
      const __m128i b = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero);
      return _mm_cvtepi32_ps(_mm_unpacklo_epi16(b, zero));
    };
    const __m128 origin = _mm_set1_ps(node.Origin[k]);
    const __m128 scale = _mm_set1_ps(node.Scale[k]);
    lo = _mm_add_ps(origin, _mm_mul_ps(codes(node.QLo[k] + 4 * g), scale));
    hi = _mm_add_ps(origin, _mm_mul_ps(codes(node.QHi[k] + 4 * g), scale));
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
        lo[k][c] = node.Origin[k] + node.QLo[k][c] * node.Scale[k];
        hi[k][c] = node.Origin[k] + node.QHi[k][c] * node.Scale[k];
      }
#endif
    }
  }

  /// Float lower bounds of the squared distances from the query interval
  /// [xlo, xhi] to the child boxes; returns the mask of those <= threshold.
  static int BoxDistances(
    const Node& node, const float* xlo, const float* xhi, float threshold, float* dist2)
  {
#ifdef GRIDFREE_BVH_USE_SSE
    int mask = 0;
    for (int g = 0; g < kWidth / 4; ++g)
    {
      auto axis = [&](int k)
      {
        __m128 lo, hi;
        DecodeAxis(node, k, g, lo, hi);
        const __m128 gap = _mm_max_ps(
          _mm_max_ps(_mm_sub_ps(lo, _mm_set1_ps(xhi[k])), _mm_sub_ps(_mm_set1_ps(xlo[k]), hi)),
          _mm_setzero_ps());
        return _mm_mul_ps(gap, gap);
      };
      __m128 d2 = _mm_add_ps(axis(0), axis(1));
      if constexpr (DIM == 3)
      {
        d2 = _mm_add_ps(d2, axis(2));
      }
      _mm_storeu_ps(dist2 + 4 * g, d2);
      mask |= _mm_movemask_ps(_mm_cmple_ps(d2, _mm_set1_ps(threshold))) << (4 * g);
    }
    return mask;
#else
    float lo[DIM][kWidth], hi[DIM][kWidth];
    DecodeBoxes(node, lo, hi);
    int mask = 0;
    for (int c = 0; c < kWidth; ++c)
    {
      float sum = 0.0f;
      for (int k = 0; k < DIM; ++k)
      {
        const float gap = std::max(std::max(lo[k][c] - xhi[k], xlo[k] - hi[k][c]), 0.0f);
        sum += gap * gap;
      }
      dist2[c] = sum;
      mask |= (sum <= threshold) << c;
    }
    return mask;
#endif
  }

  /// Box of the primitives below a child reference; false if an invariant of
  /// Validate() fails in that subtree.
  bool ValidateSubtree(
    std::uint32_t ref, int depth, std::vector<char>& seen, BoundingBox<DIM>& content) const;

  /// Index (into Primitives) of the nearest primitive, -1 if empty; best2
  /// returns its squared distance.
  std::int64_t FindNearest(const Vec<DIM>& x, double& best2) const;

  std::vector<Node> Nodes;
  std::vector<PrimitiveData> Primitives; // in leaf order
  std::vector<std::int64_t> OriginalIds; // leaf order -> index given to Build
  BoundingBox<DIM> Box;
  Vec<DIM> Center = Vec<DIM>::Zero(); // origin of the node coordinates
};

//------------------------------------------------------------------------------
template <int DIM>
void Bvh<DIM>::Build(
  const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives)
{
  this->Nodes.clear();
  this->Primitives.clear();
  this->OriginalIds.clear();
  this->Box = BoundingBox<DIM>();
  this->Center.setZero();

  const std::size_t n = primitives.size();
  if (n == 0)
  {
    return;
  }
  if (n >= kMaxPrimitives)
  {
    throw std::length_error("gridfree::Bvh: too many primitives");
  }

  BuildState s;
  s.Boxes.resize(n);
  s.Centers.resize(n);
  s.Order.resize(n);
  const auto numVerts = static_cast<std::int64_t>(vertices.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    BoundingBox<DIM> b;
    for (const std::int64_t v : primitives[i])
    {
      if (v < 0 || v >= numVerts)
      {
        throw std::out_of_range("gridfree::Bvh: primitive references a missing vertex");
      }
      b.Expand(vertices[v]);
    }
    s.Boxes[i] = b;
    s.Centers[i] = b.Center();
    s.Order[i] = static_cast<std::uint32_t>(i);
    this->Box.Expand(b);
  }

  Range root;
  root.Begin = 0;
  root.End = static_cast<std::uint32_t>(n);
  this->Evaluate(s, root, 0);
  // The root is always an internal node, so traversal has a single entry path.
  this->Center = this->Box.Center();
  this->Nodes.reserve(2 * n / kMaxLeafSize + 1);
  if (root.Leaf)
  {
    Node node;
    this->EncodeBoxes(node, &root, 1);
    node.Child[0] = kLeafFlag | (root.Begin << 3) | (root.End - root.Begin);
    this->Nodes.push_back(node);
  }
  else
  {
    this->BuildNode(s, root, 0);
  }
  this->Nodes.shrink_to_fit();

  // Copy the primitives in leaf order so that a leaf is contiguous in memory.
  this->Primitives.resize(n);
  this->OriginalIds.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t id = s.Order[i];
    for (int k = 0; k < DIM; ++k)
    {
      this->Primitives[i].V[k] = vertices[primitives[id][k]];
    }
    this->OriginalIds[i] = id;
  }
}

//------------------------------------------------------------------------------
// Computes the range's box and decides whether it becomes a leaf or where it
// splits, using a 16-bin SAH sweep over each axis of the centroid box.
template <int DIM>
void Bvh<DIM>::Evaluate(BuildState& s, Range& r, int level) const
{
  constexpr int kBins = 16;
  // Relative cost of descending one level vs. one primitive test; box tests
  // are cheap (4 at a time) compared to a triangle test.
  constexpr double kTraversalCost = 1.0;

  BoundingBox<DIM> centers;
  r.Box = BoundingBox<DIM>();
  for (std::uint32_t i = r.Begin; i < r.End; ++i)
  {
    r.Box.Expand(s.Boxes[s.Order[i]]);
    centers.Expand(s.Centers[s.Order[i]]);
  }
  r.Leaf = true;
  r.Mid = r.Begin;
  const std::uint32_t n = r.End - r.Begin;
  if (n <= 1)
  {
    return;
  }
  const bool mustSplit = n > static_cast<std::uint32_t>(kMaxLeafSize);
  const Vec<DIM> extent = centers.Extent();

  // Object median along the longest centroid axis: always balanced, used when
  // the SAH has no valid split or the tree got too deep.
  auto medianSplit = [&]()
  {
    const int axis = centers.LongestAxis();
    r.Mid = r.Begin + n / 2;
    std::nth_element(s.Order.begin() + r.Begin, s.Order.begin() + r.Mid, s.Order.begin() + r.End,
      [&](std::uint32_t p, std::uint32_t q) { return s.Centers[p][axis] < s.Centers[q][axis]; });
    r.Leaf = false;
  };

  if (level >= kMaxSahLevel || !(extent.maxCoeff() > 0.0))
  {
    if (mustSplit)
    {
      medianSplit();
    }
    return;
  }

  struct Bin
  {
    std::uint32_t Count = 0;
    BoundingBox<DIM> Box;
  };
  double bestCost = std::numeric_limits<double>::infinity();
  int bestAxis = -1;
  int bestBin = -1;
  for (int axis = 0; axis < DIM; ++axis)
  {
    if (!(extent[axis] > 0.0))
    {
      continue;
    }
    const double lo = centers.Min[axis];
    const double scale = kBins / extent[axis];
    Bin bins[kBins];
    for (std::uint32_t i = r.Begin; i < r.End; ++i)
    {
      const std::uint32_t id = s.Order[i];
      const int b = std::min(kBins - 1, static_cast<int>((s.Centers[id][axis] - lo) * scale));
      bins[b].Count++;
      bins[b].Box.Expand(s.Boxes[id]);
    }
    // Right-to-left sweep stores the cost of the right part of every split.
    double rightCost[kBins];
    BoundingBox<DIM> acc;
    std::uint32_t count = 0;
    for (int b = kBins - 1; b > 0; --b)
    {
      acc.Expand(bins[b].Box);
      count += bins[b].Count;
      rightCost[b] = count ? acc.HalfArea() * count : 0.0;
    }
    acc = BoundingBox<DIM>();
    count = 0;
    for (int b = 1; b < kBins; ++b) // split between bins b - 1 and b
    {
      acc.Expand(bins[b - 1].Box);
      count += bins[b - 1].Count;
      if (count == 0 || count == n)
      {
        continue;
      }
      const double cost = acc.HalfArea() * count + rightCost[b];
      if (cost < bestCost)
      {
        bestCost = cost;
        bestAxis = axis;
        bestBin = b;
      }
    }
  }

  if (bestAxis < 0)
  {
    if (mustSplit)
    {
      medianSplit();
    }
    return;
  }
  const double area = r.Box.HalfArea();
  const double splitCost = kTraversalCost + (area > 0.0 ? bestCost / area : 0.0);
  if (!mustSplit && static_cast<double>(n) <= splitCost)
  {
    return;
  }

  const double lo = centers.Min[bestAxis];
  const double scale = kBins / extent[bestAxis];
  const auto mid = std::partition(s.Order.begin() + r.Begin, s.Order.begin() + r.End,
    [&](std::uint32_t id)
    {
      return std::min(kBins - 1, static_cast<int>((s.Centers[id][bestAxis] - lo) * scale)) <
        bestBin;
    });
  r.Mid = static_cast<std::uint32_t>(mid - s.Order.begin());
  r.Leaf = false;
  if (r.Mid == r.Begin || r.Mid == r.End)
  {
    medianSplit(); // cannot happen with exact arithmetic; stay safe anyway
  }
}

//------------------------------------------------------------------------------
// Creates the node for a range that must split, opening up to 4 children: the
// range is split in two, then the child with the largest area is split again
// until there are 4 children or only leaves are left.
template <int DIM>
std::uint32_t Bvh<DIM>::BuildNode(BuildState& s, const Range& r, int level)
{
  Range kids[kWidth];
  int count = 1;
  kids[0] = r;
  for (;;)
  {
    int pick = -1;
    double pickArea = -1.0;
    for (int i = 0; i < count; ++i)
    {
      if (!kids[i].Leaf && kids[i].Box.HalfArea() > pickArea)
      {
        pick = i;
        pickArea = kids[i].Box.HalfArea();
      }
    }
    if (pick < 0 || count == kWidth)
    {
      break;
    }
    const Range parent = kids[pick];
    kids[pick].Begin = parent.Begin;
    kids[pick].End = parent.Mid;
    kids[count].Begin = parent.Mid;
    kids[count].End = parent.End;
    this->Evaluate(s, kids[pick], level + 1);
    this->Evaluate(s, kids[count], level + 1);
    ++count;
  }

  // Nodes are stored depth first: the parent, then each child's subtree.
  const auto index = static_cast<std::uint32_t>(this->Nodes.size());
  Node node;
  this->EncodeBoxes(node, kids, count);
  this->Nodes.push_back(node);
  for (int i = 0; i < count; ++i)
  {
    const Range& kid = kids[i];
    // Recursion reallocates Nodes: compute the child before storing it.
    const std::uint32_t child = kid.Leaf ? (kLeafFlag | (kid.Begin << 3) | (kid.End - kid.Begin))
                                         : this->BuildNode(s, kid, level + 1);
    this->Nodes[index].Child[i] = child;
  }
  return index;
}

//------------------------------------------------------------------------------
// Quantizes the children's boxes, rounding every code outward.
//
// A decoded bound is computed in float as Origin + q * Scale, possibly fused;
// its error is below 2^-23 (|Origin| + q * Scale), so codes are chosen against
// the exact value shifted by the margin 2^-22 (|Origin| + q * Scale). Code 0
// decodes to Origin exactly. Box corners are first moved by 2^-50 of their
// magnitude to cover the rounding of the recentering subtraction.
template <int DIM>
void Bvh<DIM>::EncodeBoxes(Node& node, const Range* kids, int count) const
{
  auto lower = [](double v) { return v - std::abs(v) * 0x1p-50; };
  auto upper = [](double v) { return v + std::abs(v) * 0x1p-50; };
  for (int i = 0; i < kWidth; ++i)
  {
    node.Child[i] = kEmptyChild;
  }
  for (int k = 0; k < DIM; ++k)
  {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (int i = 0; i < count; ++i)
    {
      lo = std::min(lo, lower(kids[i].Box.Min[k] - this->Center[k]));
      hi = std::max(hi, upper(kids[i].Box.Max[k] - this->Center[k]));
    }
    const float origin = detail::FloatDown(lo);
    const double o = origin;
    auto margin = [&](double qs) { return 0x1p-22 * (std::abs(o) + qs); };
    // Smallest scale whose code 255 still decodes above hi; kept normal so
    // that q * Scale never loses relative precision.
    float scale = std::max(
      detail::FloatUp((hi - o + 0x1p-22 * std::abs(o)) / (255.0 * (1.0 - 0x1p-21))), 0x1p-100f);
    while (o + 255.0 * scale - margin(255.0 * scale) < hi)
    {
      scale = std::nextafter(scale, std::numeric_limits<float>::infinity());
    }
    const double sc = scale;
    node.Origin[k] = origin;
    node.Scale[k] = scale;
    for (int i = 0; i < kWidth; ++i)
    {
      if (i >= count)
      {
        node.QLo[k][i] = 255; // empty slot: inverted box, never visited anyway
        node.QHi[k][i] = 0;
        continue;
      }
      const double clo = lower(kids[i].Box.Min[k] - this->Center[k]);
      const double chi = upper(kids[i].Box.Max[k] - this->Center[k]);
      int ql = static_cast<int>(std::min(std::max(std::floor((clo - o) / sc), 0.0), 255.0));
      while (ql > 0 && o + ql * sc + margin(ql * sc) > clo)
      {
        --ql;
      }
      int qh = static_cast<int>(std::min(std::max(std::ceil((chi - o) / sc), 0.0), 255.0));
      while (qh < 255 && o + qh * sc - margin(qh * sc) < chi)
      {
        ++qh;
      }
      node.QLo[k][i] = static_cast<std::uint8_t>(ql);
      node.QHi[k][i] = static_cast<std::uint8_t>(qh);
    }
  }
}

//------------------------------------------------------------------------------
template <int DIM>
std::int64_t Bvh<DIM>::FindNearest(const Vec<DIM>& x, double& best2) const
{
  best2 = std::numeric_limits<double>::infinity();
  if (this->Nodes.empty())
  {
    return -1;
  }
  std::int64_t best = -1;
  float threshold = std::numeric_limits<float>::infinity();

  // The query in node coordinates, as a float interval [xlo, xhi] that
  // contains the exact x - Center despite the rounding of the subtraction.
  float xlo[DIM], xhi[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    const double y = x[k] - this->Center[k];
    xlo[k] = detail::FloatDown(y - std::abs(y) * 0x1p-50);
    xhi[k] = detail::FloatUp(y + std::abs(y) * 0x1p-50);
  }

  struct Entry
  {
    std::uint32_t Ref;
    float Dist2;
  };
  Entry stack[kStackSize];
  int top = 0;
  stack[top++] = Entry{ 0u, 0.0f };

  while (top > 0)
  {
    const Entry entry = stack[--top];
    if (entry.Dist2 > threshold)
    {
      continue; // a closer primitive was found since this entry was pushed
    }
    std::uint32_t ref = entry.Ref;
    for (;;) // descend towards the nearest child, pushing the others
    {
      if (ref & kLeafFlag)
      {
        const std::uint32_t begin = (ref & ~kLeafFlag) >> 3;
        const std::uint32_t end = begin + (ref & 7u);
        for (std::uint32_t i = begin; i < end; ++i)
        {
          const double d2 = this->Primitives[i].SquaredDistance(x, best2);
          if (d2 < best2)
          {
            best2 = d2;
            best = i;
          }
        }
        threshold = detail::PruneThreshold(best2);
        break;
      }

      const Node& node = this->Nodes[ref];
      float dist2[kWidth];
      const int mask = BoxDistances(node, xlo, xhi, threshold, dist2);
      // Collect the children to visit, sorted by distance. Empty slots hold
      // an inverted box whose finite distance may pass the test: skip them.
      Entry hits[kWidth];
      int numHits = 0;
      for (int c = 0; c < kWidth; ++c)
      {
        if ((mask >> c & 1) && node.Child[c] != kEmptyChild)
        {
          Entry e{ node.Child[c], dist2[c] };
          int j = numHits++;
          for (; j > 0 && hits[j - 1].Dist2 > e.Dist2; --j)
          {
            hits[j] = hits[j - 1];
          }
          hits[j] = e;
        }
      }
      if (numHits == 0)
      {
        break;
      }
      // Random queries over a large mesh are bound by memory latency: request
      // every child that will be visited now, so the misses overlap.
      for (int j = 0; j < numHits; ++j)
      {
        this->Prefetch(hits[j].Ref);
      }
      for (int j = numHits - 1; j > 0; --j)
      {
        stack[top++] = hits[j];
      }
      ref = hits[0].Ref;
    }
  }
  return best;
}

//------------------------------------------------------------------------------
template <int DIM>
bool Bvh<DIM>::Validate() const
{
  if (this->Primitives.empty())
  {
    return this->Nodes.empty() && this->OriginalIds.empty();
  }
  if (this->Nodes.empty() || this->OriginalIds.size() != this->Primitives.size())
  {
    return false;
  }
  std::vector<char> seen(this->Primitives.size(), 0);
  BoundingBox<DIM> content;
  if (!this->ValidateSubtree(0u, 1, seen, content))
  {
    return false;
  }
  return std::all_of(seen.begin(), seen.end(), [](char c) { return c == 1; });
}

template <int DIM>
bool Bvh<DIM>::ValidateSubtree(
  std::uint32_t ref, int depth, std::vector<char>& seen, BoundingBox<DIM>& content) const
{
  content = BoundingBox<DIM>();
  if (ref & kLeafFlag)
  {
    const std::uint32_t begin = (ref & ~kLeafFlag) >> 3;
    const std::uint32_t count = ref & 7u;
    if (count == 0 || count > static_cast<std::uint32_t>(kMaxLeafSize) ||
      begin + count > this->Primitives.size())
    {
      return false;
    }
    for (std::uint32_t i = begin; i < begin + count; ++i)
    {
      seen[i]++;
      for (const auto& v : this->Primitives[i].V)
      {
        content.Expand(v);
      }
    }
    return true;
  }
  if (ref >= this->Nodes.size() || depth > kMaxDepth)
  {
    return false;
  }
  const Node& node = this->Nodes[ref];
  float lo[DIM][kWidth], hi[DIM][kWidth];
  DecodeBoxes(node, lo, hi);
  for (int c = 0; c < kWidth; ++c)
  {
    if (node.Child[c] == kEmptyChild)
    {
      continue;
    }
    BoundingBox<DIM> box;
    if (!this->ValidateSubtree(node.Child[c], depth + 1, seen, box))
    {
      return false;
    }
    for (int k = 0; k < DIM; ++k)
    {
      // Same outward shift as the encoder and the query for the subtraction.
      const double l = box.Min[k] - this->Center[k];
      const double h = box.Max[k] - this->Center[k];
      if (!(lo[k][c] <= l - std::abs(l) * 0x1p-50 && hi[k][c] >= h + std::abs(h) * 0x1p-50))
      {
        return false;
      }
    }
    content.Expand(box);
  }
  return true;
}

//------------------------------------------------------------------------------
template <int DIM>
ClosestPointResult<DIM> Bvh<DIM>::ClosestPoint(const Vec<DIM>& x) const
{
  ClosestPointResult<DIM> result;
  double best2;
  const std::int64_t best = this->FindNearest(x, best2);
  if (best < 0)
  {
    return result;
  }
  const auto cp = this->Primitives[best].ClosestPoint(x);
  result.point = cp.point;
  result.distance = std::sqrt(cp.squaredDistance);
  result.primitive = this->OriginalIds[best];
  result.barycentric = cp.weights;
  return result;
}
} // namespace gridfree

#endif
