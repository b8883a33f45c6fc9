// The closest silhouette point of the reflecting (Neumann and Robin) part of
// a boundary, seen from a query point: the query walk on stars needs to size
// its star-shaped regions (Sawhney et al. 2023, Sec. 4.3; Documentation/
// WalkOnStars.md §3).
//
// A silhouette is where the boundary turns away from the viewer: in 2D a
// vertex whose two segments lie on the same side of the sight line, in 3D an
// edge whose two triangles do. With unit outward normals n0, n1 of the two
// primitives and w the unit direction from the vertex (the edge's closest
// point) to the query x, that is a = w·n0 and b = w·n1 of opposite signs.
// When x lies in the plane of one primitive (a ≈ 0) the other decides: the
// edge hides what lies behind it iff b > 0 (the other primitive faces away).
// Every tolerance errs towards "silhouette", which only shrinks a star.
//
// The domain is on the inner side of the outward normals (one-sided): a
// convex vertex or edge (the domain's interior angle below π) can never be
// seen as a silhouette from inside, so only reflex ones are candidates. A
// vertex or edge with one primitive (the rim of the reflecting part, which
// meets the Dirichlet part there) or more than two, or whose primitives'
// orientations disagree, is always a silhouette. Where a two-sided primitive
// (an insulating sheet: the domain on both of its sides) meets another at
// an angle, the vertex or edge is reflex seen from one side or the other:
// it is a candidate whichever way it turns (flat ones never are).
//
// The hierarchy is a binary tree of boxes, each with a cone bounding the
// normals below it (axis, half-angle): a subtree can hold a silhouette for x
// only if some direction from x into its box is orthogonal to some normal in
// its cone (Johnson & Cohen 2001's test, as in the paper's Sec. 4.3.1).
#ifndef GRIDFREE_STARS_SILHOUETTE_TREE_H
#define GRIDFREE_STARS_SILHOUETTE_TREE_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/stars/BoxTreeTraversal.h>
#include <gridfree/geometry/ClosestPointPrimitives.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

namespace gridfree
{
// Unit outward normal of a primitive of a boundary whose domain lies on the
// left of its segments (2D: counter-clockwise around the domain) or on the
// side its triangles turn clockwise on (3D: the usual outward orientation,
// vertices counter-clockwise seen from outside); zero when degenerate.
template <int DIM, typename Ids>
Vec<DIM> OutwardUnitNormal(const std::vector<Vec<DIM>>& vertices, const Ids& ids)
{
  const Vec<DIM> n = SimplexUnitNormal<DIM>(vertices, ids);
  return DIM == 2 ? Vec<DIM>(-n) : n;
}

// A vertex (2D) or an edge (3D) that may be a silhouette.
template <int DIM>
struct SilhouetteCandidate
{
  Vec<DIM> A = Vec<DIM>::Zero(); // the vertex; an edge's first end
  Vec<DIM> B = Vec<DIM>::Zero(); // an edge's second end (= A in 2D)
  Vec<DIM> N0 = Vec<DIM>::Zero(); // unit outward normals of its two primitives
  Vec<DIM> N1 = Vec<DIM>::Zero();
  bool Always = false; // a rim, non-manifold or inconsistently oriented one

  // Closest point to x (the vertex, or on the edge).
  Vec<DIM> ClosestPoint(const Vec<DIM>& x) const
  {
    if constexpr (DIM == 2)
    {
      (void)x;
      return this->A;
    }
    else
    {
      const Vec<DIM> e = this->B - this->A;
      const double ee = e.squaredNorm();
      const double t = ee > 0.0 ? std::clamp((x - this->A).dot(e) / ee, 0.0, 1.0) : 0.0;
      return this->A + t * e;
    }
  }
};

// Tolerance of the silhouette test on unit dot products. (The distance below
// which x counts as on a candidate is the tree's OnCandidateTolerance(),
// relative to the scene.)
constexpr double kSilhouetteDotTolerance = 1e-6;

// Whether `c` is a silhouette seen from x, whose distance to it is `d`
// (closest point p); `onTolerance` is the absolute distance below which x
// counts as on the candidate (then a reflex candidate always is one).
template <int DIM>
bool IsSilhouette(
  const SilhouetteCandidate<DIM>& c, const Vec<DIM>& x, const Vec<DIM>& p, double d,
  double onTolerance)
{
  if (c.Always || d <= onTolerance)
  {
    return true;
  }
  const Vec<DIM> w = (x - p) / d;
  const double a = w.dot(c.N0);
  const double b = w.dot(c.N1);
  const double tol = kSilhouetteDotTolerance;
  if (std::abs(a) <= tol)
  {
    return b > -tol;
  }
  if (std::abs(b) <= tol)
  {
    return a > -tol;
  }
  return (a < 0.0) != (b < 0.0);
}

template <int DIM>
class SilhouetteTree
{
public:
  using Primitive = std::array<std::int64_t, DIM>;

  // The candidates of a boundary given as vertices and primitives
  // (segments or triangles, oriented as OutwardUnitNormal expects), one-
  // sided but for the primitives `twoSided` marks (empty: none).
  void Build(const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives,
    const std::vector<std::uint8_t>& twoSided = {})
  {
    this->Candidates = MakeCandidates(vertices, primitives, twoSided);
    BoundingBox<DIM> all;
    for (const Vec<DIM>& v : vertices)
    {
      all.Expand(v);
    }
    this->OnTolerance = 1e-12 * std::max(all.Diagonal(), 1e-300);
    this->BuildTree();
  }

  // Candidates of a one-sided boundary (see the file comment); public for
  // tests, which compare the tree against a loop over them.
  static std::vector<SilhouetteCandidate<DIM>> MakeCandidates(
    const std::vector<Vec<DIM>>& vertices, const std::vector<Primitive>& primitives,
    const std::vector<std::uint8_t>& twoSided = {})
  {
    std::vector<SilhouetteCandidate<DIM>> out;
    auto sheet = [&twoSided](std::int64_t p) {
      return !twoSided.empty() && twoSided[static_cast<std::size_t>(p)] != 0;
    };
    // Two primitives meeting at an angle (not flat): a two-sided pair's
    // candidate whichever way it turns.
    auto bent = [](const Vec<DIM>& n0, const Vec<DIM>& n1) { return n0.dot(n1) < 1.0 - 1e-12; };
    if constexpr (DIM == 2)
    {
      // Per vertex: the segment arriving at it and the one leaving it.
      struct Incidence
      {
        int In = 0, Out = 0;
        std::int64_t InSegment = -1, OutSegment = -1;
      };
      std::vector<Incidence> at(vertices.size());
      for (std::size_t s = 0; s < primitives.size(); ++s)
      {
        Incidence& out0 = at[static_cast<std::size_t>(primitives[s][0])];
        out0.Out += 1;
        out0.OutSegment = static_cast<std::int64_t>(s);
        Incidence& in1 = at[static_cast<std::size_t>(primitives[s][1])];
        in1.In += 1;
        in1.InSegment = static_cast<std::int64_t>(s);
      }
      for (std::size_t v = 0; v < vertices.size(); ++v)
      {
        const Incidence& i = at[v];
        if (i.In + i.Out == 0)
        {
          continue;
        }
        SilhouetteCandidate<DIM> c;
        c.A = c.B = vertices[v];
        if (i.In == 1 && i.Out == 1)
        {
          const Primitive& in = primitives[static_cast<std::size_t>(i.InSegment)];
          const Primitive& next = primitives[static_cast<std::size_t>(i.OutSegment)];
          const Vec<DIM> e0 = vertices[in[1]] - vertices[in[0]];
          const Vec<DIM> e1 = vertices[next[1]] - vertices[next[0]];
          // The domain on the left: a right turn is a reflex vertex.
          const double turn = e0[0] * e1[1] - e0[1] * e1[0];
          c.N0 = OutwardUnitNormal<DIM>(vertices, in);
          c.N1 = OutwardUnitNormal<DIM>(vertices, next);
          if (c.N0.isZero() || c.N1.isZero())
          {
            c.Always = true; // a degenerate segment: no normal to test
          }
          else if (sheet(i.InSegment) || sheet(i.OutSegment))
          {
            if (!bent(c.N0, c.N1))
            {
              continue; // straight
            }
          }
          else if (!(turn < 0.0))
          {
            continue; // convex or straight: never a silhouette from inside
          }
        }
        else
        {
          c.Always = true;
        }
        out.push_back(c);
      }
    }
    else
    {
      // Per undirected edge: the triangles using it, and in which direction.
      struct Use
      {
        std::int64_t Triangle;
        bool Forward; // the edge runs from its smaller to its larger vertex
        int Opposite; // the triangle's third vertex
      };
      std::map<std::pair<std::int64_t, std::int64_t>, std::vector<Use>> edges;
      for (std::size_t t = 0; t < primitives.size(); ++t)
      {
        const Primitive& p = primitives[t];
        for (int k = 0; k < 3; ++k)
        {
          const std::int64_t a = p[k], b = p[(k + 1) % 3];
          const auto key = std::make_pair(std::min(a, b), std::max(a, b));
          edges[key].push_back({ static_cast<std::int64_t>(t), a < b, static_cast<int>(p[(k + 2) % 3]) });
        }
      }
      for (const auto& [key, uses] : edges)
      {
        SilhouetteCandidate<DIM> c;
        c.A = vertices[static_cast<std::size_t>(key.first)];
        c.B = vertices[static_cast<std::size_t>(key.second)];
        if (uses.size() == 2 && uses[0].Forward != uses[1].Forward)
        {
          const Primitive& t0 = primitives[static_cast<std::size_t>(uses[0].Triangle)];
          const Primitive& t1 = primitives[static_cast<std::size_t>(uses[1].Triangle)];
          c.N0 = OutwardUnitNormal<DIM>(vertices, t0);
          c.N1 = OutwardUnitNormal<DIM>(vertices, t1);
          if (c.N0.isZero() || c.N1.isZero())
          {
            c.Always = true;
            out.push_back(c);
            continue;
          }
          if (sheet(uses[0].Triangle) || sheet(uses[1].Triangle))
          {
            if (!bent(c.N0, c.N1))
            {
              continue; // flat
            }
            out.push_back(c);
            continue;
          }
          // Reflex iff the second triangle's third vertex lies outside the
          // first one's plane.
          const Vec<DIM> r1 = vertices[static_cast<std::size_t>(uses[1].Opposite)];
          if (!((r1 - c.A).dot(c.N0) > 0.0))
          {
            continue;
          }
        }
        else
        {
          c.Always = true;
        }
        out.push_back(c);
      }
    }
    return out;
  }

