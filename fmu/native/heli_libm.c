/* Math functions of the native heli rotor FMU when libm is not linked: see heli_libm.h. */
#include "heli_libm.h"

#ifdef HELI_LIBM_LINKED

int heli_libm_ready(void) { return 1; }

const char* heli_libm_problem(void) { return 0; }

#else

#include <dlfcn.h>
#include <stddef.h>

#if defined(__GNUC__)
#pragma GCC visibility push(hidden)
#endif

typedef double (*unary_fn)(double);
typedef double (*binary_fn)(double, double);

#define POINTER1(f) static unary_fn p_##f;
#define POINTER2(f) static binary_fn p_##f;
HELI_LIBM_UNARY(POINTER1)
HELI_LIBM_BINARY(POINTER2)

#define CALL1(f) double heli_libm_##f(double x) { return p_##f(x); }
#define CALL2(f) double heli_libm_##f(double x, double y) { return p_##f(x, y); }
HELI_LIBM_UNARY(CALL1)
HELI_LIBM_BINARY(CALL2)

static const char* problem = "the math library was not looked up";

/* Take every function from libm.so.6 when the FMU's library is loaded (it stays open). */
__attribute__((constructor)) static void resolve(void) {
  void* libm = dlopen("libm.so.6", RTLD_NOW | RTLD_LOCAL);
  int missing = 0;
  if (!libm) {
    problem = "libm.so.6 (the C math library) cannot be opened";
    return;
  }
#define LOOKUP(f) missing |= !(*(void**) &p_##f = dlsym(libm, #f));
  HELI_LIBM_UNARY(LOOKUP)
  HELI_LIBM_BINARY(LOOKUP)
  problem = missing ? "libm.so.6 lacks one of the math functions the model calls" : NULL;
}

int heli_libm_ready(void) { return problem == NULL; }

const char* heli_libm_problem(void) { return problem; }

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif
