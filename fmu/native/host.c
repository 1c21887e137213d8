/* A minimal FMI 2.0 co-simulation master for the tests and the benchmark: loads an FMU's
   shared library (dlopen; LoadLibrary on Windows) and drives it through the standard functions
   only. It builds for Linux (x86_64, aarch64) and, with mingw, for Windows.

   host run SO GUID SCENE DT STEPS IN_VRS IN_VALUES OUT_VRS [quiet]
       (SCENE is VR=NAME, the scene parameter's value reference and value) instantiate, set the scene and the inputs (held constant), initialise, then STEPS
       steps of DT seconds; prints "t v1 v2 ..." (%.17g) after each step, or with "quiet"
       only "steps N cpu_s C wall_s W" (the loop's CPU and wall time).
   host cycles SO GUID SCENE N
       N instantiate / initialise / step / free cycles; prints "rss_kb BEFORE AFTER".

   Value-reference and value lists are comma-separated. Exit status 0 on success. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "host_platform.h"

#define MAX_VALUES 256

typedef struct {
  fmi2InstantiateTYPE* instantiate;
  fmi2FreeInstanceTYPE* free_instance;
  fmi2SetupExperimentTYPE* setup;
  fmi2EnterInitializationModeTYPE* enter;
  fmi2ExitInitializationModeTYPE* exit_init;
  fmi2SetRealTYPE* set_real;
  fmi2GetRealTYPE* get_real;
  fmi2SetStringTYPE* set_string;
  fmi2DoStepTYPE* do_step;
  fmi2TerminateTYPE* terminate;
} api;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
  char text[4096];
  va_list ap;
  (void) env;
  va_start(ap, message);
  vsnprintf(text, sizeof text, message, ap);
  va_end(ap);
  fprintf(stderr, "[%s %d %s] %s\n", name, (int) status, category, text);
}

static void* symbol(void* lib, const char* name) {
  void* f = find_symbol(lib, name);
  if (!f) {
    fprintf(stderr, "missing %s\n", name);
    exit(2);
  }
  return f;
}

static void load(const char* path, api* a) {
  void* lib = open_library(path);
  if (!lib) {
    fprintf(stderr, "loading %s failed: %s\n", path, library_error());
    exit(2);
  }
  a->instantiate = (fmi2InstantiateTYPE*) symbol(lib, "fmi2Instantiate");
  a->free_instance = (fmi2FreeInstanceTYPE*) symbol(lib, "fmi2FreeInstance");
  a->setup = (fmi2SetupExperimentTYPE*) symbol(lib, "fmi2SetupExperiment");
  a->enter = (fmi2EnterInitializationModeTYPE*) symbol(lib, "fmi2EnterInitializationMode");
  a->exit_init = (fmi2ExitInitializationModeTYPE*) symbol(lib, "fmi2ExitInitializationMode");
  a->set_real = (fmi2SetRealTYPE*) symbol(lib, "fmi2SetReal");
  a->get_real = (fmi2GetRealTYPE*) symbol(lib, "fmi2GetReal");
  a->set_string = (fmi2SetStringTYPE*) symbol(lib, "fmi2SetString");
  a->do_step = (fmi2DoStepTYPE*) symbol(lib, "fmi2DoStep");
  a->terminate = (fmi2TerminateTYPE*) symbol(lib, "fmi2Terminate");
}

static size_t parse_vrs(const char* text, fmi2ValueReference* out) {
  size_t n = 0;
  char* end;
  while (*text && n < MAX_VALUES) {
    out[n++] = (fmi2ValueReference) strtoul(text, &end, 10);
    text = *end == ',' ? end + 1 : end;
  }
  return n;
}

static size_t parse_reals(const char* text, double* out) {
  size_t n = 0;
  char* end;
  while (*text && n < MAX_VALUES) {
    out[n++] = strtod(text, &end);
    text = *end == ',' ? end + 1 : end;
  }
  return n;
}

static const fmi2CallbackFunctions CALLBACKS = {logger, calloc, free, NULL, NULL};

static fmi2Component start(const api* a, const char* guid, const char* scene, const fmi2ValueReference* in_vr,
                           const double* in, size_t n_in, fmi2ValueReference scene_vr) {
  fmi2Component c = a->instantiate("host", fmi2CoSimulation, guid, "", &CALLBACKS, fmi2False, fmi2False);
  if (!c || a->setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) || a->enter(c)) return NULL;
  if (a->set_string(c, &scene_vr, 1, &scene) > fmi2Warning || a->set_real(c, in_vr, n_in, in) > fmi2Warning) return NULL;
  return a->exit_init(c) ? NULL : c;
}

static int run(const api* a, char** argv, int quiet) {
  fmi2ValueReference in_vr[MAX_VALUES], out_vr[MAX_VALUES];
  double in[MAX_VALUES], out[MAX_VALUES], dt = strtod(argv[4], NULL), t, t0;
  long steps = strtol(argv[5], NULL, 10), k;
  size_t n_in = parse_vrs(argv[6], in_vr), n_out = parse_vrs(argv[8], out_vr), j;
  fmi2Component c;
  clock_t c0;
  char* scene = strchr(argv[3], '=');
  parse_reals(argv[7], in);
  if (!scene || !(c = start(a, argv[2], scene + 1, in_vr, in, n_in, (fmi2ValueReference) atoi(argv[3])))) return 1;
  t0 = now();
  c0 = clock();
  for (k = 0; k < steps; ++k) {
    t = (double) k * dt; /* communication points k dt, as fmpy makes them */
    if (a->set_real(c, in_vr, n_in, in) || a->do_step(c, t, (double) (k + 1) * dt - t, fmi2True) ||
        a->get_real(c, out_vr, n_out, out))
      return 1;
    if (quiet) continue;
    printf("%.17g", (double) (k + 1) * dt);
    for (j = 0; j < n_out; ++j) printf(" %.17g", out[j]);
    printf("\n");
  }
  if (quiet)
    printf("steps %ld cpu_s %.9f wall_s %.9f\n", steps, (double) (clock() - c0) / CLOCKS_PER_SEC, now() - t0);
  a->terminate(c);
  a->free_instance(c);
  return 0;
}