  std::size_t NumberOfCandidates() const { return this->Candidates.size(); }
  const std::vector<SilhouetteCandidate<DIM>>& CandidateList() const { return this->Candidates; }
  double OnCandidateTolerance() const { return this->OnTolerance; }

  // min(rMax, distance from x to its closest silhouette point).
  double ClosestDistance(const Vec<DIM>& x, double rMax) const
  {
    if (this->Nodes.empty())
    {
      return rMax;
    }
    double best = rMax;
    double best2 = rMax * rMax;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0)
    {
      const Node& node = this->Nodes[stack[--top]];
      if (!(node.Box.SquaredDistance(x) < best2) || !this->MayHoldSilhouette(node, x))
      {
        continue;
      }
      if (node.Count > 0)
      {
        for (std::uint32_t i = node.First; i < node.First + node.Count; ++i)
        {
          const SilhouetteCandidate<DIM>& c = this->Candidates[i];
          const Vec<DIM> p = c.ClosestPoint(x);
          const double d2 = (x - p).squaredNorm();
          if (d2 < best2 && IsSilhouette(c, x, p, std::sqrt(d2), this->OnTolerance))
          {
            best2 = d2;
            best = std::sqrt(d2);
          }
        }
        continue;
      }
      PushNearerChildLast<DIM>(this->Nodes, node.Left, x, stack, top);
    }
    return best;
  }

private:
  struct Node
  {
    BoundingBox<DIM> Box;
    Vec<DIM> Axis = Vec<DIM>::Zero(); // cone of the normals below
    double HalfAngle = M_PI;          // >= π/2: never pruned by the cone
    std::uint32_t Left = 0;           // children Left and Left + 1 (inner node)
    std::uint32_t First = 0;          // candidates First .. First + Count − 1 (leaf)
    std::uint32_t Count = 0;
  };
  static constexpr std::uint32_t kLeafSize = 4;

