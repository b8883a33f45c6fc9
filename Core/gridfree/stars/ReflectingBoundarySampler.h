// Points on the reflecting (Neumann and Robin) part of a boundary inside a
// ball, for the boundary-data term ∫ G h of walk on stars (Documentation/
// WalkOnStars.md §2, the term of Eqn. WoSt-3).
//
// A binary tree of boxes over the primitives, each node knowing the area
// (length in 2D) below it. A sample descends from the root: where both
// children's boxes meet the ball, it picks one with probability ∝ about the
// integral of the Green's function over its part of the ball (ChildWeights);
// where one does, it takes it.
// In the leaf it picks a primitive ∝ area and a uniform point on it. Every
// primitive that meets the ball can be reached, so the estimate G h / pdf is
// unbiased; points outside the ball (or hidden from its centre) are
// rejected by the caller with weight 0.
#ifndef GRIDFREE_STARS_REFLECTING_BOUNDARY_SAMPLER_H
#define GRIDFREE_STARS_REFLECTING_BOUNDARY_SAMPLER_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/stars/BoxTreeTraversal.h>
#include <gridfree/stars/FlatPatches.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sampling/Random.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace gridfree
{
template <int DIM>
struct BoundarySample
{
  Vec<DIM> Point = Vec<DIM>::Zero();
  std::int64_t Primitive = -1; // index as passed to Build
  Vec<DIM> Barycentric = Vec<DIM>::Zero();
  double Pdf = 0.0; // per unit area (length in 2D)
};

template <int DIM>
class ReflectingBoundarySampler
{
public:
  using Primitive = std::array<std::int64_t, DIM>;

  void Build(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives)
  {
    this->Vertices = vertices;
    this->Primitives = primitives;
    this->Order.resize(primitives.size());
    this->Areas.resize(primitives.size());
    this->LeafOf.assign(primitives.size(), 0);
    this->Nodes.clear();
    for (std::size_t i = 0; i < primitives.size(); ++i)
    {
      this->Order[i] = static_cast<std::int64_t>(i);
      this->Areas[i] = this->PrimitiveArea(static_cast<std::int64_t>(i));
    }
    if constexpr (DIM == 3)
    {
      this->PatchReach = FlatPatchAreas(vertices, primitives, this->Areas);
      for (double& reach : this->PatchReach)
      {
        reach = std::sqrt(reach / M_PI);
      }
    }
    if (primitives.empty())
    {
      return;
    }
    this->Nodes.reserve(2 * primitives.size() / kLeafSize + 2);
    this->Nodes.emplace_back();
    this->BuildNode(0, 0, static_cast<std::uint32_t>(primitives.size()), 0, 0);
  }

  bool Empty() const { return this->Nodes.empty() || !(this->Nodes[0].Area > 0.0); }
  double TotalArea() const { return this->Nodes.empty() ? 0.0 : this->Nodes[0].Area; }

  // Draws a point on the primitives whose boxes meet B(x, R); false when
  // none does (the term is then 0).
  bool Sample(const Vec<DIM>& x, double R, RandomStream& rng, BoundarySample<DIM>& out) const
  {
    if (this->Empty() || !(this->Nodes[0].Box.SquaredDistance(x) < R * R))
    {
      return false;
    }
    double pdf = 1.0;
    std::uint32_t index = 0;
    while (this->Nodes[index].Count == 0)
    {
      const Node& node = this->Nodes[index];
      double w0 = 0.0, w1 = 0.0;
      this->ChildWeights(node, x, R, w0, w1);
      if (!(w0 + w1 > 0.0))
      {
        return false;
      }
      const double p0 = w0 / (w0 + w1);
      const bool left = w1 == 0.0 || (w0 > 0.0 && rng.NextDouble() < p0);
      pdf *= left ? p0 : 1.0 - p0;
      index = node.Left + (left ? 0 : 1);
    }
    const Node& leaf = this->Nodes[index];
    if (!(leaf.Area > 0.0))
    {
      return false;
    }
    double pick = rng.NextDouble() * leaf.Area;
    std::uint32_t k = leaf.First;
    for (; k + 1 < leaf.First + leaf.Count; ++k)
    {
      const double a = this->Areas[static_cast<std::size_t>(this->Order[k])];
      if (pick < a)
      {
        break;
      }
      pick -= a;
    }
    const std::int64_t prim = this->Order[k];
    if (!(this->Areas[static_cast<std::size_t>(prim)] > 0.0))
    {
      return false;
    }
    out.Primitive = prim;
    out.Barycentric = UniformBarycentric(rng);
    out.Point = this->PointAt(prim, out.Barycentric);
    out.Pdf = pdf / leaf.Area;
    return true;
  }

  // The density Sample(x, R) has at a point of primitive `prim` (0 when the
  // descent cannot reach it): for tests, and for combining strategies.
  double Pdf(const Vec<DIM>& x, double R, std::int64_t prim) const
  {
    if (this->Empty() || prim < 0 || static_cast<std::size_t>(prim) >= this->LeafOf.size() ||
      !(this->Areas[static_cast<std::size_t>(prim)] > 0.0))
    {
      return 0.0;
    }
    std::uint32_t index = this->LeafOf[static_cast<std::size_t>(prim)];
    double pdf = 1.0 / this->Nodes[index].Area;
    while (index != 0)
    {
      const std::uint32_t parent = this->Nodes[index].Parent;
      const Node& node = this->Nodes[parent];
      double w0 = 0.0, w1 = 0.0;
      this->ChildWeights(node, x, R, w0, w1);
      const double w = index == node.Left ? w0 : w1;
      if (!(w > 0.0))
      {
        return 0.0;
      }
      pdf *= w / (w0 + w1);
      index = parent;
    }
    return this->Nodes[0].Box.SquaredDistance(x) < R * R ? pdf : 0.0;
  }

  // Calls visit(primitive) for every primitive in a leaf whose box is nearer
  // to x than `radius`, which visit may shrink (later boxes are then tested
  // against the smaller radius); nearer subtrees first. The primitive itself
  // may lie farther (SquaredDistance tells). Walk on stars bounds its
  // radius by the Robin primitives this way.
  template <class Visit>
  void VisitWithin(const Vec<DIM>& x, double& radius, const Visit& visit) const
  {
    this->VisitWithin(x, radius, visit, [](std::uint32_t) { return false; });
  }

  // The same, leaving out every subtree whose node `skip(node index)`
  // rules out (a bound on what its primitives could do: RobinRadius.h).
  template <class Visit, class Skip>
  void VisitWithin(const Vec<DIM>& x, double& radius, const Visit& visit, const Skip& skip) const
  {
    if (this->Nodes.empty())
    {
      return;
    }
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0)
    {
      const std::uint32_t index = stack[--top];
      const Node& node = this->Nodes[index];
      if (!(node.Box.SquaredDistance(x) < radius * radius) || skip(index))
      {
        continue;
      }
      if (node.Count > 0)
      {
        for (std::uint32_t i = node.First; i < node.First + node.Count; ++i)
        {
          visit(this->Order[i]);
        }
        continue;
      }
      PushNearerChildLast<DIM>(this->Nodes, node.Left, x, stack, top);
    }
  }

  // The hierarchy's nodes, for summaries of their subtrees kept elsewhere
  // (indexed as the nodes; a child's index exceeds its parent's, so a pass
  // from the last node to the first meets children first): visit(index,
  // box, first, last) with the primitives under the node, first .. last − 1.
  std::size_t NodeCount() const { return this->Nodes.size(); }
  template <class Visit>
  void ForEachNode(const Visit& visit) const
  {
    for (std::size_t i = 0; i < this->Nodes.size(); ++i)
    {
      const Node& node = this->Nodes[i];
      const std::int64_t* first = this->Order.data() + node.First;
      visit(static_cast<std::uint32_t>(i), node.Box, first, first + node.Span);
    }
  }

  // 3D: a point of the plane of triangle `prim` (x lies on it) with density
  // 1/(2π R r) per unit area at distance r < R from x: an angle uniform in
  // the plane and r uniform in [0, R). False for a degenerate triangle.
  // Drawn this way, a term G(r) h / pdf stays bounded as r → 0 (G ~ 1/r),
  // where drawing by area leaves it unbounded (WalkOnStars.h, flux term).
  bool SampleInPlane(
    const Vec<DIM>& x, std::int64_t prim, double R, RandomStream& rng, Vec<DIM>& y) const
  {
    static_assert(DIM == 3, "plane sampling is for triangles");
    const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
    const Vec<DIM>& a = this->Vertices[static_cast<std::size_t>(p[0])];
    const Vec<DIM> e1 = this->Vertices[static_cast<std::size_t>(p[1])] - a;
    const Vec<DIM> normal = e1.cross(this->Vertices[static_cast<std::size_t>(p[2])] - a);
    if (!(normal.squaredNorm() > 0.0))
    {
      return false;
    }
    const Vec<DIM> t1 = e1.normalized();
    const Vec<DIM> t2 = normal.cross(e1).normalized();
    const double angle = 2.0 * M_PI * rng.NextDouble();
    const double r = R * rng.NextDouble();
    y = x + r * (std::cos(angle) * t1 + std::sin(angle) * t2);
    return true;
  }

  // The share of a walker's flux draws made by SampleInPlane when it stands
  // on triangle `prim` with a star of radius R: half where the flat patch
  // around it is large, ρ ≥ R/4 with ρ the radius of a disc of the patch's
  // area (a face of a box, where the plane draws bound G/pdf near x by R
  // and land on the face most of the time), and 2ρ/R below (a finely
  // curved mesh, where the patch is one small triangle and most plane
  // draws would miss it and be thrown away). Any share in (0, 1) keeps the
  // mixture unbiased; a share s bounds G/pdf near x by R/(2s), while the
  // flux term's variance from the rest of the ball grows as 1/(1 − s).
  double PlaneShare(std::int64_t prim, double R) const
  {
    const double reach = 4.0 * this->PatchReach[static_cast<std::size_t>(prim)];
    return R > reach ? 0.5 * reach / R : 0.5;
  }

  // SampleInPlane's density at distance r from x.
  static double NearPdf(double R, double r)
  {
    return r > 0.0 && r < R ? 1.0 / (2.0 * M_PI * R * r) : 0.0;
  }

  // The first vertex of a primitive (a point of its plane).
  const Vec<DIM>& FirstVertex(std::int64_t prim) const
  {
    return this->Vertices[static_cast<std::size_t>(
      this->Primitives[static_cast<std::size_t>(prim)][0])];
  }

  // Squared distance from x to a primitive.
  double SquaredDistance(std::int64_t prim, const Vec<DIM>& x) const
  {
    const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
    if constexpr (DIM == 2)
    {
      return SquaredDistanceToSegment<2>(x, this->Vertices[p[0]], this->Vertices[p[1]]);
    }
    else
    {
      return SquaredDistanceToTriangle(x, this->Vertices[p[0]], this->Vertices[p[1]], this->Vertices[p[2]]);
    }
  }

  double Area(std::int64_t prim) const { return this->Areas[static_cast<std::size_t>(prim)]; }
  Vec<DIM> PointAt(std::int64_t prim, const Vec<DIM>& barycentric) const
  {
    const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
    Vec<DIM> z = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      z += barycentric[k] * this->Vertices[static_cast<std::size_t>(p[k])];
    }
    return z;
  }

