/* FMI 2.0 interface of the heli rotor model (co-simulation and model exchange): each function
   checks its instance and hands the call to the model core (heli_core.h). Value references are
   the core's slots. */
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "heli_core.h"
#include "heli_forward.h"

/* The call's instance, or return fmi2Error (reported by the core). */
#define INSTANCE(call)                                  \
  heli_instance* c = heli_checked(component, call);    \
  if (!c) return fmi2Error

typedef struct {
  fmi2CallbackLogger logger;
  fmi2ComponentEnvironment env;
} environment;

/* The FMI 2.0 logger takes a printf format: every '%' doubled, so that the text arrives unchanged. */
static void log_fmi2(void* e, const char* name, int status, const char* category, const char* message) {
  environment* w = (environment*) e;
  char escaped[8 * 4 * 512];
  size_t k = 0;
  if (!w || !w->logger) return;
  for (; *message && k + 2 < sizeof escaped; ++message) {
    if (*message == '%') escaped[k++] = '%';
    escaped[k++] = *message;
  }
  escaped[k] = 0;
  w->logger(w->env, name, (fmi2Status) status, category, escaped);
}

/* -- life cycle ------------------------------------------------------------------------------- */

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
  environment* w = (environment*) calloc(1, sizeof *w);
  heli_instance* c;
  (void) fmuResourceLocation; /* everything is compiled in */
  (void) visible;
  if (w && functions) {
    w->logger = functions->logger;
    w->env = functions->componentEnvironment;
  }
  if (fmuType != fmi2CoSimulation && fmuType != fmi2ModelExchange) {
    heli_report_without(log_fmi2, w, instanceName, "fmi2Instantiate: fmuType %d is neither fmi2ModelExchange nor "
                        "fmi2CoSimulation", (int) fmuType);
    free(w);
    return NULL;
  }
  c = w ? heli_instantiate("fmi2", instanceName, fmuType == fmi2ModelExchange ? HELI_MODEL_EXCHANGE : HELI_COSIMULATION,
                           fmuGUID, log_fmi2, w, loggingOn != fmi2False) : NULL;
  if (!c) free(w);
  return c;
}

void fmi2FreeInstance(fmi2Component component) {
  heli_instance* c = (heli_instance*) component;
  void* w;
  if (!heli_checked(c, "fmi2FreeInstance")) return;
  w = heli_environment(c);
  heli_free(c);
  free(w);
}

fmi2Status fmi2SetDebugLogging(fmi2Component component, fmi2Boolean loggingOn, size_t n, const fmi2String categories[]) {
  INSTANCE("fmi2SetDebugLogging");
  return (fmi2Status) heli_set_debug_logging(c, loggingOn != fmi2False, n, categories);
}

fmi2Status fmi2SetupExperiment(fmi2Component component, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  INSTANCE("fmi2SetupExperiment");
  (void) toleranceDefined, (void) tolerance; /* fixed-step: no tolerance */
  return (fmi2Status) heli_setup(c, "fmi2SetupExperiment", startTime, stopTimeDefined != fmi2False, stopTime);
}

HELI_FORWARD0(fmi2Status, fmi2EnterInitializationMode, heli_enter_initialization, (fmi2Component instance))

HELI_FORWARD0(fmi2Status, fmi2ExitInitializationMode, heli_exit_initialization, (fmi2Component instance))

HELI_FORWARD0(fmi2Status, fmi2Terminate, heli_terminate, (fmi2Component instance))

HELI_FORWARD0(fmi2Status, fmi2Reset, heli_reset, (fmi2Component instance))

/* -- values ------------------------------------------------------------------------------------- */

fmi2Status fmi2GetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
  size_t k;
  INSTANCE("fmi2GetReal");
  if (heli_no_values(c, "fmi2GetReal", n, vr, value) || !heli_gettable_now(c, "fmi2GetReal")) return fmi2Error;
  for (k = 0; k < n; ++k)
    if (!heli_lookup(c, "fmi2GetReal", vr[k], "Real") || heli_get_real(c, "fmi2GetReal", (int) vr[k], &value[k]))
      return fmi2Error;
  return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
  int st = fmi2OK, one;
  size_t k;
  INSTANCE("fmi2SetReal");
  if (heli_no_values(c, "fmi2SetReal", n, vr, value) || !heli_settable_now(c, "fmi2SetReal")) return fmi2Error;
  for (k = 0; k < n; ++k) {
    one = heli_lookup(c, "fmi2SetReal", vr[k], "Real") ? heli_set_real(c, "fmi2SetReal", (int) vr[k], value[k])
                                                        : fmi2Error;
    if (one > st) st = one;
  }
  return (fmi2Status) st;
}

