// The source terms of a problem: point and curve sources (concentrated,
// paper Sec. 5.1.2) and a volume source f made per thread (each thread of a
// batch gets its own: expression parsers and cell locators are not shared).
// The VTK module fills one from its Source input and SourceExpression
// (Filters/GridFreeSourceConversion); C++ users fill it directly.
#ifndef GRIDFREE_SOURCES_SOURCE_SET_H
#define GRIDFREE_SOURCES_SOURCE_SET_H

#include <gridfree/sources/ConcentratedSources.h>
#include <gridfree/sources/SourceTerms.h>

#include <functional>
#include <memory>

namespace gridfree
{
// Makes one thread's volume source. lengthScale is the problem's size (the
// boundary's bounding-box diagonal): sources without an exact gradient (the
// expression) differentiate by central differences with step
// 1e-5·lengthScale; a lengthScale that is not positive keeps VolumeSource's
// default step, 1e-5·max(1, |y|∞). Interpolated data (images, other
// datasets) have exact gradients and ignore it.
template <int DIM>
using VolumeSourceFactory = std::function<std::unique_ptr<VolumeSource<DIM>>(double lengthScale)>;

template <int DIM>
struct SourceSet
{
  std::unique_ptr<PointSources<DIM>> Points;
  std::unique_ptr<CurveSources<DIM>> Curves;
  // Makes one thread's volume source (sum of dataset and expression); empty
  // when there is no volume source.
  VolumeSourceFactory<DIM> MakeVolume;
  // Polygons of a source dataset that were left out (a caller's message).
  long long IgnoredSurfaceCells = 0;

  bool Empty() const { return !this->Points && !this->Curves && !this->MakeVolume; }
  ConcentratedSourceSet<DIM> Concentrated() const
  {
    ConcentratedSourceSet<DIM> set;
    set.Points = this->Points.get();
    set.Curves = this->Curves.get();
    return set;
  }
};
} // namespace gridfree

#endif