private:
  struct Node
  {
    BoundingBox<DIM> Box;
    double Area = 0.0;
    std::uint32_t Parent = 0;
    std::uint32_t Left = 0;  // children Left, Left + 1 (inner node)
    std::uint32_t First = 0; // Order[First .. First + Count − 1] (leaf)
    std::uint32_t Count = 0;
    std::uint32_t Span = 0;  // primitives under the node: Order[First .. First + Span − 1]
  };
  static constexpr std::uint32_t kLeafSize = 4;

  static Vec<DIM> UniformBarycentric(RandomStream& rng)
  {
    Vec<DIM> w;
    if constexpr (DIM == 2)
    {
      const double t = rng.NextDouble();
      w << 1.0 - t, t;
    }
    else
    {
      const double s = std::sqrt(rng.NextDouble());
      const double t = rng.NextDouble();
      w << 1.0 - s, s * (1.0 - t), s * t;
    }
    return w;
  }

  // Branch weights: 0 for a child whose box misses the ball, else about the
  // integral of G over its part of the ball: its area, capped by that of the
  // ball's cross-section (a large subtree that grazes the ball holds little
  // of its area inside), times G at its box's distance d (1/d in 3D,
  // log(R/d) in 2D), with d kept above a tenth of R (3D) or a hundredth (2D).
  // Without the cap, small balls near big subtrees drew from far primitives,
  // and the few near ones they hit carried very large weights.
  void ChildWeights(const Node& node, const Vec<DIM>& x, double R, double& w0, double& w1) const
  {
    const double R2 = R * R;
    const double cap = DIM == 2 ? 2.0 * R : M_PI * R2;
    auto weight = [&](const Node& child) {
      const double d2 = child.Box.SquaredDistance(x);
      if (!(d2 < R2))
      {
        return 0.0;
      }
      const double area = std::min(child.Area, cap);
      if constexpr (DIM == 3)
      {
        return area / std::sqrt(std::max(d2, 0.01 * R2));
      }
      else
      {
        return area * (0.1 + 0.5 * std::log(R2 / std::max(d2, 1e-4 * R2)));
      }
    };
    w0 = weight(this->Nodes[node.Left]);
    w1 = weight(this->Nodes[node.Left + 1]);
  }

  double PrimitiveArea(std::int64_t prim) const
  {
    const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
    const Vec<DIM> e1 = this->Vertices[p[1]] - this->Vertices[p[0]];
    if constexpr (DIM == 2)
    {
      return e1.norm();
    }
    else
    {
      return 0.5 * e1.cross(this->Vertices[p[2]] - this->Vertices[p[0]]).norm();
    }
  }

  void BuildNode(std::uint32_t index, std::uint32_t first, std::uint32_t count,
    std::uint32_t parent, int depth)
  {
    Node node;
    node.Parent = parent;
    node.First = first;
    node.Span = count;
    BoundingBox<DIM> centroids;
    for (std::uint32_t i = first; i < first + count; ++i)
    {
      const std::int64_t prim = this->Order[i];
      const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
      Vec<DIM> c = Vec<DIM>::Zero();
      for (int k = 0; k < DIM; ++k)
      {
        node.Box.Expand(this->Vertices[p[k]]);
        c += this->Vertices[p[k]] / DIM;
      }
      centroids.Expand(c);
      node.Area += this->Areas[static_cast<std::size_t>(prim)];
    }
    if (count <= kLeafSize || depth >= 60)
    {
      node.First = first;
      node.Count = count;
      for (std::uint32_t i = first; i < first + count; ++i)
      {
        this->LeafOf[static_cast<std::size_t>(this->Order[i])] = index;
      }
      this->Nodes[index] = node;
      return;
    }
    const int axis = centroids.LongestAxis();
    const std::uint32_t half = count / 2;
    auto centroid = [this, axis](std::int64_t prim) {
      const Primitive& p = this->Primitives[static_cast<std::size_t>(prim)];
      double s = 0.0;
      for (int k = 0; k < DIM; ++k)
      {
        s += this->Vertices[p[k]][axis];
      }
      return s;
    };
    auto begin = this->Order.begin() + first;
    std::nth_element(begin, begin + half, begin + count,
      [&centroid](std::int64_t p, std::int64_t q) { return centroid(p) < centroid(q); });
    node.Left = static_cast<std::uint32_t>(this->Nodes.size());
    this->Nodes[index] = node;
    this->Nodes.emplace_back();
    this->Nodes.emplace_back();
    this->BuildNode(node.Left, first, half, index, depth + 1);
    this->BuildNode(node.Left + 1, first + half, count - half, index, depth + 1);
  }

  std::vector<Vec<DIM>> Vertices;
  std::vector<Primitive> Primitives;
  std::vector<std::int64_t> Order; // primitives in leaf order
  std::vector<double> Areas;       // per primitive (original order)
  std::vector<double> PatchReach;  // 3D: √(area of its flat patch / π), per primitive
  std::vector<std::uint32_t> LeafOf;
  std::vector<Node> Nodes;
};
} // namespace gridfree

#endif
