#include "EmbreePeer.h"

#include <gridfree/geometry/ClosestPointPrimitives.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gridfree
{
namespace bench
{
namespace
{
// Smallest float >= v: the query radius must never drop below a distance
// already found, or Embree could cull a triangle that is still closer.
float RoundUpToFloat(double v)
{
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v)
  {
    f = std::nextafter(f, std::numeric_limits<float>::infinity());
  }
  return f;
}

void ThrowOnError(RTCDevice device, const char* what)
{
  const RTCError code = rtcGetDeviceError(device);
  if (code != RTC_ERROR_NONE)
  {
    throw std::runtime_error(
      std::string("Embree error ") + std::to_string(int(code)) + " in " + what);
  }
}
} // namespace

// What one rtcPointQuery carries into the callback: the query point in
// double, the best squared distance so far and its triangle.
struct EmbreePeer::QueryState
{
  const EmbreePeer* Peer;
  Vec3 X;
  double Best2;
  std::int64_t Best;
  // Added to the radius handed back to Embree: Embree traverses with the
  // query point rounded to float and tests float boxes, so a radius of
  // exactly the best distance could cull a box holding a triangle that is
  // closer to the double query point. The margin covers the point's own
  // rounding plus a few float ulps of the coordinates.
  double Margin;
};

EmbreePeer::EmbreePeer(
  const std::vector<Vec3>& vertices, const std::vector<std::array<std::int64_t, 3>>& triangles)
{
  if (vertices.size() >= std::numeric_limits<unsigned>::max() ||
    triangles.size() >= std::numeric_limits<unsigned>::max())
  {
    throw std::length_error("EmbreePeer: Embree indices are 32-bit");
  }
  this->Device = rtcNewDevice(nullptr);
  if (!this->Device)
  {
    throw std::runtime_error("Embree: cannot create a device");
  }
  rtcSetDeviceMemoryMonitorFunction(this->Device, &EmbreePeer::MemoryMonitor, this);
  // Count only what the scene needs, not the device's own state.
  this->Bytes = 0;

  const auto start = std::chrono::steady_clock::now();
  this->Scene = rtcNewScene(this->Device);
  RTCGeometry geometry = rtcNewGeometry(this->Device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* xyz = static_cast<float*>(rtcSetNewGeometryBuffer(
    geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
  auto* ids = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
    geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size()));
  ThrowOnError(this->Device, "buffer allocation");
  for (std::size_t i = 0; i < vertices.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      xyz[3 * i + c] = static_cast<float>(vertices[i][c]);
    }
  }
  for (std::size_t i = 0; i < triangles.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      ids[3 * i + c] = static_cast<unsigned>(triangles[i][c]);
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(this->Scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(this->Scene);
  this->BuildTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ThrowOnError(this->Device, "scene build");

  this->Triangles.resize(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      const Vec3& v = vertices[triangles[i][c]];
      this->Triangles[i][c] = v;
      this->MaxAbsCoordinate = std::max(this->MaxAbsCoordinate, v.cwiseAbs().maxCoeff());
    }
  }
}

EmbreePeer::~EmbreePeer()
{
  if (this->Scene)
  {
    rtcReleaseScene(this->Scene);
  }
  if (this->Device)
  {
    rtcReleaseDevice(this->Device);
  }
}

std::string EmbreePeer::Version()
{
  return RTC_VERSION_STRING;
}

bool EmbreePeer::MemoryMonitor(void* self, ssize_t bytes, bool /*post*/)
{
  static_cast<EmbreePeer*>(self)->Bytes += static_cast<long long>(bytes);
  return true; // never refuse an allocation
}

// Called by Embree for each triangle in a leaf its traversal reaches. Returns
// true exactly when it shrank the query radius, which tells Embree to reload
// the radius and cull more.
bool EmbreePeer::PointQueryCallback(RTCPointQueryFunctionArguments* args)
{
  auto* state = static_cast<QueryState*>(args->userPtr);
  const auto& t = state->Peer->Triangles[args->primID];
  // The plane test inside the kernel rejects triangles farther than the
  // best so far without the full computation, as in our own leaves.
  const double d2 = SquaredDistanceToTriangle(state->X, t[0], t[1], t[2], state->Best2);
  if (!(d2 < state->Best2))
  {
    return false;
  }
  state->Best2 = d2;
  state->Best = args->primID;
  const float radius = RoundUpToFloat(std::sqrt(d2) + state->Margin);
  if (radius < args->query->radius)
  {
    args->query->radius = radius;
    return true;
  }
  return false;
}

void EmbreePeer::Nearest(QueryState& state) const
{
  alignas(16) RTCPointQuery query;
  query.x = static_cast<float>(state.X[0]);
  query.y = static_cast<float>(state.X[1]);
  query.z = static_cast<float>(state.X[2]);
  query.time = 0.0f;
  query.radius = std::numeric_limits<float>::infinity();
  const Vec3 rounded(query.x, query.y, query.z);
  state.Margin =
    (state.X - rounded).norm() + 0x1p-21 * (this->MaxAbsCoordinate + state.X.cwiseAbs().maxCoeff());
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(this->Scene, &query, &context, &EmbreePeer::PointQueryCallback, &state);
}

double EmbreePeer::Distance(const Vec3& x) const
{
  QueryState state{ this, x, std::numeric_limits<double>::infinity(), -1, 0.0 };
  this->Nearest(state);
  return std::sqrt(state.Best2);
}

EmbreePeer::Closest EmbreePeer::ClosestPoint(const Vec3& x) const
{
  QueryState state{ this, x, std::numeric_limits<double>::infinity(), -1, 0.0 };
  this->Nearest(state);
  Closest result{ std::sqrt(state.Best2), state.Best,
    Vec3::Constant(std::numeric_limits<double>::infinity()) };
  if (state.Best >= 0)
  {
    // Like our BVH: the point itself only for the winner.
    const auto& t = this->Triangles[static_cast<std::size_t>(state.Best)];
    result.Point = ClosestPointOnTriangle(x, t[0], t[1], t[2]).point;
  }
  return result;
}

bool EmbreePeer::Intersect(const Vec3& origin, const Vec3& direction, float& t) const
{
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(16) RTCRayHit rayhit;
  rayhit.ray.org_x = static_cast<float>(origin[0]);
  rayhit.ray.org_y = static_cast<float>(origin[1]);
  rayhit.ray.org_z = static_cast<float>(origin[2]);
  rayhit.ray.dir_x = static_cast<float>(direction[0]);
  rayhit.ray.dir_y = static_cast<float>(direction[1]);
  rayhit.ray.dir_z = static_cast<float>(direction[2]);
  rayhit.ray.tnear = 0.0f;
  rayhit.ray.tfar = std::numeric_limits<float>::infinity();
  rayhit.ray.time = 0.0f;
  rayhit.ray.mask = ~0u;
  rayhit.ray.id = 0;
  rayhit.ray.flags = 0;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(this->Scene, &context, &rayhit);
  t = rayhit.ray.tfar;
  return rayhit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}
} // namespace bench
} // namespace gridfree