fmi2Status fmi2GetString(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2String value[]) {
  size_t k;
  INSTANCE("fmi2GetString");
  if (heli_no_values(c, "fmi2GetString", n, vr, value) || !heli_gettable_now(c, "fmi2GetString")) return fmi2Error;
  for (k = 0; k < n; ++k) {
    if (!heli_lookup(c, "fmi2GetString", vr[k], "String")) return fmi2Error;
    value[k] = heli_get_string(c, (int) vr[k]);
  }
  return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2String value[]) {
  int st = fmi2OK, one;
  size_t k;
  INSTANCE("fmi2SetString");
  if (heli_no_values(c, "fmi2SetString", n, vr, value) || !heli_settable_now(c, "fmi2SetString")) return fmi2Error;
  for (k = 0; k < n; ++k) {
    one = heli_lookup(c, "fmi2SetString", vr[k], "String") ? heli_set_string(c, "fmi2SetString", (int) vr[k], value[k])
                                                            : fmi2Error;
    if (one > st) st = one;
  }
  return (fmi2Status) st;
}

/* This FMU has no Integer or Boolean variables: every value reference is refused. */
#define NO_SUCH_TYPE(name, type, value_type)                                                                 \
  fmi2Status fmi2##name(fmi2Component component, const fmi2ValueReference vr[], size_t n, value_type value[]) { \
    INSTANCE("fmi2" #name);                                                                                \
    (void) value;                                                                                          \
    return (fmi2Status) heli_no_such_type(c, "fmi2" #name, type, vr, n);                                   \
  }
NO_SUCH_TYPE(GetInteger, "Integer", fmi2Integer)
NO_SUCH_TYPE(SetInteger, "Integer", const fmi2Integer)
NO_SUCH_TYPE(GetBoolean, "Boolean", fmi2Boolean)
NO_SUCH_TYPE(SetBoolean, "Boolean", const fmi2Boolean)

/* -- exact derivatives ------------------------------------------------------------------------------ */

HELI_FORWARD(fmi2Status, fmi2GetDirectionalDerivative, heli_directional, (fmi2Component instance, const fmi2ValueReference unknown[], size_t nu, const fmi2ValueReference known[], size_t nk, const fmi2Real dv_known[], fmi2Real dv_unknown[]),
             unknown, nu, known, nk, dv_known, dv_unknown)

/* -- co-simulation ------------------------------------------------------------------------------------ */

fmi2Status fmi2DoStep(fmi2Component component, fmi2Real t, fmi2Real dt, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  INSTANCE("fmi2DoStep");
  (void) noSetFMUStatePriorToCurrentPoint;
  return (fmi2Status) heli_do_step(c, "fmi2DoStep", t, dt);
}

/* Calls this FMU does not support: an error that says why. */
#define UNSUPPORTED(name, why, params, uses)                 \
  fmi2Status fmi2##name params {                             \
    INSTANCE("fmi2" #name);                                  \
    uses;                                                    \
    return (fmi2Status) heli_refuse(c, "fmi2" #name, why);   \
  }
UNSUPPORTED(CancelStep, "this FMU never runs a step asynchronously (no fmi2Pending)", (fmi2Component component), )
UNSUPPORTED(SetRealInputDerivatives, "not supported (canInterpolateInputs = false)",
            (fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
             const fmi2Real value[]), ((void) vr, (void) n, (void) order, (void) value))
UNSUPPORTED(GetRealOutputDerivatives, "not supported (maxOutputDerivativeOrder = 0)",
            (fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
             fmi2Real value[]), ((void) vr, (void) n, (void) order, (void) value))

/* Status kinds this FMU does not have: fmi2Discard with a message (fmi2Error for a NULL value pointer). */
#define NO_STATUS(name, value_type)                                                        \
  fmi2Status fmi2##name(fmi2Component component, const fmi2StatusKind s, value_type* value) { \
    INSTANCE("fmi2" #name);                                                               \
    return (fmi2Status) heli_no_status(c, "fmi2" #name, (int) s, value);                  \
  }
NO_STATUS(GetStatus, fmi2Status)
NO_STATUS(GetIntegerStatus, fmi2Integer)
NO_STATUS(GetStringStatus, fmi2String)

fmi2Status fmi2GetRealStatus(fmi2Component component, const fmi2StatusKind s, fmi2Real* value) {
  INSTANCE("fmi2GetRealStatus");
  if (s != fmi2LastSuccessfulTime) return (fmi2Status) heli_no_status(c, "fmi2GetRealStatus", (int) s, value);
  return (fmi2Status) heli_last_successful_time(c, "fmi2GetRealStatus", value);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component component, const fmi2StatusKind s, fmi2Boolean* value) {
  int terminated = 0, st;
  INSTANCE("fmi2GetBooleanStatus");
  if (s != fmi2Terminated) return (fmi2Status) heli_no_status(c, "fmi2GetBooleanStatus", (int) s, value);
  st = heli_terminated_status(c, "fmi2GetBooleanStatus", value ? &terminated : NULL);
  if (value && st == fmi2OK) *value = terminated ? fmi2True : fmi2False;
  return (fmi2Status) st;
}

/* -- model exchange ------------------------------------------------------------------------------------ */

HELI_FORWARD0(fmi2Status, fmi2EnterEventMode, heli_event_mode, (fmi2Component instance))

fmi2Status fmi2NewDiscreteStates(fmi2Component component, fmi2EventInfo* info) {
  int st;
  INSTANCE("fmi2NewDiscreteStates");
  if (!info) return (fmi2Status) heli_refuse(c, "fmi2NewDiscreteStates", "the event info pointer is NULL");
  st = heli_discrete_states(c, "fmi2NewDiscreteStates");
  if (st == fmi2OK) memset(info, 0, sizeof *info); /* no events, no discrete states: nothing to iterate */
  return (fmi2Status) st;
}

HELI_FORWARD0(fmi2Status, fmi2EnterContinuousTimeMode, heli_continuous_time_mode, (fmi2Component instance))

fmi2Status fmi2CompletedIntegratorStep(fmi2Component component, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean* enterEventMode, fmi2Boolean* terminateSimulation) {
  int terminate = 0, st;
  INSTANCE("fmi2CompletedIntegratorStep");
  (void) noSetFMUStatePriorToCurrentPoint;
  st = heli_completed_integrator_step(c, "fmi2CompletedIntegratorStep", &terminate);
  if (enterEventMode) *enterEventMode = fmi2False;
  if (terminateSimulation) *terminateSimulation = terminate ? fmi2True : fmi2False;
  return (fmi2Status) st;
}

HELI_FORWARD(fmi2Status, fmi2SetTime, heli_set_time, (fmi2Component instance, fmi2Real time),
             time)

HELI_FORWARD(fmi2Status, fmi2SetContinuousStates, heli_set_states, (fmi2Component instance, const fmi2Real x[], size_t nx),
             x, nx)

HELI_FORWARD(fmi2Status, fmi2GetContinuousStates, heli_get_states, (fmi2Component instance, fmi2Real x[], size_t nx),
             x, nx)

HELI_FORWARD(fmi2Status, fmi2GetDerivatives, heli_get_derivatives, (fmi2Component instance, fmi2Real derivatives[], size_t nx),
             derivatives, nx)

HELI_FORWARD(fmi2Status, fmi2GetNominalsOfContinuousStates, heli_get_nominals, (fmi2Component instance, fmi2Real x_nominal[], size_t nx),
             x_nominal, nx)

fmi2Status fmi2GetEventIndicators(fmi2Component component, fmi2Real indicators[], size_t ni) {
  INSTANCE("fmi2GetEventIndicators");
  (void) indicators;
  return (fmi2Status) (ni ? heli_refuse(c, "fmi2GetEventIndicators", "this FMU has no event indicators") : fmi2OK);
}

/* -- FMU state -------------------------------------------------------------------------------------- */

HELI_FORWARD(fmi2Status, fmi2GetFMUstate, heli_get_state, (fmi2Component instance, fmi2FMUstate* state),
             state)

HELI_FORWARD(fmi2Status, fmi2SetFMUstate, heli_set_state, (fmi2Component instance, fmi2FMUstate state),
             state)

HELI_FORWARD(fmi2Status, fmi2FreeFMUstate, heli_free_state, (fmi2Component instance, fmi2FMUstate* state),
             state)

HELI_FORWARD(fmi2Status, fmi2SerializedFMUstateSize, heli_serialized_size, (fmi2Component instance, fmi2FMUstate state, size_t* size),
             state, size)

HELI_FORWARD(fmi2Status, fmi2SerializeFMUstate, heli_serialize, (fmi2Component instance, fmi2FMUstate state, fmi2Byte bytes[], size_t size),
             state, (unsigned char*) bytes, size)

HELI_FORWARD(fmi2Status, fmi2DeSerializeFMUstate, heli_deserialize, (fmi2Component instance, const fmi2Byte bytes[], size_t size, fmi2FMUstate* state),
             (const unsigned char*) bytes, size, state)
