// How constructive solid geometry combines its operands' domains
// (CsgFunctions.h).
#ifndef GRIDFREE_IMPLICIT_CSG_OPERATION_H
#define GRIDFREE_IMPLICIT_CSG_OPERATION_H

namespace gridfree
{
// Difference: the first operand minus all others.
enum class CsgOperation
{
  Union,
  Intersection,
  Difference
};

} // namespace gridfree

#endif
