/* The C math library for the native heli rotor FMU, with or without libm linked.

   The shipped binary is compiled with HELI_LIBM_LINKED and linked with -lm: every math
   function is called directly. A library rebuilt from sources/ by a tool that does not link
   libm (fmpy's CMake project, or a plain `cc -shared sources/\*.c`) would not load in a host
   that has no libm of its own ("undefined symbol: sincos"); without HELI_LIBM_LINKED the math
   functions are therefore called through pointers that heli_libm.c takes from libm.so.6
   (dlopen) when the library is loaded. Same functions, same results. Include after <math.h>. */
#ifndef HELI_LIBM_H
#define HELI_LIBM_H

#if (defined(_WIN32) || defined(__APPLE__)) && !defined(HELI_LIBM_LINKED)
#define HELI_LIBM_LINKED /* the C runtime (Windows) or libSystem (macOS) has the math functions */
#endif

int heli_libm_ready(void); /* 1 when the math functions can be called */
const char* heli_libm_problem(void); /* why not (NULL when ready) */

#ifndef HELI_LIBM_LINKED
#define HELI_LIBM_UNARY(X) X(sin) X(cos) X(tan) X(asin) X(acos) X(atan) X(sinh) X(cosh) X(tanh) X(exp) \
  X(log) X(log10) X(sqrt) X(floor) X(ceil) X(erf) X(expm1) X(log1p) X(cbrt) X(round) X(trunc)
#define HELI_LIBM_BINARY(X) X(atan2) X(pow) X(fmin) X(fmax) X(fmod) X(hypot) X(copysign)
#define HELI_LIBM_DECLARE1(f) double heli_libm_##f(double);
#define HELI_LIBM_DECLARE2(f) double heli_libm_##f(double, double);
HELI_LIBM_UNARY(HELI_LIBM_DECLARE1)
HELI_LIBM_BINARY(HELI_LIBM_DECLARE2)
#define sin heli_libm_sin
#define cos heli_libm_cos
#define tan heli_libm_tan
#define asin heli_libm_asin
#define acos heli_libm_acos
#define atan heli_libm_atan
#define sinh heli_libm_sinh
#define cosh heli_libm_cosh
#define tanh heli_libm_tanh
#define exp heli_libm_exp
#define log heli_libm_log
#define log10 heli_libm_log10
#define sqrt heli_libm_sqrt
#define floor heli_libm_floor
#define ceil heli_libm_ceil
#define erf heli_libm_erf
#define expm1 heli_libm_expm1
#define log1p heli_libm_log1p
#define cbrt heli_libm_cbrt
#define round heli_libm_round
#define trunc heli_libm_trunc
#define atan2 heli_libm_atan2
#define pow heli_libm_pow
#define fmin heli_libm_fmin
#define fmax heli_libm_fmax
#define fmod heli_libm_fmod
#define hypot heli_libm_hypot
#define copysign heli_libm_copysign
#endif

#endif
