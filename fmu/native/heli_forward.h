/* The one forwarding shape of the FMI wrappers (fmi2Functions.c, fmi3Functions.c): check the
   instance, hand the call to the model core with the call's name, return its status. */
#ifndef HELI_FORWARD_H
#define HELI_FORWARD_H

#include "heli_core.h"

/* STATUS NAME PARAMS { return CORE(instance, "NAME", args...); }: PARAMS names the instance `instance`. */
#define HELI_FORWARD(STATUS, NAME, CORE, PARAMS, ...)                \
  STATUS NAME PARAMS {                                               \
    heli_instance* c = heli_checked(instance, #NAME);               \
    if (!c) return (STATUS) HELI_ERROR;                              \
    return (STATUS) CORE(c, #NAME, __VA_ARGS__);                     \
  }

/* The same for a call with no argument besides the instance. */
#define HELI_FORWARD0(STATUS, NAME, CORE, PARAMS)                    \
  STATUS NAME PARAMS {                                               \
    heli_instance* c = heli_checked(instance, #NAME);               \
    if (!c) return (STATUS) HELI_ERROR;                              \
    return (STATUS) CORE(c, #NAME);                                  \
  }

#endif
