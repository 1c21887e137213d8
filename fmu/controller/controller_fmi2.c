/* FMI 2.0 co-simulation interface of the hover-hold controller (see fmu/controller): a
   sampled linear-quadratic regulator around the hover trim,

       out = clamp(TRIM_OUT - gain_scale * GAINS e, LOW, HIGH),
       e = in - TRIM_IN, north/east turned into the trim heading's axes, heading wrapped to +-pi,

   computed by fmi2DoStep (no direct feedthrough) from the inputs averaged over the last quarter
   revolution (WINDOW s, each sample weighted by its step; at most HH_SAMPLES samples): the
   average removes the rotor's harmonics (the 4/rev vibration of the fuselage), which the
   design's quasi-static rotor does not have and which high-gain feedback would amplify; the
   window before the start counts as at the trim. Before the first step the outputs are
   TRIM_OUT. The heading is taken as the angle nearest the trim heading (one remainder(), so any
   finite heading costs the same); a heading beyond +-HEADING_LIMIT rad, which a double no longer
   resolves to 2e-6 rad, and outputs that overflow are refused (fmi2Discard) instead of being
   sent on. With stopTimeDefined a step past stopTime is fmi2Error. The design's numbers are in
   hover_hold_data.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "hover_hold_data.h"

#define PI 3.14159265358979323846
#define VR_SCALE (HH_NIN + HH_NOUT)
#define NV (VR_SCALE + 1)
#define HH_SAMPLES 2048
#define YAW 5                      /* the heading's index among the inputs (fuselage.yaw) */
#define HEADING_LIMIT 8589934592.0 /* 2^33 rad: beyond it a double's spacing exceeds 2e-6 rad */
#define TIME_TOLERANCE 1e-9        /* relative: a step ending this close past stopTime is no step past it */

enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED };

typedef struct {
  unsigned magic;
  char* name;
  fmi2CallbackLogger logger;
  fmi2ComponentEnvironment env;
  int logging_on, phase, stop_defined;
  double t, stop, scale;
  double in[HH_NIN], out[HH_NOUT];
  int head, count;                     /* ring of the latest samples: newest at head */
  double sample_dt[HH_SAMPLES], samples[HH_SAMPLES][HH_NIN];
} controller;

#define MAGIC 0x484f4c44u

static const char* category(fmi2Status st) {
  static const char* const names[] = {"logAll", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                      "logStatusFatal"};
  return (unsigned) st < 5 ? names[st] : "logAll";
}

static void say(controller* c, fmi2Status st, const char* fmt, ...) {
  char text[512];
  va_list ap;
  if (st == fmi2OK && !c->logging_on) return;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  if (c->logger) c->logger(c->env, c->name, st, category(st), "%s", text);
  if (st > fmi2OK) fprintf(stderr, "HoverHold (%s): %s\n", c->name, text);
}

static controller* live(fmi2Component component, const char* call) {
  controller* c = (controller*) component;
  if (c && c->magic == MAGIC) return c;
  fprintf(stderr, "HoverHold: %s called without a valid instance\n", call);
  return NULL;
}

static fmi2Status wrong_phase(controller* c, const char* call) {
  static const char* const names[] = {"instantiated", "initialization", "step", "terminated"};
  say(c, fmi2Error, "%s: not allowed in %s mode", call, names[c->phase]);
  return fmi2Error;
}

static fmi2Status null_pointer(controller* c, const char* call) {
  say(c, fmi2Error, "%s: the pointer for the value is NULL", call);
  return fmi2Error;
}

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }

static void reset(controller* c) {
  c->phase = INSTANTIATED;
  c->t = 0.0;
  c->stop_defined = 0;
  c->scale = 1.0;
  memcpy(c->in, TRIM_IN, sizeof c->in);
  memcpy(c->out, TRIM_OUT, sizeof c->out);
  c->head = 0; /* one revolution at the trim before the start: the first averages ramp in */
  c->count = 1;
  c->sample_dt[0] = WINDOW;
  memcpy(c->samples[0], TRIM_IN, sizeof c->samples[0]);
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions* cb, fmi2Boolean visible, fmi2Boolean logging_on) {
  controller* c;
  (void) resources, (void) visible;
  if (!name || !*name || type != fmi2CoSimulation || !guid || strcmp(guid, HH_GUID)) {
    if (cb && cb->logger)
      cb->logger(cb->componentEnvironment, name ? name : "", fmi2Error, "logStatusError",
                 "fmi2Instantiate: needs a non-empty instance name, fmi2CoSimulation and GUID %s", HH_GUID);
    return NULL;
  }
  c = (controller*) calloc(1, sizeof *c);
  if (!c || !(c->name = (char*) malloc(strlen(name) + 1))) {
    free(c);
    return NULL;
  }
  strcpy(c->name, name);
  c->magic = MAGIC;
  c->logger = cb ? cb->logger : NULL;
  c->env = cb ? cb->componentEnvironment : NULL;
  c->logging_on = logging_on != fmi2False;
  reset(c);
  return c;
}

