/* A C host linked to libpython that runs the pythonfmu FMU once and exits, for the exit test.

   python_host MODE SO GUID RESOURCES_URI STEPS DT VR
     MODE embed: the host starts Python itself (Py_Initialize before loading the FMU, as an
                 application embedding Python does) and finalises it after freeing the FMU;
     MODE linked: the host only links libpython; pythonfmu's library starts Python.
   Runs STEPS steps of DT s and prints "t value" of the Real VR after each, then frees the
   instance and returns 0 from main: whatever happens at exit after that is the FMU's. The
   interpreter finds numpy through PYTHONPATH. */
#include <Python.h>
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
  (void) env, (void) category;
  if (status > fmi2OK) fprintf(stderr, "%s [%d] %s\n", name, (int) status, message);
}

#define LOAD(type, name) type* name = (type*) dlsym(lib, "fmi2" #name)

int main(int argc, char** argv) {
  fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
  int embed, steps, k;
  double dt, t = 0.0, value;
  void* lib;
  fmi2Component c;
  fmi2ValueReference vr;
  if (argc != 8) {
    fprintf(stderr, "usage: python_host embed|linked SO GUID RESOURCES_URI STEPS DT VR\n");
    return 2;
  }
  embed = !strcmp(argv[1], "embed");
  steps = atoi(argv[5]);
  dt = atof(argv[6]);
  vr = (fmi2ValueReference) strtoul(argv[7], NULL, 10);
  if (embed) Py_Initialize();
  lib = dlopen(argv[2], RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    fprintf(stderr, "dlopen: %s\n", dlerror());
    return 3;
  }
  {
    LOAD(fmi2InstantiateTYPE, Instantiate);
    LOAD(fmi2SetupExperimentTYPE, SetupExperiment);
    LOAD(fmi2EnterInitializationModeTYPE, EnterInitializationMode);
    LOAD(fmi2ExitInitializationModeTYPE, ExitInitializationMode);
    LOAD(fmi2DoStepTYPE, DoStep);
    LOAD(fmi2GetRealTYPE, GetReal);
    LOAD(fmi2TerminateTYPE, Terminate);
    LOAD(fmi2FreeInstanceTYPE, FreeInstance);
    c = Instantiate("exit-test", fmi2CoSimulation, argv[3], argv[4], &cb, fmi2False, fmi2False);
    if (!c) return 4;
    if (SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) || EnterInitializationMode(c) ||
        ExitInitializationMode(c) > fmi2Warning)
      return 5;
    for (k = 0; k < steps; ++k, t += dt) {
      if (DoStep(c, t, dt, fmi2True) || GetReal(c, &vr, 1, &value)) return 6;
      printf("%.17g %.17g\n", t + dt, value);
    }
    Terminate(c);
    FreeInstance(c);
  }
  fflush(stdout);
  if (embed) Py_FinalizeEx();
  return 0;
}
