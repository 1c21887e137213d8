/* FMI 3.0 interface of the heli rotor model (model exchange and co-simulation): each function
   checks its instance, maps FMI 3.0 value references (scalars and arrays) to the core's slots
   (heli_model.variables3) and hands the call to the model core (heli_core.h). The continuous
   states are in the order of the FMI 3.0 derivatives (heli_model.me_order3). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "heli_core.h"
#include "heli_forward.h"

#define M (&heli_model_data)
#define MAX_SLOTS (HELI_NV + HELI_NX)

/* The call's instance, or return fmi3Error (reported by the core). */
#define INSTANCE(call)                                  \
  heli_instance* c = heli_checked(instance, call);     \
  if (!c) return fmi3Error

typedef struct {
  fmi3LogMessageCallback log;
  fmi3InstanceEnvironment env;
} environment;

static void log_fmi3(void* e, const char* name, int status, const char* category, const char* message) {
  environment* w = (environment*) e;
  (void) name;
  if (w && w->log) w->log(w->env, (fmi3Status) status, category, message);
}

/* -- value references ------------------------------------------------------------------------------ */

/* The slots of the variables vr[0 .. n-1] into slots[] (-1: time); their count, or -1 (reported) when a
   value reference is unknown, of another type than `type`, or (`time_ok` 0) the independent time. */
static int expand(heli_instance* c, const char* call, const fmi3ValueReference vr[], size_t n, const char* type,
                  int time_ok, int slots[]) {
  size_t k;
  int total = 0, j;
  if (heli_no_values(c, call, n, vr, vr)) return -1;
  for (k = 0; k < n; ++k) {
    const heli_variable3* v;
    if (vr[k] >= (fmi3ValueReference) M->n_variables3) {
      char why[128];
      snprintf(why, sizeof why, "unknown value reference %u (this FMU has value references 0 to %d)", vr[k],
               M->n_variables3 - 1);
      heli_refuse(c, call, why);
      return -1;
    }
    v = &M->variables3[vr[k]];
    if (v->slots[0] < 0 && !time_ok) {
      heli_refuse(c, call, "value reference 0 is the independent variable 'time', which cannot be set");
      return -1;
    }
    if (v->slots[0] >= 0 && !heli_lookup(c, call, (unsigned) v->slots[0], type)) return -1;
    if (total + v->n > MAX_SLOTS) return heli_refuse(c, call, "too many values"), -1;
    for (j = 0; j < v->n; ++j) slots[total++] = v->slots[j];
  }
  return total;
}

static int count_problem(heli_instance* c, const char* call, const char* what, size_t given, int needed) {
  char why[160];
  if (given == (size_t) needed) return 0;
  strcpy(why, what);
  strcat(why, ": the number of values does not match the elements of the variables");
  heli_refuse(c, call, why);
  return 1;
}

/* -- life cycle ------------------------------------------------------------------------------------ */

const char* fmi3GetVersion(void) { return fmi3Version; }

static fmi3Instance instantiate(const char* call, fmi3String name, fmi3String token, int kind, fmi3Boolean logging,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
  environment* w = (environment*) calloc(1, sizeof *w);
  heli_instance* c;
  if (!w) return NULL;
  w->log = log;
  w->env = env;
  (void) call;
  c = heli_instantiate("fmi3", name, kind, token, log_fmi3, w, logging != fmi3False);
  if (!c) free(w);
  return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
  (void) resourcePath, (void) visible; /* everything is compiled in */
  return instantiate("fmi3InstantiateModelExchange", instanceName, instantiationToken, HELI_MODEL_EXCHANGE, loggingOn,
                     instanceEnvironment, logMessage);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
  (void) resourcePath, (void) visible, (void) earlyReturnAllowed, (void) requiredIntermediateVariables;
  (void) nRequiredIntermediateVariables, (void) intermediateUpdate; /* no intermediate updates, no early return */
  if (eventModeUsed) {
    heli_report_without(log_fmi3, NULL, instanceName, "fmi3InstantiateCoSimulation: eventModeUsed = true, but this FMU "
                        "has no events (hasEventMode = false)");
    if (logMessage) logMessage(instanceEnvironment, fmi3Error, "logStatusError", "fmi3InstantiateCoSimulation: "
                               "eventModeUsed = true, but this FMU has no events (hasEventMode = false)");
    return NULL;
  }
  return instantiate("fmi3InstantiateCoSimulation", instanceName, instantiationToken, HELI_COSIMULATION, loggingOn,
                     instanceEnvironment, logMessage);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
  (void) instantiationToken, (void) resourcePath, (void) visible, (void) loggingOn, (void) clockUpdate;
  (void) lockPreemption, (void) unlockPreemption;
  if (logMessage) logMessage(instanceEnvironment, fmi3Error, "logStatusError", "fmi3InstantiateScheduledExecution: "
                             "this FMU offers model exchange and co-simulation only");
  heli_report_without(NULL, NULL, instanceName, "fmi3InstantiateScheduledExecution: this FMU offers model exchange "
                      "and co-simulation only");
  return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) {
  heli_instance* c = (heli_instance*) instance;
  void* w;
  if (!heli_checked(c, "fmi3FreeInstance")) return;
  w = heli_environment(c);
  heli_free(c);
  free(w);
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
  INSTANCE("fmi3SetDebugLogging");
  return (fmi3Status) heli_set_debug_logging(c, loggingOn != fmi3False, nCategories, categories);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
  INSTANCE("fmi3EnterInitializationMode");
  (void) toleranceDefined, (void) tolerance; /* fixed-step: no tolerance */
  if (heli_setup(c, "fmi3EnterInitializationMode", startTime, stopTimeDefined != fmi3False, stopTime)) return fmi3Error;
  return (fmi3Status) heli_enter_initialization(c, "fmi3EnterInitializationMode");
}

