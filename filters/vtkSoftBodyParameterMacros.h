/**
 * Setters and getters for properties kept in a filter's plain parameter struct `this->P`
 * (VTK's vtkSetMacro family stores into a member of the filter itself). Like vtkSetMacro they
 * call Modified() only on a change; unlike vtkSetClampMacro they never clamp: an out-of-range
 * value reaches core's validation, which refuses it quoting the value the user typed.
 *
 * ParaView's client-server wrapper expands these macros like VTK's own, so the properties are
 * reachable from the server-manager XML and pvpython.
 */
#ifndef vtkSoftBodyParameterMacros_h
#define vtkSoftBodyParameterMacros_h

#include "vtkSetGet.h"

// NaN never equals itself, so setting NaN always marks the filter modified (and is refused).
#define vtkSoftBodyParameterMacro(name, type)                                                     \
  virtual void Set##name(type value)                                                              \
  {                                                                                               \
    if (this->P.name != value)                                                                    \
    {                                                                                             \
      this->P.name = value;                                                                       \
      this->Modified();                                                                           \
    }                                                                                             \
  }                                                                                               \
  virtual type Get##name() const { return this->P.name; }

#define vtkSoftBodyBooleanParameterMacro(name)                                                    \
  vtkSoftBodyParameterMacro(name, vtkTypeBool);                                                   \
  virtual void name##On() { this->Set##name(1); }                                                 \
  virtual void name##Off() { this->Set##name(0); }

#define vtkSoftBodyVector3ParameterMacro(name)                                                    \
  virtual void Set##name(double x, double y, double z)                                            \
  {                                                                                               \
    if (this->P.name[0] != x || this->P.name[1] != y || this->P.name[2] != z)                     \
    {                                                                                             \
      this->P.name[0] = x;                                                                        \
      this->P.name[1] = y;                                                                        \
      this->P.name[2] = z;                                                                        \
      this->Modified();                                                                           \
    }                                                                                             \
  }                                                                                               \
  virtual void Set##name(const double value[3]) { this->Set##name(value[0], value[1], value[2]); } \
  virtual double* Get##name() VTK_SIZEHINT(3) { return this->P.name; }                            \
  virtual void Get##name(double value[3])                                                         \
  {                                                                                               \
    value[0] = this->P.name[0];                                                                   \
    value[1] = this->P.name[1];                                                                   \
    value[2] = this->P.name[2];                                                                   \
  }

#define vtkSoftBodyStringParameterMacro(name)                                                     \
  virtual void Set##name(const char* value)                                                       \
  {                                                                                               \
    const std::string text = value ? value : "";                                                  \
    if (this->P.name != text)                                                                     \
    {                                                                                             \
      this->P.name = text;                                                                        \
      this->Modified();                                                                           \
    }                                                                                             \
  }                                                                                               \
  virtual const char* Get##name() const { return this->P.name.c_str(); }

#endif