void fmi2FreeInstance(fmi2Component component) {
  controller* c = (controller*) component;
  if (!c || c->magic != MAGIC) return;
  c->magic = 0;
  free(c->name);
  free(c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component component, fmi2Boolean on, size_t n, const fmi2String categories[]) {
  static const char* const known[] = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                                      "logAll"};
  controller* c = live(component, "fmi2SetDebugLogging");
  size_t k, j;
  if (!c) return fmi2Error;
  for (k = 0; k < n; ++k) {
    for (j = 0; categories && categories[k] && j < 5 && strcmp(categories[k], known[j]); ++j) {}
    if (!categories || !categories[k] || j == 5) {
      say(c, fmi2Error, "fmi2SetDebugLogging: unknown log category '%s'",
          categories && categories[k] ? categories[k] : "(NULL)");
      return fmi2Error;
    }
  }
  c->logging_on = on != fmi2False;
  return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component component, fmi2Boolean tol_defined, fmi2Real tol, fmi2Real start,
                               fmi2Boolean stop_defined, fmi2Real stop) {
  controller* c = live(component, "fmi2SetupExperiment");
  (void) tol_defined, (void) tol;
  if (!c) return fmi2Error;
  if (c->phase != INSTANTIATED) return wrong_phase(c, "fmi2SetupExperiment");
  if (!isfinite(start) || (stop_defined && !(stop >= start))) {
    say(c, fmi2Error, "fmi2SetupExperiment: startTime = %g s must be finite and stopTime = %g s (stopTimeDefined = %s) "
        "not before it", start, stop, stop_defined ? "true" : "false");
    return fmi2Error;
  }
  c->t = start;
  c->stop_defined = stop_defined != fmi2False;
  c->stop = stop;
  return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component component) {
  controller* c = live(component, "fmi2EnterInitializationMode");
  if (!c) return fmi2Error;
  if (c->phase != INSTANTIATED) return wrong_phase(c, "fmi2EnterInitializationMode");
  c->phase = INITIALIZATION;
  return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component component) {
  controller* c = live(component, "fmi2ExitInitializationMode");
  if (!c) return fmi2Error;
  if (c->phase != INITIALIZATION) return wrong_phase(c, "fmi2ExitInitializationMode");
  c->phase = STEPPING;
  return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component component) {
  controller* c = live(component, "fmi2Terminate");
  if (!c) return fmi2Error;
  if (c->phase != STEPPING && c->phase != INITIALIZATION) return wrong_phase(c, "fmi2Terminate");
  c->phase = TERMINATED;
  return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component component) {
  controller* c = live(component, "fmi2Reset");
  if (!c) return fmi2Error;
  reset(c);
  return fmi2OK;
}

static int bad_vr(controller* c, const char* call, fmi2ValueReference vr) {
  if (vr < NV) return 0;
  say(c, fmi2Error, "%s: unknown value reference %u (0 to %d)", call, vr, NV - 1);
  return 1;
}

fmi2Status fmi2GetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
  controller* c = live(component, "fmi2GetReal");
  size_t k;
  if (!c || (n && (!vr || !value))) return fmi2Error;
  if (c->phase == INSTANTIATED) return wrong_phase(c, "fmi2GetReal");
  for (k = 0; k < n; ++k) {
    if (bad_vr(c, "fmi2GetReal", vr[k])) return fmi2Error;
    value[k] = vr[k] < HH_NIN ? c->in[vr[k]] : vr[k] < VR_SCALE ? c->out[vr[k] - HH_NIN] : c->scale;
  }
  return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
  controller* c = live(component, "fmi2SetReal");
  size_t k;
  if (!c || (n && (!vr || !value))) return fmi2Error;
  if (c->phase == TERMINATED) return wrong_phase(c, "fmi2SetReal");
  for (k = 0; k < n; ++k) {
    if (bad_vr(c, "fmi2SetReal", vr[k])) return fmi2Error;
    if (vr[k] >= HH_NIN && vr[k] < VR_SCALE) {
      say(c, fmi2Error, "fmi2SetReal: output '%s' cannot be set", NAMES[vr[k]]);
      return fmi2Error;
    }
    if (vr[k] == VR_SCALE && (c->phase == STEPPING || !(value[k] >= 0.0 && value[k] <= 1.0))) {
      say(c, fmi2Error, "fmi2SetReal: gain_scale = %g must be in [0, 1] and set before initialisation ends",
          value[k]);
      return fmi2Error;
    }
    if (vr[k] == VR_SCALE) c->scale = value[k];
    else c->in[vr[k]] = value[k];
  }
  return fmi2OK;
}

