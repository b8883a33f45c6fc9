// Merging identical vertices (Geometry/WeldVertices.h): a soup made from an
// indexed mesh welds back to that mesh's vertex count, vertices whose values
// differ stay apart, unused vertices go, and the boundary answers every
// query exactly as before.
#include <gridfree/boundary/Boundary.h>
#include <gridfree/geometry/WeldVertices.h>
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

using namespace gridfree;
using namespace gridfree::testing;

namespace
{
// Every triangle with three vertices of its own, triangles shuffled.
SimplexMesh<3> SoupOf(const SimplexMesh<3>& mesh, std::vector<double>& values,
  const std::vector<double>& meshValues)
{
  SimplexMesh<3> soup;
  std::vector<std::size_t> order(mesh.Simplices.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  std::shuffle(order.begin(), order.end(), std::mt19937(4));
  values.clear();
  for (std::size_t t : order)
  {
    std::array<std::int64_t, 3> tri;
    for (int k = 0; k < 3; ++k)
    {
      tri[k] = static_cast<std::int64_t>(soup.Vertices.size());
      soup.Vertices.push_back(mesh.Vertices[mesh.Simplices[t][k]]);
      values.push_back(meshValues[mesh.Simplices[t][k]]);
    }
    soup.Simplices.push_back(tri);
  }
  return soup;
}
} // namespace

TEST(WeldVertices, SoupWeldsBackToTheIndexedMesh)
{
  const SimplexMesh<3> mesh = MakeIcosphere(3);
  std::vector<double> meshValues;
  for (const Vec3& v : mesh.Vertices)
  {
    meshValues.push_back(v[0] - 2.0 * v[2]);
  }
  std::vector<double> values;
  SimplexMesh<3> soup = SoupOf(mesh, values, meshValues);
  const SimplexMesh<3> original = soup;
  const std::vector<double> originalValues = values;

  const std::size_t removed =
    WeldIdenticalVertices<3>(soup.Vertices, soup.Simplices, &values, 1);
  EXPECT_EQ(soup.Vertices.size(), mesh.Vertices.size());
  EXPECT_EQ(removed, original.Vertices.size() - mesh.Vertices.size());
  ASSERT_EQ(values.size(), soup.Vertices.size());
  ASSERT_EQ(soup.Simplices.size(), original.Simplices.size());
  // Same triangles, same corner values, in the same order.
  for (std::size_t t = 0; t < soup.Simplices.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(soup.Vertices[soup.Simplices[t][k]], original.Vertices[original.Simplices[t][k]]);
      EXPECT_EQ(values[soup.Simplices[t][k]], originalValues[original.Simplices[t][k]]);
    }
  }

  // The boundaries built before and after answer identically.
  Boundary<3> before, after;
  before.Set(original.Vertices, original.Simplices, ValueAssociation::Points, 1, originalValues);
  after.Set(soup.Vertices, soup.Simplices, ValueAssociation::Points, 1, values);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int q = 0; q < 2000; ++q)
  {
    const Vec3 x(u(rng), u(rng), u(rng));
    const auto a = before.ClosestPoint(x);
    const auto b = after.ClosestPoint(x);
    ASSERT_EQ(a.distance, b.distance);
    ASSERT_EQ(a.primitive, b.primitive);
    double ga, gb;
    before.Evaluate(a, &ga);
    after.Evaluate(b, &gb);
    ASSERT_EQ(ga, gb);
  }
}

TEST(WeldVertices, DifferentValuesOrUnusedVerticesAndCoordinateOnlyWelds)
{
  // Two triangles sharing an edge whose vertices appear twice: once with the
  // same values (merged), once with a different value at one of them (kept
  // apart), plus an unused vertex (dropped).
  std::vector<Vec3> vertices = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0),
    Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(5, 5, 5) };
  std::vector<std::array<std::int64_t, 3>> triangles = { { 0, 1, 2 }, { 3, 5, 4 } };
  std::vector<double> values = { 0.0, 1.0, 2.0, 1.0, 7.0, 3.0, 9.0 };
  auto t = triangles;
  auto v = vertices;
  auto g = values;
  EXPECT_EQ(WeldIdenticalVertices<3>(v, t, &g, 1), 2u); // vertex 3 merged, 6 dropped
  EXPECT_EQ(v.size(), 5u);
  EXPECT_EQ(t[1][0], t[0][1]); // (1, 0, 0) with value 1: one vertex
  EXPECT_NE(t[1][2], t[0][2]); // (0, 1, 0): values 2 and 7 differ
  // Without values, coordinates alone decide.
  t = triangles;
  v = vertices;
  EXPECT_EQ(WeldIdenticalVertices<3>(v, t), 3u);
  EXPECT_EQ(v.size(), 4u);
  EXPECT_EQ(t[1][2], t[0][2]);
  // 2D segments too; -0.0 and 0.0 differ in bits and are not merged (a
  // harmless miss: the mesh keeps both copies).
  std::vector<Vec2> points = { Vec2(0, 0), Vec2(1, 0), Vec2(1, 0), Vec2(-0.0, 0) };
  std::vector<std::array<std::int64_t, 2>> segments = { { 0, 1 }, { 2, 3 } };
  EXPECT_EQ(WeldIdenticalVertices<2>(points, segments), 1u);
  EXPECT_EQ(points.size(), 3u);
  EXPECT_EQ(segments[0][1], segments[1][0]);
}
