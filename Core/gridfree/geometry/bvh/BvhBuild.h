// Building the hierarchy: the binned SAH sweep, the collapse into 4-wide
// nodes, their quantized child boxes, and the leaves' float groups.
// Part of the hierarchy of Bvh.h, which includes it after the class: include
// <gridfree/geometry/Bvh.h>, not this file.
#ifndef GRIDFREE_GEOMETRY_BVH_BVH_BUILD_H
#define GRIDFREE_GEOMETRY_BVH_BVH_BUILD_H

#include <gridfree/geometry/Bvh.h>

namespace gridfree
{
//------------------------------------------------------------------------------
template <int DIM>
void Bvh<DIM>::Build(
  const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives)
{
  this->Nodes.clear();
  this->Primitives.clear();
  this->Groups.clear();
  this->OriginalIds.clear();
  this->VertexMargin = 0.0;
  this->Count = 0;
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
  this->Count = n;

  // Records (and the boundary box) in blocks on all threads; block boxes are
  // merged in order, and min / max are exact, so the box is the same on any
  // thread count.
  BuildState s;
  s.Records.resize(n);
  const auto numVerts = static_cast<std::int64_t>(vertices.size());
  const std::size_t blocks = (n + kBuildBlock - 1) / kBuildBlock;
  std::vector<BoundingBox<DIM>> blockBoxes(blocks);
  std::vector<RangeBounds> blockBounds(blocks);
  ForEachBlock(n, [&](std::size_t block, std::size_t begin, std::size_t end) {
    blockBounds[block].Reset();
    for (std::size_t i = begin; i < end; ++i)
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
      BuildRecord& record = s.Records[i];
      for (int k = 0; k < DIM; ++k)
      {
        record.Lo[k] = detail::FloatDown(b.Min[k]);
        record.Hi[k] = detail::FloatUp(b.Max[k]);
      }
      record.Id = static_cast<std::uint32_t>(i);
      blockBoxes[block].Expand(b);
      blockBounds[block].Add(record);
    }
  });
  for (const BoundingBox<DIM>& b : blockBoxes)
  {
    this->Box.Expand(b);
  }
  // The root's record bounds too, so that its first pass is not needed.
  Range root;
  root.Known = true;
  root.Bounds.Reset();
  for (const RangeBounds& b : blockBounds)
  {
    for (int k = 0; k < DIM; ++k)
    {
      root.Bounds.Lo[k] = std::min(root.Bounds.Lo[k], b.Lo[k]);
      root.Bounds.Hi[k] = std::max(root.Bounds.Hi[k], b.Hi[k]);
      root.Bounds.CLo[k] = std::min(root.Bounds.CLo[k], b.CLo[k]);
      root.Bounds.CHi[k] = std::max(root.Bounds.CHi[k], b.CHi[k]);
    }
  }

  root.Begin = 0;
  root.End = static_cast<std::uint32_t>(n);
  this->Evaluate(s, root, 0);
  // The root is always an internal node, so traversal has a single entry path.
  this->Center = this->Box.Center();
  // At most one node per 7 primitives is typical (leaves of 2.5 or more, 3
  // leaves per node and a third more for the levels above); reserving for the
  // worst case (one per kMaxLeafSize / 2) would hold 64 bytes per 2 primitives
  // until the shrink below, a third of the peak memory of a 10M build.
  this->Nodes.reserve(n / 6 + 1);
  if (root.Leaf)
  {
    Node node;
    this->EncodeBoxes(node, &root, 1);
    node.Child[0] = kLeafFlag | (root.Begin << 3) | (root.End - root.Begin - 1);
    this->Nodes.push_back(node);
  }
  else
  {
    this->BuildNode(s, root, 0, this->Nodes);
  }
  this->Nodes.shrink_to_fit();