/* The heading psi (rad) as the angle nearest the trim heading: unchanged within pi of it, else
   wrapped by one remainder() (any finite psi in the same time). */
static double near_trim(double psi) {
  double d = psi - TRIM_IN[YAW];
  return fabs(d) <= PI ? psi : TRIM_IN[YAW] + remainder(d, 2 * PI);
}

/* Record the inputs held over a step of dt s; the average of the latest samples spanning one
   revolution (the oldest one weighted by the part of it inside) into mean. */
static void average(controller* c, double dt, double* mean) {
  double span = 0.0, w;
  int n, k, j;
  c->head = (c->head + 1) % HH_SAMPLES;
  c->count = c->count < HH_SAMPLES ? c->count + 1 : HH_SAMPLES;
  c->sample_dt[c->head] = dt;
  memcpy(c->samples[c->head], c->in, sizeof c->in);
  c->samples[c->head][YAW] = near_trim(c->in[YAW]);
  memset(mean, 0, sizeof(double) * HH_NIN);
  for (n = 0; n < c->count && span < WINDOW; ++n) {
    j = (c->head - n + HH_SAMPLES) % HH_SAMPLES;
    w = c->sample_dt[j] < WINDOW - span ? c->sample_dt[j] : WINDOW - span;
    span += w;
    for (k = 0; k < HH_NIN; ++k) mean[k] += w * c->samples[j][k];
  }
  for (k = 0; k < HH_NIN; ++k) mean[k] /= span;
}

/* The regulator: outputs (into out) from the inputs averaged over the last revolution; -1 when all
   are finite, else the index of the first that is not. */
static int regulate(controller* c, double dt, double* out) {
  double e[HH_NIN], north, east;
  int i, k;
  average(c, dt, e);
  for (k = 0; k < HH_NIN; ++k) e[k] -= TRIM_IN[k];
  north = e[0], east = e[1];
  e[0] = COS_HEADING * north + SIN_HEADING * east;
  e[1] = -SIN_HEADING * north + COS_HEADING * east;
  if (fabs(e[YAW]) > PI) e[YAW] = remainder(e[YAW], 2 * PI); /* the samples are near the trim already */
  for (i = 0; i < HH_NOUT; ++i) {
    double u = 0.0;
    for (k = 0; k < HH_NIN; ++k) u += GAINS[i][k] * e[k];
    u = TRIM_OUT[i] - c->scale * u;
    if (!isfinite(u)) return i;
    out[i] = u < LOW[i] ? LOW[i] : u > HIGH[i] ? HIGH[i] : u;
  }
  return -1;
}

/* The input farthest from its trim (for a message). */
static int largest_input(const controller* c) {
  int k, worst = 0;
  for (k = 1; k < HH_NIN; ++k)
    if (fabs(c->in[k] - TRIM_IN[k]) > fabs(c->in[worst] - TRIM_IN[worst])) worst = k;
  return worst;
}

/* One sample of the regulator; on outputs that overflow, everything stays as it was (fmi2Discard). */
static fmi2Status sample(controller* c, double dt) {
  int head = c->head, count = c->count, bad, worst;
  double out[HH_NOUT], dt_old = c->sample_dt[(c->head + 1) % HH_SAMPLES], old[HH_NIN];
  memcpy(old, c->samples[(c->head + 1) % HH_SAMPLES], sizeof old);
  if ((bad = regulate(c, dt, out)) < 0) {
    memcpy(c->out, out, sizeof out);
    return fmi2OK;
  }
  memcpy(c->samples[c->head], old, sizeof old); /* undo the sample */
  c->sample_dt[c->head] = dt_old;
  c->head = head, c->count = count;
  worst = largest_input(c);
  say(c, fmi2Discard, "fmi2DoStep: output '%s' would not be finite: the inputs overflow the regulator (the farthest "
      "from the trim: '%s' = %g); the step was discarded", NAMES[HH_NIN + bad], NAMES[worst], c->in[worst]);
  return fmi2Discard;
}