/* The life-cycle calls: the one forwarding shape of heli_forward.h. */
#define FORWARD(name, core) HELI_FORWARD0(fmi3Status, fmi3##name, core, (fmi3Instance instance))
FORWARD(ExitInitializationMode, heli_exit_initialization)
FORWARD(Terminate, heli_terminate)
FORWARD(Reset, heli_reset)
FORWARD(EnterEventMode, heli_event_mode)
FORWARD(EnterContinuousTimeMode, heli_continuous_time_mode)
FORWARD(EnterStepMode, heli_step_mode)

static int not_provided(heli_instance* c, const char* call) {
  return heli_refuse(c, call, "not provided (providesEvaluateDiscreteStates = false: this FMU has no discrete states)");
}
FORWARD(EvaluateDiscreteStates, not_provided)

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
                                    fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged,
                                    fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined,
                                    fmi3Float64* nextEventTime) {
  fmi3Boolean* flags[5];
  int k, st;
  INSTANCE("fmi3UpdateDiscreteStates");
  if ((st = heli_discrete_states(c, "fmi3UpdateDiscreteStates")) != fmi3OK) return (fmi3Status) st;
  flags[0] = discreteStatesNeedUpdate, flags[1] = terminateSimulation, flags[2] = nominalsOfContinuousStatesChanged;
  flags[3] = valuesOfContinuousStatesChanged, flags[4] = nextEventTimeDefined;
  for (k = 0; k < 5; ++k)
    if (flags[k]) *flags[k] = fmi3False; /* no events, no discrete states */
  if (nextEventTime) *nextEventTime = 0.0;
  return fmi3OK;
}

/* -- values --------------------------------------------------------------------------------------- */

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 values[],
                          size_t nValues) {
  int slots[MAX_SLOTS], total, k;
  INSTANCE("fmi3GetFloat64");
  if (!heli_gettable_now(c, "fmi3GetFloat64") || (total = expand(c, "fmi3GetFloat64", vr, n, "Float64", 1, slots)) < 0 ||
      count_problem(c, "fmi3GetFloat64", "values", nValues, total) || (total && !values))
    return fmi3Error;
  for (k = 0; k < total; ++k) {
    if (slots[k] < 0) values[k] = heli_time(c);
    else if (heli_get_real(c, "fmi3GetFloat64", slots[k], &values[k])) return fmi3Error;
  }
  return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Float64 values[],
                          size_t nValues) {
  int slots[MAX_SLOTS], total, k, st = fmi3OK, one;
  INSTANCE("fmi3SetFloat64");
  if ((total = expand(c, "fmi3SetFloat64", vr, n, "Float64", 0, slots)) < 0 ||
      count_problem(c, "fmi3SetFloat64", "values", nValues, total) || (total && !values) ||
      !heli_settable_now(c, "fmi3SetFloat64"))
    return fmi3Error;
  for (k = 0; k < total; ++k)
    if ((one = heli_set_real(c, "fmi3SetFloat64", slots[k], values[k])) > st) st = one;
  return (fmi3Status) st;
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3String values[],
                         size_t nValues) {
  int slots[MAX_SLOTS], total, k;
  INSTANCE("fmi3GetString");
  if (!heli_gettable_now(c, "fmi3GetString") || (total = expand(c, "fmi3GetString", vr, n, "String", 0, slots)) < 0 ||
      count_problem(c, "fmi3GetString", "values", nValues, total) || (total && !values))
    return fmi3Error;
  for (k = 0; k < total; ++k) values[k] = heli_get_string(c, slots[k]);
  return fmi3OK;
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3String values[],
                         size_t nValues) {
  int slots[MAX_SLOTS], total, k, st = fmi3OK, one;
  INSTANCE("fmi3SetString");
  if ((total = expand(c, "fmi3SetString", vr, n, "String", 0, slots)) < 0 ||
      count_problem(c, "fmi3SetString", "values", nValues, total) || (total && !values) ||
      !heli_settable_now(c, "fmi3SetString"))
    return fmi3Error;
  for (k = 0; k < total; ++k)
    if ((one = heli_set_string(c, "fmi3SetString", slots[k], values[k])) > st) st = one;
  return (fmi3Status) st;
}

/* Types this FMU has no variables of: every value reference is refused (unknown, or of another type). */
static fmi3Status no_such_type(fmi3Instance instance, const char* call, const char* type, const fmi3ValueReference vr[],
                               size_t n) {
  int slots[MAX_SLOTS];
  INSTANCE(call);
  if (expand(c, call, vr, n, type, 0, slots) < 0) return fmi3Error;
  return n ? (fmi3Status) heli_refuse(c, call, "no such variable") : fmi3OK;
}

#define NO_SUCH_TYPE(T)                                                                                          \
  fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3##T values[],        \
                        size_t nValues) {                                                                        \
    (void) values, (void) nValues;                                                                               \
    return no_such_type(instance, "fmi3Get" #T, #T, vr, n);                                                      \
  }                                                                                                              \
  fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3##T values[],  \
                        size_t nValues) {                                                                        \
    (void) values, (void) nValues;                                                                               \
    return no_such_type(instance, "fmi3Set" #T, #T, vr, n);                                                      \
  }
NO_SUCH_TYPE(Float32)
NO_SUCH_TYPE(Int8)
NO_SUCH_TYPE(UInt8)
NO_SUCH_TYPE(Int16)
NO_SUCH_TYPE(UInt16)
NO_SUCH_TYPE(Int32)
NO_SUCH_TYPE(UInt32)
NO_SUCH_TYPE(Int64)
NO_SUCH_TYPE(UInt64)
NO_SUCH_TYPE(Boolean)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, size_t valueSizes[],
                         fmi3Binary values[], size_t nValues) {
  (void) valueSizes, (void) values, (void) nValues;
  return no_such_type(instance, "fmi3GetBinary", "Binary", vr, n);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
  (void) valueSizes, (void) values, (void) nValues;
  return no_such_type(instance, "fmi3SetBinary", "Binary", vr, n);
}

/* -- calls of features this FMU does not have: an error that says why ----------------------------------- */

#define UNSUPPORTED(name, why, params, uses)                \
  fmi3Status fmi3##name params {                            \
    INSTANCE("fmi3" #name);                                 \
    uses;                                                   \
    return (fmi3Status) heli_refuse(c, "fmi3" #name, why);  \
  }
#define NO_CLOCKS "this FMU has no clocks"
UNSUPPORTED(GetClock, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Clock values[]),
            ((void) vr, (void) n, (void) values))
UNSUPPORTED(SetClock, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Clock values[]), ((void) vr, (void) n, (void) values))
UNSUPPORTED(GetIntervalDecimal, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                            fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]),
            ((void) vr, (void) n, (void) intervals, (void) qualifiers))
UNSUPPORTED(GetIntervalFraction, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                             fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                             fmi3IntervalQualifier qualifiers[]),
            ((void) vr, (void) n, (void) counters, (void) resolutions, (void) qualifiers))
UNSUPPORTED(GetShiftDecimal, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                         fmi3Float64 shifts[]), ((void) vr, (void) n, (void) shifts))
UNSUPPORTED(GetShiftFraction, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                          fmi3UInt64 counters[], fmi3UInt64 resolutions[]),
            ((void) vr, (void) n, (void) counters, (void) resolutions))
