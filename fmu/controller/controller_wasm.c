/* The WebAssembly entry points of the hover-hold controller (controller_fmi2.c, unchanged), for
   the browser page of `heli fly`: one instance driven through its FMI 2.0 functions as a
   co-simulation master drives the controller FMU. Inputs (the helicopter's fuselage outputs)
   and outputs (its four pitch inputs) cross through one buffer of doubles, in the order of the
   FMU's value references. Every function returns the fmi2Status of its last call. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "hover_hold_data.h"

#define HH_EXPORT(name) __attribute__((export_name(#name), visibility("default")))

static fmi2Component controller;
static double buffer[HH_NIN + HH_NOUT + 1];
static char message[1024];

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String format, ...) {
  va_list ap;
  (void) env, (void) name, (void) category;
  if (status == fmi2OK) return;
  va_start(ap, format);
  vsnprintf(message, sizeof message, format, ap);
  va_end(ap);
}

static void* allocate(size_t n, size_t size) { return calloc(n, size); }

static const fmi2CallbackFunctions callbacks = {logger, allocate, free, NULL, NULL};

HH_EXPORT(hh_buffer) double* hh_buffer(void) { return buffer; }

HH_EXPORT(hh_message) const char* hh_message(void) { return message; }

HH_EXPORT(hh_inputs) int hh_inputs(void) { return HH_NIN; }

HH_EXPORT(hh_outputs) int hh_outputs(void) { return HH_NOUT; }

HH_EXPORT(hh_free) void hh_free(void) {
  if (controller) fmi2FreeInstance(controller);
  controller = NULL;
}

/* A fresh instance with gain_scale (0: open loop, 1: closed), initialised at time 0. */
HH_EXPORT(hh_open) int hh_open(double gain_scale) {
  fmi2ValueReference scale = HH_NIN + HH_NOUT;
  fmi2Status status;
  hh_free();
  message[0] = 0;
  controller = fmi2Instantiate("page", fmi2CoSimulation, HH_GUID, "", &callbacks, fmi2False, fmi2False);
  if (!controller) return fmi2Fatal;
  status = fmi2SetupExperiment(controller, fmi2False, 0.0, 0.0, fmi2False, 0.0);
  if (status == fmi2OK) status = fmi2EnterInitializationMode(controller);
  if (status == fmi2OK) status = fmi2SetReal(controller, &scale, 1, &gain_scale);
  if (status == fmi2OK) status = fmi2ExitInitializationMode(controller);
  return status;
}

/* Set the inputs from hh_buffer[0 .. HH_NIN). */
HH_EXPORT(hh_set_inputs) int hh_set_inputs(void) {
  fmi2ValueReference vr[HH_NIN];
  int k;
  for (k = 0; k < HH_NIN; ++k) vr[k] = (fmi2ValueReference) k;
  return fmi2SetReal(controller, vr, HH_NIN, buffer);
}

HH_EXPORT(hh_step) int hh_step(double t, double dt) { return fmi2DoStep(controller, t, dt, fmi2True); }

/* The outputs into hh_buffer[HH_NIN .. HH_NIN + HH_NOUT). */
HH_EXPORT(hh_get_outputs) int hh_get_outputs(void) {
  fmi2ValueReference vr[HH_NOUT];
  int k;
  for (k = 0; k < HH_NOUT; ++k) vr[k] = (fmi2ValueReference) (HH_NIN + k);
  return fmi2GetReal(controller, vr, HH_NOUT, buffer + HH_NIN);
}