static long rss_kb(void) {
  long pages = 0, resident = 0;
  FILE* f = fopen("/proc/self/statm", "r");
  if (f) {
    if (fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    fclose(f);
  }
  return resident * 4;
}

static int cycles(const api* a, const char* guid, const char* scene, long n) {
  fmi2ValueReference vr = 0;
  double v = 0.0, dt = 1e-3;
  long k, before = 0;
  for (k = 0; k < n; ++k) {
    fmi2Component c = start(a, guid, strchr(scene, '=') + 1, &vr, &v, 0, (fmi2ValueReference) atoi(scene));
    if (!c || a->do_step(c, 0.0, dt, fmi2True) || a->get_real(c, &vr, 1, &v)) return 1;
    a->free_instance(c);
    if (k == 9) before = rss_kb(); /* after warm-up: the allocator's own pools are in place */
  }
  printf("rss_kb %ld %ld\n", before, rss_kb());
  return 0;
}

int main(int argc, char** argv) {
  api a;
  if (argc >= 10 && !strcmp(argv[1], "run")) {
    load(argv[2], &a);
    return run(&a, argv + 1, argc > 10 && !strcmp(argv[10], "quiet"));
  }
  if (argc == 6 && !strcmp(argv[1], "cycles") && strchr(argv[4], '=')) {
    load(argv[2], &a);
    return cycles(&a, argv[3], argv[4], strtol(argv[5], NULL, 10));
  }
  fprintf(stderr, "usage: host run SO GUID SCENE DT STEPS IN_VRS IN_VALUES OUT_VRS [quiet]\n"
                  "       host cycles SO GUID SCENE N\n");
  return 2;
}