UNSUPPORTED(SetIntervalDecimal, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                            const fmi3Float64 intervals[]), ((void) vr, (void) n, (void) intervals))
UNSUPPORTED(SetIntervalFraction, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                             const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]),
            ((void) vr, (void) n, (void) counters, (void) resolutions))
UNSUPPORTED(SetShiftDecimal, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                         const fmi3Float64 shifts[]), ((void) vr, (void) n, (void) shifts))
UNSUPPORTED(SetShiftFraction, NO_CLOCKS, (fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                          const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]),
            ((void) vr, (void) n, (void) counters, (void) resolutions))
UNSUPPORTED(ActivateModelPartition, NO_CLOCKS, (fmi3Instance instance, fmi3ValueReference clockReference,
                                                fmi3Float64 activationTime), ((void) clockReference, (void) activationTime))
UNSUPPORTED(EnterConfigurationMode, "this FMU has no structural parameters", (fmi3Instance instance), )
UNSUPPORTED(ExitConfigurationMode, "this FMU has no structural parameters", (fmi3Instance instance), )
UNSUPPORTED(GetOutputDerivatives, "not supported (maxOutputDerivativeOrder = 0)",
            (fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Int32 orders[],
             fmi3Float64 values[], size_t nValues), ((void) vr, (void) n, (void) orders, (void) values, (void) nValues))
UNSUPPORTED(GetNumberOfVariableDependencies, "not provided at run time: modelDescription.xml lists every dependency",
            (fmi3Instance instance, fmi3ValueReference vr, size_t* n), ((void) vr, (void) n))
UNSUPPORTED(GetVariableDependencies, "not provided at run time: modelDescription.xml lists every dependency",
            (fmi3Instance instance, fmi3ValueReference dependent, size_t elementIndicesOfDependent[],
             fmi3ValueReference independents[], size_t elementIndicesOfIndependents[],
             fmi3DependencyKind dependencyKinds[], size_t nDependencies),
            ((void) dependent, (void) elementIndicesOfDependent, (void) independents,
             (void) elementIndicesOfIndependents, (void) dependencyKinds, (void) nDependencies))

/* -- exact derivatives ---------------------------------------------------------------------------- */

typedef int (*derivative_fn)(heli_instance*, const char*, const unsigned[], size_t, const unsigned[], size_t,
                             const double[], double[]);

/* Directional (forward) or adjoint (reverse) derivative: seeds belong to the knowns (forward) or to the
   unknowns (reverse); the elements of array variables count one by one. */
static fmi3Status derivative(fmi3Instance instance, const char* call, derivative_fn f, int reverse,
                             const fmi3ValueReference unknowns[], size_t nu, const fmi3ValueReference knowns[],
                             size_t nk, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],
                             size_t nSensitivity) {
  int us[MAX_SLOTS], ks[MAX_SLOTS], n_u, n_k;
  unsigned u[MAX_SLOTS], k[MAX_SLOTS];
  int j;
  INSTANCE(call);
  if ((n_u = expand(c, call, unknowns, nu, "Float64", 0, us)) < 0 ||
      (n_k = expand(c, call, knowns, nk, "Float64", 0, ks)) < 0 ||
      count_problem(c, call, "seed", nSeed, reverse ? n_u : n_k) ||
      count_problem(c, call, "sensitivity", nSensitivity, reverse ? n_k : n_u))
    return fmi3Error;
  for (j = 0; j < n_u; ++j) u[j] = (unsigned) us[j];
  for (j = 0; j < n_k; ++j) k[j] = (unsigned) ks[j];
  return (fmi3Status) f(c, call, u, (size_t) n_u, k, (size_t) n_k, seed, sensitivity);
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
  return derivative(instance, "fmi3GetDirectionalDerivative", heli_directional, 0, unknowns, nUnknowns, knowns,
                    nKnowns, seed, nSeed, sensitivity, nSensitivity);
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
  return derivative(instance, "fmi3GetAdjointDerivative", heli_adjoint, 1, unknowns, nUnknowns, knowns, nKnowns, seed,
                    nSeed, sensitivity, nSensitivity);
}