  // The leaves in record order (depth first, children in order), each given
  // slots for whole groups of four (BvhLeafFilter.h) so that its float copies
  // start a group of their own. The leaf references, which hold the range of
  // records while building, are rewritten to hold the first group.
  struct LeafSlots
  {
    std::uint32_t* Ref;
    std::uint32_t Begin; // first record
    std::uint32_t Count;
    std::uint32_t Group; // first group; slots start at 4 * Group
  };
  std::vector<LeafSlots> leaves;
  leaves.reserve(n / 3 + 1);
  std::uint32_t groups = 0;
  auto collect = [&](auto& self, std::uint32_t index) -> void
  {
    for (std::uint32_t& c : this->Nodes[index].Child)
    {
      if (c == kEmptyChild)
      {
        continue;
      }
      if (!(c & kLeafFlag))
      {
        self(self, c);
        continue;
      }
      const std::uint32_t count = (c & 7u) + 1;
      leaves.push_back(LeafSlots{ &c, (c & ~kLeafFlag) >> 3, count, groups });
      groups += (count + 3) / 4;
    }
  };
  collect(collect, 0u);
  const std::size_t slots = std::size_t(4) * groups;
  auto forEachLeaf = [&](const auto& body)
  {
    ForEachBlock(leaves.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t l = begin; l < end; ++l)
      {
        body(leaves[l]);
      }
    });
  };

  // Only the leaf order is needed from here on: release the records before
  // the primitives are copied, to lower the peak memory of large builds. A
  // leaf's unused slots repeat its first primitive, so that every slot is a
  // real primitive (a hint may name any slot).
  this->OriginalIds.resize(slots);
  forEachLeaf([&](const LeafSlots& leaf) {
    for (std::uint32_t j = 0; j < 4 * ((leaf.Count + 3) / 4); ++j)
    {
      this->OriginalIds[4 * std::size_t(leaf.Group) + j] =
        s.Records[leaf.Begin + (j < leaf.Count ? j : 0)].Id;
    }
    *leaf.Ref = kLeafFlag | (leaf.Group << 3) | (leaf.Count - 1);
  });
  std::vector<BuildRecord>().swap(s.Records);

  // Copy the primitives in leaf order so that a leaf is contiguous in memory.
  this->Primitives.resize(slots);
  ForEachBlock(slots, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto& ids = primitives[static_cast<std::size_t>(this->OriginalIds[i])];
      for (int k = 0; k < DIM; ++k)
      {
        this->Primitives[i].V[k] = vertices[ids[k]];
      }
    }
  });

  // Their float copies for the leaf filter, relative to the centre and
  // rounded to nearest: each coordinate moves by at most 2^-24 of the largest
  // one (plus the recentering's 2^-53), so a vertex by less than 2^-23 of it.
  double largest = 0.0;
  for (int k = 0; k < DIM; ++k)
  {
    largest = std::max({ largest, std::abs(this->Box.Min[k] - this->Center[k]),
      std::abs(this->Box.Max[k] - this->Center[k]) });
  }
  this->VertexMargin = largest * 0x1p-23 * (1.0 + 0x1p-20);
  this->Groups.resize(groups);
  ForEachBlock(this->Groups.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t g = begin; g < end; ++g)
    {
      detail::BvhLeafGroup<DIM>& group = this->Groups[g];
      for (int lane = 0; lane < 4; ++lane)
      {
        for (int v = 0; v < DIM; ++v)
        {
          for (int k = 0; k < DIM; ++k)
          {
            group.V[v][k][lane] =
              static_cast<float>(this->Primitives[4 * g + lane].V[v][k] - this->Center[k]);
          }
        }
      }
    }
  });
}

