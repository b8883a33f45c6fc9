// Boundary values g given as a function of the boundary point, for
// boundaries that carry no per-vertex table: implicit surfaces, CSG trees,
// or a mesh whose values come from elsewhere.
//
// A walk asks for g once, at its last step, with the closest-point answer.
// Implementations are shared by all threads (Evaluate is const); those that
// need scratch memory keep it per thread.
#ifndef GRIDFREE_BOUNDARY_BOUNDARY_VALUES_H
#define GRIDFREE_BOUNDARY_BOUNDARY_VALUES_H

#include <gridfree/geometry/ClosestPointResult.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/math/Vector.h>

#include <tbb/enumerable_thread_specific.h>

#include <functional>
#include <memory>
#include <stdexcept>
#include <utility>

namespace gridfree
{
template <int DIM>
class BoundaryValueFunction
{
public:
  virtual ~BoundaryValueFunction() = default;
  // Numbers per boundary point.
  virtual int Components() const = 0;
  // Writes g at the boundary point `hit` (Components() numbers).
  virtual void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const = 0;
};

// g(p) = f(p) for any VolumeSource f (an expression in x, y, z; an image or
// any dataset interpolated at p). Sources keep scratch memory, so each thread
// makes its own from the factory on first use.
template <int DIM>
class VolumeBoundaryValues final : public BoundaryValueFunction<DIM>
{
public:
  using Factory = std::function<std::unique_ptr<VolumeSource<DIM>>()>;

  VolumeBoundaryValues(Factory factory, int components)
    : MakeSource(std::move(factory))
    , NumberOfComponents(components)
    , PerThread([this]() { return this->MakeSource(); })
  {
    if (!this->MakeSource || components < 1)
    {
      throw std::invalid_argument("boundary values: need a source factory and components >= 1");
    }
  }

  // The per-thread factory captures `this`: not copyable or movable.
  VolumeBoundaryValues(const VolumeBoundaryValues&) = delete;
  VolumeBoundaryValues& operator=(const VolumeBoundaryValues&) = delete;

  int Components() const override { return this->NumberOfComponents; }

  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const override
  {
    this->PerThread.local()->Evaluate(hit.point, out);
  }

private:
  Factory MakeSource;
  int NumberOfComponents;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<VolumeSource<DIM>>> PerThread;
};

// g as a plain thread-safe callable of the boundary point and its part
// (tests, CSG parts with their own constants).
template <int DIM>
class CallableBoundaryValues final : public BoundaryValueFunction<DIM>
{
public:
  using Function = std::function<void(const Vec<DIM>& point, std::int64_t part, double* out)>;

  CallableBoundaryValues(Function f, int components)
    : F(std::move(f))
    , NumberOfComponents(components)
  {
    if (!this->F || components < 1)
    {
      throw std::invalid_argument("boundary values: need a function and components >= 1");
    }
  }

  int Components() const override { return this->NumberOfComponents; }

  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const override
  {
    this->F(hit.point, hit.primitive, out);
  }

private:
  Function F;
  int NumberOfComponents;
};
} // namespace gridfree

#endif