fmi2Status fmi2DoStep(fmi2Component component, fmi2Real t, fmi2Real dt, fmi2Boolean no_set_prior) {
  controller* c = live(component, "fmi2DoStep");
  int k;
  fmi2Status st;
  (void) no_set_prior;
  if (!c) return fmi2Error;
  if (c->phase != STEPPING) return wrong_phase(c, "fmi2DoStep");
  if (!(dt > 0.0) || !isfinite(dt) || !isfinite(t)) {
    say(c, fmi2Error, "fmi2DoStep: currentCommunicationPoint %g s and communicationStepSize %g s must be finite, "
        "the step positive", t, dt);
    return fmi2Error;
  }
  if (c->stop_defined && t + dt > c->stop + TIME_TOLERANCE * (fabs(c->stop) > 1.0 ? fabs(c->stop) : 1.0)) {
    say(c, fmi2Error, "fmi2DoStep: the step from %.17g s to %.17g s ends past stopTime = %.17g s (stopTimeDefined = "
        "true); the step was not taken", t, t + dt, c->stop);
    return fmi2Error;
  }
  for (k = 0; k < HH_NIN; ++k) {
    if (!isfinite(c->in[k])) {
      say(c, fmi2Discard, "fmi2DoStep: input '%s' is not finite", NAMES[k]);
      return fmi2Discard;
    }
  }
  if (fabs(c->in[YAW]) > HEADING_LIMIT) {
    say(c, fmi2Discard, "fmi2DoStep: input '%s' = %g rad is beyond +-%g rad, where a double no longer resolves a "
        "heading (its spacing is %g rad): a wrong connection? The step was discarded", NAMES[YAW], c->in[YAW],
        HEADING_LIMIT, nextafter(fabs(c->in[YAW]), HUGE_VAL) - fabs(c->in[YAW]));
    return fmi2Discard;
  }
  if ((st = sample(c, dt)) != fmi2OK) return st;
  c->t = t + dt;
  return fmi2OK;
}

/* -- what this FMU does not have ---------------------------------------------------------- */

static fmi2Status unsupported(fmi2Component component, const char* call) {
  controller* c = live(component, call);
  if (c) say(c, fmi2Error, "%s: not supported by this FMU", call);
  return fmi2Error;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2GetInteger (no Integer variables)") : fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2SetInteger (no Integer variables)") : fmi2OK;
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2GetBoolean (no Boolean variables)") : fmi2OK;
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2SetBoolean (no Boolean variables)") : fmi2OK;
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2GetString (no String variables)") : fmi2OK;
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) {
  (void) vr, (void) v;
  return n ? unsupported(c, "fmi2SetString (no String variables)") : fmi2OK;
}
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* s) {
  (void) s;
  return unsupported(c, "fmi2GetFMUstate");
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
  (void) s;
  return unsupported(c, "fmi2SetFMUstate");
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* s) {
  (void) s;
  return unsupported(c, "fmi2FreeFMUstate");
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t* n) {
  (void) s, (void) n;
  return unsupported(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
  (void) s, (void) b, (void) n;
  return unsupported(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate* s) {
  (void) s, (void) b, (void) n;
  return unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference k[], size_t nk, const fmi2Real dk[], fmi2Real du[]) {
  (void) u, (void) nu, (void) k, (void) nk, (void) dk, (void) du;
  return unsupported(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[]) {
  (void) vr, (void) n, (void) order, (void) v;
  return unsupported(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[]) {
  (void) vr, (void) n, (void) order, (void) v;
  return unsupported(c, "fmi2GetRealOutputDerivatives");
}
fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

static fmi2Status no_status(fmi2Component component, const char* call, const void* v) {
  controller* c = live(component, call);
  if (!c) return fmi2Error;
  if (!v) return null_pointer(c, call);
  say(c, fmi2Discard, "%s: not available (fmi2DoStep never returns fmi2Pending)", call);
  return fmi2Discard;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status* v) {
  (void) s, (void) v;
  return no_status(c, "fmi2GetStatus", v);
}
fmi2Status fmi2GetRealStatus(fmi2Component component, const fmi2StatusKind s, fmi2Real* v) {
  controller* c = live(component, "fmi2GetRealStatus");
  if (!c) return fmi2Error;
  if (!v) return null_pointer(c, "fmi2GetRealStatus");
  if (s != fmi2LastSuccessfulTime) return no_status(component, "fmi2GetRealStatus", v);
  *v = c->t;
  return fmi2OK;
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer* v) {
  (void) s, (void) v;
  return no_status(c, "fmi2GetIntegerStatus", v);
}
fmi2Status fmi2GetBooleanStatus(fmi2Component component, const fmi2StatusKind s, fmi2Boolean* v) {
  controller* c = live(component, "fmi2GetBooleanStatus");
  if (!c) return fmi2Error;
  if (!v) return null_pointer(c, "fmi2GetBooleanStatus");
  if (s != fmi2Terminated) return no_status(component, "fmi2GetBooleanStatus", v);
  *v = fmi2False;
  return fmi2OK;
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String* v) {
  (void) s, (void) v;
  return no_status(c, "fmi2GetStringStatus", v);
}