//------------------------------------------------------------------------------
// Computes the range's box and decides whether it becomes a leaf or where it
// splits, using a 16-bin SAH sweep over each axis of the centroid box.
template <int DIM>
void Bvh<DIM>::Evaluate(BuildState& s, Range& r, int level) const
{
  constexpr int kBins = 16;
  // Relative cost of descending one level vs. testing one group of four
  // primitives in float (BvhLeafFilter.h): both are mostly a cache miss.
  // Leaves cost their number of groups, so the heuristic fills whole groups.
  constexpr double kTraversalCost = 2.0;
  auto groupsOf = [](std::uint32_t count) { return static_cast<double>((count + 3) / 4); };

  BuildRecord* const first = s.Records.data() + r.Begin;
  BuildRecord* const last = s.Records.data() + r.End;
  // Range box and centroid box: from the parent's partition, or one pass.
  r.SplitKnown = false;
  if (!r.Known)
  {
    r.Bounds.Reset();
    for (const BuildRecord* p = first; p != last; ++p)
    {
      r.Bounds.Add(*p);
    }
  }
  const float* const boxLo = r.Bounds.Lo;
  const float* const boxHi = r.Bounds.Hi;
  const float* const cLo = r.Bounds.CLo;
  const float* const cHi = r.Bounds.CHi;
  r.Box = BoundingBox<DIM>();
  if (r.End > r.Begin)
  {
    for (int k = 0; k < DIM; ++k)
    {
      r.Box.Min[k] = boxLo[k];
      r.Box.Max[k] = boxHi[k];
    }
  }
  r.Leaf = true;
  r.Mid = r.Begin;
  const std::uint32_t n = r.End - r.Begin;
  if (n <= 1)
  {
    return;
  }
  const bool mustSplit = n > static_cast<std::uint32_t>(kMaxLeafSize);
  int longest = 0;
  double extent[DIM];
  for (int k = 0; k < DIM; ++k)
  {
    extent[k] = static_cast<double>(cHi[k]) - static_cast<double>(cLo[k]);
    longest = extent[k] > extent[longest] ? k : longest;
  }

  // Object median along the longest centroid axis: always balanced, used when
  // the SAH has no valid split or the tree got too deep.
  auto medianSplit = [&]()
  {
    const int axis = longest;
    r.Mid = r.Begin + n / 2;
    std::nth_element(first, first + n / 2, last,
      [&](const BuildRecord& p, const BuildRecord& q) { return p.Center(axis) < q.Center(axis); });
    r.Leaf = false;
    r.SplitKnown = false;
  };

  if (level >= kMaxSahLevel || !(extent[longest] > 0.0))
  {
    if (mustSplit)
    {
      medianSplit();
    }
    return;
  }

  // Bins of all axes filled in one pass over the range.
  struct Bin
  {
    std::uint32_t Count = 0;
    float Lo[DIM];
    float Hi[DIM];
  };
  Bin bins[DIM][kBins];
  // Small ranges use fewer bins: the sweep below costs the same for 5
  // primitives as for 5 million, and near the leaves (most ranges) it was
  // most of the build.
  const int numBins = static_cast<int>(std::min<std::uint32_t>(kBins, std::max<std::uint32_t>(n, 4u)));
  float scale[DIM];
  for (int axis = 0; axis < DIM; ++axis)
  {
    // Float is enough to bin (the same function bins and partitions, so the
    // two always agree); the product is clamped below because rounding may
    // push the largest centre to kBins.
    scale[axis] = extent[axis] > 0.0 ? static_cast<float>(numBins / extent[axis]) : 0.0f;
    for (int b = 0; b < numBins; ++b)
    {
      for (int k = 0; k < DIM; ++k)
      {
        bins[axis][b].Lo[k] = std::numeric_limits<float>::infinity();
        bins[axis][b].Hi[k] = -std::numeric_limits<float>::infinity();
      }
    }
  }
  auto binOf = [&](const BuildRecord& p, int axis)
  {
    // Centres beyond the float range are infinite or NaN, and so may be the
    // product (inf * 0): those go to the last bin (converting NaN to int is
    // undefined, and gave an index far outside the bins).
    const float b = (p.Center(axis) - cLo[axis]) * scale[axis];
    return b < static_cast<float>(numBins - 1) ? (b > 0.0f ? static_cast<int>(b) : 0) : numBins - 1;
  };
  for (const BuildRecord* p = first; p != last; ++p)
  {
    for (int axis = 0; axis < DIM; ++axis)
    {
      Bin& bin = bins[axis][binOf(*p, axis)];
      bin.Count++;
      for (int k = 0; k < DIM; ++k)
      {
        bin.Lo[k] = std::min(bin.Lo[k], p->Lo[k]);
        bin.Hi[k] = std::max(bin.Hi[k], p->Hi[k]);
      }
    }
  }
  auto halfArea = [](const float (&lo)[DIM], const float (&hi)[DIM])
  {
    double e[DIM];
    for (int k = 0; k < DIM; ++k)
    {
      e[k] = std::max(0.0, static_cast<double>(hi[k]) - static_cast<double>(lo[k]));
    }
    if constexpr (DIM == 3)
    {
      return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
    else
    {
      return e[0] + e[1];
    }
  };
  auto grow = [](float (&lo)[DIM], float (&hi)[DIM], const Bin& bin)
  {
    for (int k = 0; k < DIM; ++k)
    {
      lo[k] = std::min(lo[k], bin.Lo[k]);
      hi[k] = std::max(hi[k], bin.Hi[k]);
    }
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
    // Right-to-left sweep stores the cost of the right part of every split.
    double rightCost[kBins];
    float lo[DIM], hi[DIM];
    for (int k = 0; k < DIM; ++k)
    {
      lo[k] = std::numeric_limits<float>::infinity();
      hi[k] = -std::numeric_limits<float>::infinity();
    }
    std::uint32_t count = 0;
    for (int b = numBins - 1; b > 0; --b)
    {
      grow(lo, hi, bins[axis][b]);
      count += bins[axis][b].Count;
      rightCost[b] = count ? halfArea(lo, hi) * groupsOf(count) : 0.0;
    }
    for (int k = 0; k < DIM; ++k)
    {
      lo[k] = std::numeric_limits<float>::infinity();
      hi[k] = -std::numeric_limits<float>::infinity();
    }
    count = 0;
    for (int b = 1; b < numBins; ++b) // split between bins b - 1 and b
    {
      grow(lo, hi, bins[axis][b - 1]);
      count += bins[axis][b - 1].Count;
      if (count == 0 || count == n)
      {
        continue;
      }
      const double cost = halfArea(lo, hi) * groupsOf(count) + rightCost[b];
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
  if (!mustSplit && groupsOf(n) <= splitCost)
  {
    return;
  }

  // Partition (Hoare's scheme), taking both sides' bounds on the way so that
  // the children need no pass of their own.
  auto goesLeft = [&](const BuildRecord& p) { return binOf(p, bestAxis) < bestBin; };
  RangeBounds& left = r.SplitBounds[0];
  RangeBounds& right = r.SplitBounds[1];
  left.Reset();
  right.Reset();
  BuildRecord* i = first;
  BuildRecord* j = last;
  for (;;)
  {
    while (i < j && goesLeft(*i))
    {
      left.Add(*i++);
    }
    while (i < j && !goesLeft(*(j - 1)))
    {
      right.Add(*--j);
    }
    if (i == j)
    {
      break;
    }
    std::swap(*i, *(j - 1)); // *i belongs right and *(j - 1) left: swap them
    left.Add(*i++);
    right.Add(*--j);
  }
  r.SplitKnown = true;
  r.Mid = r.Begin + static_cast<std::uint32_t>(i - first);
  r.Leaf = false;
  if (r.Mid == r.Begin || r.Mid == r.End)
  {
    medianSplit(); // cannot happen: the bins of both sides are not empty
  }
}

//------------------------------------------------------------------------------
// Creates the node for a range that must split, opening up to 4 children: the
// range is split in two, then the child with the largest area is split again
// until there are 4 children or only leaves are left.
template <int DIM>
template <class NodeVector>
std::uint32_t Bvh<DIM>::BuildNode(BuildState& s, const Range& r, int level, NodeVector& out) const
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
      // The first inner child is always taken: a NaN area (inf * 0 for a flat
      // box beyond the float range) must not leave it unsplit, which recursed
      // on the same range forever.
      const double area = kids[i].Box.HalfArea();
      if (!kids[i].Leaf && (pick < 0 || area > pickArea))
      {
        pick = i;
        pickArea = area;
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
    kids[pick].Known = kids[count].Known = parent.SplitKnown;
    kids[pick].Bounds = parent.SplitBounds[0];
    kids[count].Bounds = parent.SplitBounds[1];
    if (parent.End - parent.Begin >= kParallelBuildSize)
    {
      // Both halves of a large range at once: near the root, the splits
      // made before any subtree task starts would otherwise run alone.
      Range& a = kids[pick];
      Range& b = kids[count];
      RunBoth([&] { this->Evaluate(s, a, level + 1); }, [&] { this->Evaluate(s, b, level + 1); });
    }
    else
    {
      this->Evaluate(s, kids[pick], level + 1);
      this->Evaluate(s, kids[count], level + 1);
    }
    ++count;
  }

  // Nodes are stored depth first: the parent, then each child's subtree.
  const auto index = static_cast<std::uint32_t>(out.size());
  Node node;
  this->EncodeBoxes(node, kids, count);
  for (int i = 0; i < count; ++i)
  {
    const Range& kid = kids[i];
    if (kid.Leaf)
    {
      node.Child[i] = kLeafFlag | (kid.Begin << 3) | (kid.End - kid.Begin - 1);
    }
  }
  out.push_back(node);

  int inner = 0;
  for (int i = 0; i < count; ++i)
  {
    inner += !kids[i].Leaf;
  }
  if (r.End - r.Begin < kParallelBuildSize || inner < 2)
  {
    for (int i = 0; i < count; ++i)
    {
      if (!kids[i].Leaf)
      {
        // Recursion reallocates `out`: compute the child before storing it.
        const std::uint32_t child = this->BuildNode(s, kids[i], level + 1, out);
        out[index].Child[i] = child;
      }
    }
    return index;
  }

  // Large range: the inner children's subtrees as parallel tasks, each into
  // a vector of its own, then appended in child order with their node
  // indices moved by where they land, which gives the sequential layout.
  std::vector<Node> subtrees[kWidth];
  auto buildKid = [&](int i)
  {
    subtrees[i].reserve((kids[i].End - kids[i].Begin) / 6 + 1);
    this->BuildNode(s, kids[i], level + 1, subtrees[i]);
  };
#if defined(__SANITIZE_THREAD__)
  // Debian's libtbb is not built with ThreadSanitizer, which then reports
  // false races inside TBB's scheduling; the result is the same in order.
  for (int i = 0; i < count; ++i)
  {
    if (!kids[i].Leaf)
    {
      buildKid(i);
    }
  }
#else
  tbb::task_group tasks;
  for (int i = 0; i < count; ++i)
  {
    if (!kids[i].Leaf)
    {
      tasks.run([&buildKid, i] { buildKid(i); });
    }
  }
  tasks.wait();
#endif
  for (int i = 0; i < count; ++i)
  {
    if (kids[i].Leaf)
    {
      continue;
    }
    const auto base = static_cast<std::uint32_t>(out.size());
    for (Node& n : subtrees[i])
    {
      for (std::uint32_t& c : n.Child)
      {
        if (c != kEmptyChild && !(c & kLeafFlag))
        {
          c += base;
        }
      }
      out.push_back(n);
    }
    std::vector<Node>().swap(subtrees[i]);
    out[index].Child[i] = base; // a subtree's root is its first node
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
        node.Q[kLow][k][i] = 255; // empty slot: inverted box, never visited anyway
        node.Q[kHigh][k][i] = 0;
        continue;
      }
      const double clo = lower(kids[i].Box.Min[k] - this->Center[k]);
      const double chi = upper(kids[i].Box.Max[k] - this->Center[k]);
      // Beyond the float range (|coordinates| > ~3e38) bounds and origin may
      // be infinite and the quotients NaN: take the outermost code then
      // (converting NaN to int is undefined).
      const double fl = std::floor((clo - o) / sc);
      int ql = fl > 0.0 ? static_cast<int>(std::min(fl, 255.0)) : 0;
      while (ql > 0 && o + ql * sc + margin(ql * sc) > clo)
      {
        --ql;
      }
      const double ch = std::ceil((chi - o) / sc);
      int qh = ch < 255.0 ? static_cast<int>(std::max(ch, 0.0)) : 255;
      while (qh < 255 && o + qh * sc - margin(qh * sc) < chi)
      {
        ++qh;
      }
      node.Q[kLow][k][i] = static_cast<std::uint8_t>(ql);
      node.Q[kHigh][k][i] = static_cast<std::uint8_t>(qh);
    }
  }
}
} // namespace gridfree

#endif