/* -- co-simulation -------------------------------------------------------------------------------------- */

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean* eventHandlingNeeded,
                      fmi3Boolean* terminateSimulation, fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime) {
  int st;
  INSTANCE("fmi3DoStep");
  (void) noSetFMUStatePriorToCurrentPoint;
  st = heli_do_step(c, "fmi3DoStep", currentCommunicationPoint, communicationStepSize);
  if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
  if (terminateSimulation) *terminateSimulation = fmi3False;
  if (earlyReturn) *earlyReturn = fmi3False;
  if (lastSuccessfulTime) *lastSuccessfulTime = heli_time(c);
  return (fmi3Status) st;
}

/* -- model exchange: states in the FMI 3.0 order -------------------------------------------------------- */

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation) {
  int terminate = 0, st;
  INSTANCE("fmi3CompletedIntegratorStep");
  (void) noSetFMUStatePriorToCurrentPoint;
  st = heli_completed_integrator_step(c, "fmi3CompletedIntegratorStep", &terminate);
  if (enterEventMode) *enterEventMode = fmi3False;
  if (terminateSimulation) *terminateSimulation = terminate ? fmi3True : fmi3False;
  return (fmi3Status) st;
}

HELI_FORWARD(fmi3Status, fmi3SetTime, heli_set_time, (fmi3Instance instance, fmi3Float64 time),
             time)

typedef int (*states_fn)(heli_instance*, const char*, double[], size_t);

/* A core call on the continuous states in the FMI 2.0 order, with x[] in the FMI 3.0 order. */
static fmi3Status states_out(fmi3Instance instance, const char* call, states_fn f, fmi3Float64 x[], size_t n) {
  double buf[HELI_NX + 1];
  int k;
  INSTANCE(call);
  if (n != (size_t) M->n_states || !x) return (fmi3Status) f(c, call, x, n); /* the core reports it */
  if (f(c, call, buf, n)) return fmi3Error;
  for (k = 0; k < M->n_states; ++k) x[k] = buf[M->me_order3[k]];
  return fmi3OK;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t n) {
  double buf[HELI_NX + 1];
  int k;
  INSTANCE("fmi3SetContinuousStates");
  if (n != (size_t) M->n_states || !x) return (fmi3Status) heli_set_states(c, "fmi3SetContinuousStates", x, n);
  for (k = 0; k < M->n_states; ++k) buf[M->me_order3[k]] = x[k];
  return (fmi3Status) heli_set_states(c, "fmi3SetContinuousStates", buf, n);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t n) {
  return states_out(instance, "fmi3GetContinuousStates", heli_get_states, x, n);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 dx[], size_t n) {
  return states_out(instance, "fmi3GetContinuousStateDerivatives", heli_get_derivatives, dx, n);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t n) {
  return states_out(instance, "fmi3GetNominalsOfContinuousStates", heli_get_nominals, x, n);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* n) {
  INSTANCE("fmi3GetNumberOfContinuousStates");
  if (!n) return (fmi3Status) heli_refuse(c, "fmi3GetNumberOfContinuousStates", "the pointer is NULL");
  *n = (size_t) M->n_states;
  return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* n) {
  INSTANCE("fmi3GetNumberOfEventIndicators");
  if (!n) return (fmi3Status) heli_refuse(c, "fmi3GetNumberOfEventIndicators", "the pointer is NULL");
  *n = 0;
  return fmi3OK;
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t n) {
  INSTANCE("fmi3GetEventIndicators");
  (void) indicators;
  return (fmi3Status) (n ? heli_refuse(c, "fmi3GetEventIndicators", "this FMU has no event indicators") : fmi3OK);
}

/* -- FMU state ---------------------------------------------------------------------------------------- */

HELI_FORWARD(fmi3Status, fmi3GetFMUState, heli_get_state, (fmi3Instance instance, fmi3FMUState* state),
             state)

HELI_FORWARD(fmi3Status, fmi3SetFMUState, heli_set_state, (fmi3Instance instance, fmi3FMUState state),
             state)

HELI_FORWARD(fmi3Status, fmi3FreeFMUState, heli_free_state, (fmi3Instance instance, fmi3FMUState* state),
             state)

HELI_FORWARD(fmi3Status, fmi3SerializedFMUStateSize, heli_serialized_size, (fmi3Instance instance, fmi3FMUState state, size_t* size),
             state, size)

HELI_FORWARD(fmi3Status, fmi3SerializeFMUState, heli_serialize, (fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size),
             state, bytes, size)

HELI_FORWARD(fmi3Status, fmi3DeserializeFMUState, heli_deserialize, (fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState* state),
             bytes, size, state)
