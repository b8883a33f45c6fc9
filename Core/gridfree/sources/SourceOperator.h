// What the source term is made of the source data: the values, or the
// divergence or curl of the vector field they give (DifferentialOperatorSource.h).
#ifndef GRIDFREE_SOURCES_SOURCE_OPERATOR_H
#define GRIDFREE_SOURCES_SOURCE_OPERATOR_H

namespace gridfree
{
// What the source term is made of the source data.
enum class SourceOperator
{
  Value = 0,
  Divergence = 1,
  Curl = 2
};

} // namespace gridfree

#endif
