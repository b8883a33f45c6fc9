// The accessors of the settings a filter keeps in one gridfree::SolveSettings
// (vtkWalkOnSpheresAlgorithm's GetSettings()): defined once here for the
// base's sampling settings and the subclasses' own, so that a property's
// clamp and its Modified() behave alike in each. Use in a .cxx only.
// Private to the GridFree::Filters module.
#ifndef GridFreeSettingAccessors_h
#define GridFreeSettingAccessors_h

#include "GridFreeSolveSettings.h"

#include <algorithm>

// Set clamps to [lo, hi] and marks the filter modified when the value
// changes; Get returns it.
#define GRIDFREE_SETTING_ACCESSORS(Class, Name, Type, lo, hi)                                      \
  void Class::Set##Name(Type value)                                                                \
  {                                                                                                \
    value = std::min<Type>(std::max<Type>(value, lo), hi);                                         \
    if (this->GetSettings().Name != value)                                                         \
    {                                                                                              \
      this->GetSettings().Name = value;                                                            \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  Type Class::Get##Name() { return this->GetSettings().Name; }

// A choice's accessors: the integer code (vtkWalkOnSpheresSolver's
// enumeration) clamped to [0, hi], stored as the core's typed choice.
#define GRIDFREE_CHOICE_ACCESSORS(Class, Name, Choice, hi)                                         \
  void Class::Set##Name(int code)                                                                  \
  {                                                                                                \
    const Choice value = static_cast<Choice>(std::min(std::max(code, 0), hi));                     \
    if (this->GetSettings().Name != value)                                                         \
    {                                                                                              \
      this->GetSettings().Name = value;                                                            \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  int Class::Get##Name() { return gridfree::CodeOf(this->GetSettings().Name); }

#endif
