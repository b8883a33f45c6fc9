// Meshes and point sets for the benchmarks: bumpy spheres of any size, a
// shuffled triangle soup for the large build, VTK XML polygon files, and an
// inside test that scales to millions of triangles.
#ifndef GRIDFREE_BENCHMARKS_BENCHMARKMESHES_H
#define GRIDFREE_BENCHMARKS_BENCHMARKMESHES_H

#include "TestMeshes.h"
#include <gridfree/math/Vector.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gridfree
{
namespace bench
{
using TriangleMesh = testing::SimplexMesh<3>;

struct Mesh
{
  std::string Name;
  TriangleMesh Geometry;
  // Length the walk tolerance is relative to (ε = 1e-3·Scale): 1 for the
  // unit spheres, so the target's ε = 1e-3 is met exactly, half the longest
  // box side for files.
  double Scale = 1.0;
  // Walks "inside" start in the mesh scaled by this factor about the box
  // center: 0.9 for the (star-shaped) spheres, 1 for arbitrary surfaces.
  double StartShrink = 1.0;
  // The derivative-cost table runs on the meshes it was documented for.
  bool DerivativeTable = false;
  // The walks/s target is stated for this mesh (the icosphere).
  bool WalkTarget = false;
};

struct Box
{
  Vec3 Min;
  Vec3 Max;
  Vec3 Center() const { return 0.5 * (this->Min + this->Max); }
  double Diagonal() const { return (this->Max - this->Min).norm(); }
};

Box BoundsOf(const TriangleMesh& mesh);

// Unit icosahedron with each face cut into k×k triangles (20·k² in all, with
// shared vertices), projected on the unit sphere, then each vertex v moved to
// v·(1 + amplitude·sin(f·x) sin(f·y) sin(f·z)). k = 256 gives 1,310,720
// triangles, the size of a level-8 icosphere.
TriangleMesh MakeBumpySphere(int k, double amplitude = 0.15, double frequency = 6.0);

// A soup of exactly `triangles` triangles for the build-time benchmark: a fine
// bumpy sphere whose triangles are shuffled and given their own three
// vertices each, as raw isosurface output often is.
TriangleMesh MakeBumpySoup(std::size_t triangles, unsigned seed);

// Polygons of a .vtp file, triangulated as fans. Throws std::runtime_error
// when the file cannot be read or has no polygons.
TriangleMesh ReadPolyDataTriangles(const std::string& path);

// Queries uniform in the box, or near the surface: a uniform point on a
// random triangle moved in a random direction by up to 1% of the box
// diagonal.
std::vector<Vec3> MakeQueries(
  const TriangleMesh& mesh, bool nearSurface, std::size_t count, unsigned seed);

// Near-surface queries moved by up to `offset` (uniform in a box when
// offset < 0); MakeQueries uses 1% of the box diagonal.
std::vector<Vec3> MakeQueriesNear(
  const TriangleMesh& mesh, double offset, std::size_t count, unsigned seed);

// Mean edge length of the triangles: the mesh's own length scale.
double MeanEdgeLength(const TriangleMesh& mesh);

// Points uniform in the mesh's box that lie inside the closed surface scaled
// by `shrink` about the box center; at most `count`, from at most
// 200·count candidates.
std::vector<Vec3> MakeInsidePoints(
  const TriangleMesh& mesh, double shrink, std::size_t count, unsigned seed);

// Inside test for a closed triangle surface: parity of the crossings of the
// ray from the point in the +x direction. Triangles are binned by their
// shadow on the (y, z) plane so a query only looks at one grid cell; this
// makes it usable on soups of millions of triangles, where the brute-force
// parity count is far too slow. A random point hits a shared edge with
// probability zero, so no tie rule is needed for the random points used here.
class InsideTest
{
public:
  explicit InsideTest(const TriangleMesh& mesh);
  bool Contains(const Vec3& p) const;

private:
  int Cell(double y, double z) const;

  const TriangleMesh& Mesh;
  double Y0 = 0.0, Z0 = 0.0, InvCellY = 0.0, InvCellZ = 0.0;
  int Ny = 1, Nz = 1;
  std::vector<std::uint64_t> CellStart; // CSR offsets, Ny·Nz + 1
  std::vector<std::uint32_t> CellTriangles;
};
} // namespace bench
} // namespace gridfree

#endif
