/* What a C host of an FMU needs of its platform: open a shared library (dlopen; LoadLibrary on
   Windows), find its symbols, say why opening failed, and read a monotonic wall clock (s).
   Included by the native FMU's host (host.c) and the tests' scripted host. */
#ifndef HOST_PLATFORM_H
#define HOST_PLATFORM_H

#include <time.h>
#ifdef _WIN32
#include <windows.h>
#else
#include <dlfcn.h>
#endif

#ifdef _WIN32
static inline void* open_library(const char* path) { return (void*) LoadLibraryA(path); }
static inline void* find_symbol(void* lib, const char* name) { return (void*) GetProcAddress((HMODULE) lib, name); }
static inline const char* library_error(void) { return "LoadLibrary failed"; }
#else
static inline void* open_library(const char* path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static inline void* find_symbol(void* lib, const char* name) { return dlsym(lib, name); }
static inline const char* library_error(void) { return dlerror(); }
#endif

static inline double now(void) {
#ifdef _WIN32
  LARGE_INTEGER f, t;
  QueryPerformanceFrequency(&f);
  QueryPerformanceCounter(&t);
  return (double) t.QuadPart / (double) f.QuadPart;
#else
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double) ts.tv_sec + 1e-9 * (double) ts.tv_nsec;
#endif
}

#endif