  // The cone test: prune only when every direction from x into the node's
  // box (a cone of half-angle β around the direction to its centre) makes
  // an angle with every normal of the node's cone that differs from π/2 by
  // more than the test's tolerance.
  bool MayHoldSilhouette(const Node& node, const Vec<DIM>& x) const
  {
    if (node.HalfAngle >= 0.5 * M_PI)
    {
      return true;
    }
    const Vec<DIM> toCenter = node.Box.Center() - x;
    const double l = toCenter.norm();
    const double radius = 0.5 * node.Box.Diagonal();
    if (!(l > radius))
    {
      return true;
    }
    const double beta = std::asin(std::min(1.0, radius / l));
    const double cosTheta = std::clamp(toCenter.dot(node.Axis) / l, -1.0, 1.0);
    const double theta = std::acos(cosTheta);
    const double margin = 1e-5; // above asin(kSilhouetteDotTolerance), plus rounding
    return std::abs(theta - 0.5 * M_PI) <= node.HalfAngle + beta + margin;
  }

  void BuildTree()
  {
    this->Nodes.clear();
    if (this->Candidates.empty())
    {
      return;
    }
    this->Nodes.reserve(2 * this->Candidates.size() / kLeafSize + 2);
    this->Nodes.emplace_back();
    this->BuildNode(0, 0, static_cast<std::uint32_t>(this->Candidates.size()), 0);
  }

  void BuildNode(std::uint32_t index, std::uint32_t first, std::uint32_t count, int depth)
  {
    Node node;
    BoundingBox<DIM> centroids;
    Vec<DIM> sum = Vec<DIM>::Zero();
    bool always = false;
    for (std::uint32_t i = first; i < first + count; ++i)
    {
      const SilhouetteCandidate<DIM>& c = this->Candidates[i];
      node.Box.Expand(c.A);
      node.Box.Expand(c.B);
      centroids.Expand(0.5 * (c.A + c.B));
      sum += c.N0 + c.N1;
      always = always || c.Always;
    }
    const double length = sum.norm();
    if (!always && length > 1e-9 * count)
    {
      node.Axis = sum / length;
      double half = 0.0;
      for (std::uint32_t i = first; i < first + count; ++i)
      {
        const SilhouetteCandidate<DIM>& c = this->Candidates[i];
        for (const Vec<DIM>& n : { c.N0, c.N1 })
        {
          half = std::max(half, std::acos(std::clamp(n.dot(node.Axis), -1.0, 1.0)));
        }
      }
      node.HalfAngle = half;
    }
    // 128 stack entries: the median split keeps the depth near log2(n).
    if (count <= kLeafSize || depth >= 60)
    {
      node.First = first;
      node.Count = count;
      this->Nodes[index] = node;
      return;
    }
    const int axis = centroids.LongestAxis();
    const std::uint32_t half = count / 2;
    auto begin = this->Candidates.begin() + first;
    std::nth_element(begin, begin + half, begin + count,
      [axis](const SilhouetteCandidate<DIM>& p, const SilhouetteCandidate<DIM>& q) {
        return p.A[axis] + p.B[axis] < q.A[axis] + q.B[axis];
      });
    node.Left = static_cast<std::uint32_t>(this->Nodes.size());
    this->Nodes[index] = node;
    this->Nodes.emplace_back();
    this->Nodes.emplace_back();
    this->BuildNode(node.Left, first, half, depth + 1);
    this->BuildNode(node.Left + 1, first + half, count - half, depth + 1);
  }

  std::vector<SilhouetteCandidate<DIM>> Candidates;
  std::vector<Node> Nodes;
  double OnTolerance = 0.0;
};
} // namespace gridfree

#endif
