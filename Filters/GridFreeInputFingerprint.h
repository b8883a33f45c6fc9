// Fingerprints of what a solve is computed from, to decide whether kept
// results (running sums, a built boundary) still apply: a dataset by the
// values of its arrays (points, cells, point, cell and field data; hashed,
// each array once while it is unchanged) and by the values that define an
// image's or a rectilinear grid's geometry; any other object by its
// identity and modification time.
// Private to the GridFree::Filters module.
#ifndef GridFreeInputFingerprint_h
#define GridFreeInputFingerprint_h

#include <cstdint>
#include <string>
#include <vector>

class vtkObject;

namespace gridfree
{
// Appends the fingerprint of `object` (a data object, composite or not, an
// implicit function, or null) to `print`.
void AppendFingerprint(vtkObject* object, std::vector<std::uint64_t>& print);

// Appends a string exactly (its length, then its bytes eight at a time).
void AppendString(const std::string& s, std::vector<std::uint64_t>& print);

// Appends the bits of a double.
void AppendDouble(double v, std::vector<std::uint64_t>& print);
} // namespace gridfree

#endif
