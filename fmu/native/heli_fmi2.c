/* FMI 2.0 co-simulation interface of the heli rotor model, over the tables and compiled
   model groups of heli_data.c (see heli_model.h). Behaviour follows the pythonfmu slave
   (fmu/heli_bo105_slave.py):

   - The scene (a String parameter) selects the model group, the initial state and the
     defaults. An input or parameter that the master set is used whatever its value (also
     when it equals the XML start, the primary scene's default); one not set takes the scene's
     default. exitInitializationMode warns when a value set equal to its XML start differs
     from the default of the scene in use.
   - Inputs are held over a step; doStep splits dt into n = ceil(dt / max_step (1 - 1e-6))
     equal sub-steps of the core's fixed-step driver (RK4 or RK8, Kahan-compensated).
   - A refused value (NaN, out of range, a fixed parameter changed after initialisation) is
     stored and logged; the next doStep returns fmi2Discard until it is corrected. A step
     that diverges (non-finite state, hinge angle beyond +-pi/2, non-finite energy) is undone
     and returns fmi2Discard.
   - Outputs that are states (hinge angles and rates, fuselage states) are read from the
     state; the others (fmu_outputs: azimuths, thrusts, Euler angles, energy) are evaluated
     once per step, when the first of them is read.
   - Misuse (unknown value reference, wrong type, setting an output, calls out of order, a
     damaged serialized state) returns fmi2Error with a message; the instance stays usable.

   Messages with a status above fmi2OK always go to the logger and to stderr; fmi2OK
   messages only when logging is on. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "heli_model.h"

#define M (&heli_model_data)
#define INSTANCE_MAGIC 0x48454c49u
#define SAVED_MAGIC 0x53415645u
#define BLOB_VERSION 1u
#define TEXT_LEN 128
#define MSG_LEN 512
#define TIME_TOLERANCE 1e-9 /* relative mismatch allowed between the master's time and ours */
/* A communication step at most this much (relative) longer than n max_step is n sub-steps: a
   master that counts time in whole nanoseconds rounds the default step (max_step) up by up to
   0.5 ns, about 4e-7 of it; a sub-step 1e-6 longer than max_step changes nothing in stability. */
#define SUBSTEP_TOLERANCE 1e-6

enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED, PHASES };
static const char* const PHASE_NAMES[PHASES] = {"instantiated", "initialization", "step", "terminated"};

/* Everything an FMU state holds: settings, refusals, the simulation state. */
typedef struct {
  int phase;
  double start_time, t;
  double real[HELI_NV];              /* Real value last set */
  unsigned char set[HELI_NV];        /* set by the master (whatever the value) since instantiation or reset */
  char text[HELI_NV][TEXT_LEN];      /* String value last set */
  char error[HELI_NV][MSG_LEN];      /* why the value set is refused ("" when accepted) */
  double frozen[HELI_NV];            /* fixed parameters in use since initialisation */
  int frozen_choice[HELI_NV];
  int loaded, scene, method;         /* x, comp belong to this scene, integrated by method */
  double x[HELI_NX], comp[HELI_NX];
  int cache_valid;
  double cache[HELI_NCOMPUTED];      /* computed variables at (x, t) */
} snapshot;

typedef struct {
  unsigned magic;
  snapshot s;
} saved_state;

typedef struct {
  unsigned magic;
  snapshot s;
  char* name;
  fmi2CallbackLogger logger;
  fmi2ComponentEnvironment env;
  int logging_on;
  const double** arg;                /* work buffers of the generated functions */
  double** res;
  heli_int* iw;
  double* w;
  double p[HELI_NP + 1];
  double trial[HELI_NX], trial_comp[HELI_NX], dx[HELI_NX], energy[HELI_NENERGY];
  char message[4 * MSG_LEN * 4];
  char escaped[8 * MSG_LEN * 4];
} instance;

typedef struct {
  char magic[8];
  unsigned version, size;
  char guid[64];
  int scene, group, nx, pad;
  unsigned long long checksum;
} blob_header;

static const char BLOB_MAGIC[8] = "HELIFMU";

/* -- messages ------------------------------------------------------------------------------ */

static const char* status_name(fmi2Status st) {
  static const char* const names[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
  return (unsigned) st < 6 ? names[st] : "unknown";
}

static const char* category(fmi2Status st) {
  static const char* const names[] = {"logAll", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                      "logStatusFatal", "logAll"};
  return (unsigned) st < 6 ? names[st] : "logAll";
}

/* The logger takes a printf format: double every '%' so that the text arrives unchanged. */
static const char* escape_percent(const char* in, char* out, size_t size) {
  size_t k = 0;
  for (; *in && k + 2 < size; ++in) {
    if (*in == '%') out[k++] = '%';
    out[k++] = *in;
  }
  out[k] = 0;
  return out;
}

static void emit(fmi2CallbackLogger logger, fmi2ComponentEnvironment env, const char* name, fmi2Status st,
                 const char* text, char* scratch, size_t size) {
  if (logger) logger(env, name ? name : "", st, category(st), escape_percent(text, scratch, size));
  if (st > fmi2OK) {
    fprintf(stderr, "%s (%s) %s: %s\n", M->identifier, name ? name : "no instance", status_name(st), text);
    fflush(stderr);
  }
}

static void report(instance* c, fmi2Status st, const char* fmt, ...) {
  va_list ap;
  if (st == fmi2OK && !c->logging_on) return;
  va_start(ap, fmt);
  vsnprintf(c->message, sizeof c->message, fmt, ap);
  va_end(ap);
  emit(c->logger, c->env, c->name, st, c->message, c->escaped, sizeof c->escaped);
}

/* A report before an instance exists (or for a call without one). */
static void report_without(const fmi2CallbackFunctions* cb, const char* name, const char* fmt, ...) {
  char text[MSG_LEN], scratch[2 * MSG_LEN];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  emit(cb ? cb->logger : NULL, cb ? cb->componentEnvironment : NULL, name, fmi2Error, text, scratch, sizeof scratch);
}

/* Python's repr of a float: the shortest digits that read back exactly, positional for
   decimal exponents -4 to 15, else scientific. */
static const char* repr(double v, char* buf) {
  int digits, exponent;
  if (isnan(v)) return strcpy(buf, "nan");
  if (isinf(v)) return strcpy(buf, v > 0 ? "inf" : "-inf");
  for (digits = 1; digits < 17; ++digits) {
    snprintf(buf, 32, "%.*e", digits - 1, v);
    if (strtod(buf, NULL) == v) break;
  }
  snprintf(buf, 32, "%.*e", digits - 1, v);
  exponent = atoi(strchr(buf, 'e') + 1);
  if (exponent < -4 || exponent >= 16) return buf;
  snprintf(buf, 32, "%.*f", digits - 1 - exponent > 0 ? digits - 1 - exponent : 0, v);
  if (!strchr(buf, '.')) strcat(buf, ".0");
  return buf;
}

static void copy_text(char* dst, const char* src, size_t size) {
  strncpy(dst, src, size - 1);
  dst[size - 1] = 0;
}

/* -- variables and the values in use -------------------------------------------------------- */

static const heli_variable* var(int vr) { return &M->variables[vr]; }

static const char* causality_name(const heli_variable* v) {
  static const char* const names[] = {"input", "parameter", "output", "local"};
  return names[v->causality];
}

static int choice_of(int vr, const char* text) {
  int k;
  for (k = 0; k < var(vr)->n_allowed; ++k)
    if (!strcmp(var(vr)->allowed[k], text)) return k;
  return -1;
}

static int accepted(const instance* c, int vr) { return c->s.set[vr] && !c->s.error[vr][0]; }

/* The String value in use, as an index into the allowed values. */
static int string_choice(const instance* c, int vr) {
  int k = accepted(c, vr) ? choice_of(vr, c->s.text[vr]) : -1;
  return k >= 0 ? k : choice_of(vr, var(vr)->start_text);
}

static const char* string_value(const instance* c, int vr) {
  return c->s.set[vr] ? c->s.text[vr] : var(vr)->start_text;
}

static int scene_in_use(const instance* c) {
  int k = M->vr_scene >= 0 ? string_choice(c, M->vr_scene) : -1;
  return k >= 0 ? k : M->primary;
}

static int method_in_use(const instance* c) {
  int k = M->vr_integrator >= 0 ? string_choice(c, M->vr_integrator) : -1;
  return k >= 0 && !strcmp(var(M->vr_integrator)->allowed[k], "rk8") ? HELI_RK8 : HELI_RK4;
}

/* 1 when initial_state = "periodic" is in use (the scene may still lack a periodic start). */
static int periodic_in_use(const instance* c) {
  int k = M->vr_initial_state >= 0 ? string_choice(c, M->vr_initial_state) : -1;
  return k >= 0 && !strcmp(var(M->vr_initial_state)->allowed[k], "periodic");
}

static double use_real(const instance* c, int vr);

static double default_real(const instance* c, int vr) {
  const heli_scene* sc = &M->scenes[scene_in_use(c)];
  int periodic = sc->periodic_x0 && periodic_in_use(c);
  if (vr == M->vr_max_step) {
    double omega = M->vr_omega >= 0 ? use_real(c, M->vr_omega) : sc->omega;
    return 2 * 3.141592653589793 / fabs(omega) / sc->steps_per_rev;
  }
  if (vr == M->vr_forward_speed) return sc->free_body ? (periodic ? sc->periodic_fs_default : sc->fs_default) : 0.0;
  return periodic ? sc->periodic_defaults[vr] : sc->defaults[vr];
}

/* The value in use: the one set unless refused, else the scene's default. */
static double use_real(const instance* c, int vr) { return accepted(c, vr) ? c->s.real[vr] : default_real(c, vr); }

/* What a getter returns: the value last set, else the scene's default. */
static double value_real(const instance* c, int vr) { return c->s.set[vr] ? c->s.real[vr] : default_real(c, vr); }

/* -- checking values ------------------------------------------------------------------------ */

/* 0 if value is acceptable for vr in the scene in use, else 1 with the reason in msg. */
static int check_real(const instance* c, int vr, double value, char* msg) {
  const heli_variable* v = var(vr);
  const heli_scene* sc = &M->scenes[scene_in_use(c)];
  char a[32], b[32], d[32];
  if (!isfinite(value)) {
    snprintf(msg, MSG_LEN, "%s '%s' = %s %s is not a finite number", causality_name(v), v->name, repr(value, a), v->unit);
  } else if (!(sc->low[vr] <= value && value <= sc->high[vr])) {
    snprintf(msg, MSG_LEN, "%s '%s' = %s %s is outside its range [%s, %s]", causality_name(v), v->name,
             repr(value, a), v->unit, repr(sc->low[vr], b), repr(sc->high[vr], d));
  } else if (vr == M->vr_max_step && value <= 0) {
    snprintf(msg, MSG_LEN, "%s '%s' = %s s must be positive", causality_name(v), v->name, repr(value, a));
  } else {
    return 0;
  }
  return 1;
}

static int check_string(int vr, const char* text, char* msg) {
  const heli_variable* v = var(vr);
  size_t k, used;
  if (choice_of(vr, text) >= 0) return 0;
  used = (size_t) snprintf(msg, MSG_LEN, "parameter '%s' = '%s' is not one of: ", v->name, text);
  for (k = 0; k < (size_t) v->n_allowed && used < MSG_LEN; ++k)
    used += (size_t) snprintf(msg + used, MSG_LEN - used, "%s%s", k ? ", " : "", v->allowed[k]);
  return 1;
}

static int is_fixed_parameter(int vr) {
  return var(vr)->causality == HELI_PARAMETER && var(vr)->variability == HELI_FIXED;
}

/* After initialisation a fixed parameter must keep its value: else refuse to step. */
static int check_frozen(instance* c, int vr) {
  char a[32], b[32], msg[MSG_LEN];
  const heli_variable* v = var(vr);
  if (c->s.phase != STEPPING || !is_fixed_parameter(vr)) return 0;
  if (v->type == HELI_STRING) {
    int k = c->s.frozen_choice[vr];
    if (string_choice(c, vr) == k) return 0;
    snprintf(msg, MSG_LEN, "parameter '%s' is fixed: it cannot change after initialisation (set to '%s', "
             "in use '%s'); the FMU refuses to step until it is set back", v->name, c->s.text[vr],
             k >= 0 ? v->allowed[k] : "?");
  } else {
    if (use_real(c, vr) == c->s.frozen[vr]) return 0;
    snprintf(msg, MSG_LEN, "parameter '%s' is fixed: it cannot change after initialisation (set to %s, "
             "in use %s); the FMU refuses to step until it is set back", v->name, repr(c->s.real[vr], a),
             repr(c->s.frozen[vr], b));
  }
  memcpy(c->s.error[vr], msg, MSG_LEN);
  return 1;
}

/* -- the model -------------------------------------------------------------------------------- */

static const heli_group* group_of(const instance* c) { return &M->groups[M->scenes[c->s.scene].group]; }

static int eval_outputs(instance* c, const heli_group* g, const double* x, double t, const double* p, double* out) {
  double tt = t;
  c->arg[0] = x;
  c->arg[1] = &tt;
  c->arg[2] = p;
  c->res[0] = out;
  return g->outputs(c->arg, c->res, c->iw, c->w, 0);
}

static int eval_energy(instance* c, const heli_group* g, const double* x, double t, const double* p) {
  double tt = t;
  c->arg[0] = x;
  c->arg[1] = &tt;
  c->arg[2] = p;
  c->res[0] = c->energy;
  return g->energy(c->arg, c->res, c->iw, c->w, 0);
}

static int eval_incr(instance* c, const heli_group* g, int method, const double* x, double t, double h,
                     const double* p, double* out) {
  double tt = t, hh = h;
  c->arg[0] = x;
  c->arg[1] = &tt;
  c->arg[2] = &hh;
  c->arg[3] = p;
  c->res[0] = out;
  return g->incr[method](c->arg, c->res, c->iw, c->w, 0);
}

static void fill_params(const instance* c, int scene, double* p) {
  const heli_scene* sc = &M->scenes[scene];
  int i;
  for (i = 0; i < sc->n_params; ++i) p[i] = use_real(c, sc->param_vr[i]);
}

/* Initial state of a scene (its own, or its periodic trim with initial_state = "periodic"), with
   initial_forward_speed: body velocity R(q0)^T (V, 0, 0). */
static int initial_state(instance* c, int scene, double* x, char* msg) {
  const heli_scene* sc = &M->scenes[scene];
  int vr = M->vr_forward_speed, j, periodic = periodic_in_use(c);
  double speed;
  char a[32];
  const double *dir, *x0 = periodic && sc->periodic_x0 ? sc->periodic_x0 : sc->x0;
  memcpy(x, x0, sizeof(double) * (size_t) M->groups[sc->group].nx);
  if (periodic && !sc->periodic_x0) {
    snprintf(msg, MSG_LEN, "parameter 'initial_state' = 'periodic': the scene '%s' has no periodic start (it cannot "
             "be trimmed)", sc->name);
    return 1;
  }
  if (vr < 0 || !accepted(c, vr)) return 0;
  speed = c->s.real[vr];
  if (!sc->free_body) {
    if (speed == 0.0) return 0;
    snprintf(msg, MSG_LEN, "parameter 'initial_forward_speed' = %s m/s: the scene '%s' has no free fuselage",
             repr(speed, a), sc->name);
    return 1;
  }
  dir = periodic ? sc->periodic_fs_dir : sc->fs_dir;
  for (j = 0; j < 3; ++j) x[sc->fs_v[j]] = dir[j] * speed;
  return 0;
}

/* The computed variables at the current state (before initialisation: the scene's initial state). */
static fmi2Status ensure_cache(instance* c, const char* call) {
  char msg[MSG_LEN], a[32];
  int scene = c->s.loaded ? c->s.scene : scene_in_use(c);
  const double* x = c->s.x;
  if (c->s.cache_valid) return fmi2OK;
  if (!c->s.loaded) {
    initial_state(c, scene, c->trial, msg);
    x = c->trial;
  }
  fill_params(c, scene, c->p);
  if (eval_outputs(c, &M->groups[M->scenes[scene].group], x, c->s.t, c->p, c->s.cache)) {
    report(c, fmi2Error, "%s failed: the generated function fmu_outputs reported an error at t = %s s", call,
           repr(c->s.t, a));
    return fmi2Error;
  }
  c->s.cache_valid = 1;
  return fmi2OK;
}

/* -- instances ---------------------------------------------------------------------------------- */

static instance* checked(fmi2Component component, const char* call) {
  instance* c = (instance*) component;
  if (c && c->magic == INSTANCE_MAGIC) return c;
  report_without(NULL, NULL, "%s called without a valid instance (%s): call fmi2Instantiate first", call,
                 c ? "not an instance of this FMU" : "NULL");
  return NULL;
}

static void grow(heli_int* have, heli_work_fn f) {
  heli_int n[4];
  int k;
  f(&n[0], &n[1], &n[2], &n[3]);
  for (k = 0; k < 4; ++k)
    if (n[k] > have[k]) have[k] = n[k];
}

static int allocate_work(instance* c) {
  heli_int n[4] = {4, 1, 1, 1};
  int g, m;
  for (g = 0; g < M->n_groups; ++g) {
    grow(n, M->groups[g].outputs_work);
    grow(n, M->groups[g].energy_work);
    for (m = 0; m < HELI_METHODS; ++m) grow(n, M->groups[g].incr_work[m]);
  }
  c->arg = (const double**) calloc((size_t) n[0] + 1, sizeof(double*));
  c->res = (double**) calloc((size_t) n[1] + 1, sizeof(double*));
  c->iw = (heli_int*) calloc((size_t) n[2] + 1, sizeof(heli_int));
  c->w = (double*) calloc((size_t) n[3] + 1, sizeof(double));
  return c->arg && c->res && c->iw && c->w;
}

static void release(instance* c) {
  if (!c) return;
  c->magic = 0;
  free((void*) c->arg);
  free(c->res);
  free(c->iw);
  free(c->w);
  free(c->name);
  free(c);
}

static void clear_snapshot(snapshot* s) {
  memset(s, 0, sizeof *s);
  s->phase = INSTANTIATED;
}

static int instantiate_problem(fmi2String name, fmi2Type type, fmi2String guid, const fmi2CallbackFunctions* cb) {
  if (!name || !*name) report_without(cb, NULL, "fmi2Instantiate: instanceName is %s: give the instance a name",
                                      name ? "empty" : "NULL");
  else if (type != fmi2CoSimulation)
    report_without(cb, name, "fmi2Instantiate: fmuType %d is not supported: this FMU is for co-simulation "
                   "(fmi2CoSimulation) only", (int) type);
  else if (!guid || strcmp(guid, M->guid))
    report_without(cb, name, "fmi2Instantiate: GUID '%s' does not match this FMU's '%s'", guid ? guid : "(NULL)",
                   M->guid);
  else return 0;
  return 1;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
  instance* c;
  (void) fmuResourceLocation; /* everything is compiled in */
  (void) visible;
  if (instantiate_problem(instanceName, fmuType, fmuGUID, functions)) return NULL;
  if (!heli_libm_ready()) {
    report_without(functions, instanceName, "fmi2Instantiate: %s; rebuild the library from sources/ with "
                   "-DHELI_LIBM_LINKED and -lm", heli_libm_problem());
    return NULL;
  }
  c = (instance*) calloc(1, sizeof(instance));
  if (!c || !(c->name = (char*) malloc(strlen(instanceName) + 1)) || !allocate_work(c)) {
    release(c);
    report_without(functions, instanceName, "fmi2Instantiate: out of memory");
    return NULL;
  }
  strcpy(c->name, instanceName);
  c->magic = INSTANCE_MAGIC;
  c->logger = functions ? functions->logger : NULL;
  c->env = functions ? functions->componentEnvironment : NULL;
  c->logging_on = loggingOn != fmi2False;
  clear_snapshot(&c->s);
  report(c, fmi2OK, "fmi2Instantiate: %s, %d scenes, %d model groups", M->identifier, M->n_scenes, M->n_groups);
  return c;
}

void fmi2FreeInstance(fmi2Component component) {
  instance* c = (instance*) component;
  if (c && c->magic == INSTANCE_MAGIC) release(c);
}

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char* fmi2GetVersion(void) { return fmi2Version; }

static int known_category(fmi2String name) {
  static const char* const names[] = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                                      "logAll"};
  size_t k;
  for (k = 0; name && k < sizeof names / sizeof names[0]; ++k)
    if (!strcmp(name, names[k])) return 1;
  return 0;
}

fmi2Status fmi2SetDebugLogging(fmi2Component component, fmi2Boolean loggingOn, size_t n, const fmi2String categories[]) {
  instance* c = checked(component, "fmi2SetDebugLogging");
  size_t k;
  if (!c) return fmi2Error;
  for (k = 0; k < n; ++k) {
    if (!categories || !known_category(categories[k])) {
      report(c, fmi2Error, "fmi2SetDebugLogging: unknown log category '%s'", categories && categories[k] ?
             categories[k] : "(NULL)");
      return fmi2Error;
    }
  }
  c->logging_on = loggingOn != fmi2False;
  return fmi2OK;
}

/* -- life cycle ---------------------------------------------------------------------------------- */

static fmi2Status wrong_phase(instance* c, const char* call, const char* need) {
  report(c, fmi2Error, "%s called in %s mode: %s", call, PHASE_NAMES[c->s.phase], need);
  return fmi2Error;
}

fmi2Status fmi2SetupExperiment(fmi2Component component, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  instance* c = checked(component, "fmi2SetupExperiment");
  char a[32];
  (void) toleranceDefined, (void) tolerance, (void) stopTimeDefined, (void) stopTime;
  if (!c) return fmi2Error;
  if (c->s.phase != INSTANTIATED) return wrong_phase(c, "fmi2SetupExperiment", "it must come right after fmi2Instantiate");
  if (!isfinite(startTime)) {
    report(c, fmi2Error, "fmi2SetupExperiment: startTime = %s s is not finite", repr(startTime, a));
    return fmi2Error;
  }
  c->s.start_time = c->s.t = startTime;
  c->s.cache_valid = 0;
  return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component component) {
  instance* c = checked(component, "fmi2EnterInitializationMode");
  if (!c) return fmi2Error;
  if (c->s.phase != INSTANTIATED)
    return wrong_phase(c, "fmi2EnterInitializationMode", "it must come after fmi2Instantiate (or fmi2Reset)");
  c->s.phase = INITIALIZATION;
  return fmi2OK;
}

/* Ranges depend on the scene: check every Real set again against the final one. */
static void recheck(instance* c) {
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!c->s.set[vr] || var(vr)->type != HELI_REAL) continue;
    c->s.error[vr][0] = 0;
    check_real(c, vr, c->s.real[vr], c->s.error[vr]);
  }
}

/* The messages of refused parameters, joined with "; "; 0 if there are none. */
static int refused_parameters(const instance* c, char* out, size_t size) {
  size_t used = 0;
  int vr, n = 0;
  out[0] = 0;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (var(vr)->causality != HELI_PARAMETER || !c->s.error[vr][0] || used >= size) continue;
    used += (size_t) snprintf(out + used, size - used, "%s%s", n++ ? "; " : "", c->s.error[vr]);
  }
  return n;
}

static void freeze(instance* c) {
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!is_fixed_parameter(vr)) continue;
    if (var(vr)->type == HELI_STRING) c->s.frozen_choice[vr] = string_choice(c, vr);
    else c->s.frozen[vr] = use_real(c, vr);
  }
}

/* Values set equal to their XML start (the primary scene's default) that differ from the default of
   the scene in use (a master may apply every XML start): used as set, each with a warning. */
static int start_values_warned(instance* c) {
  int vr, n = 0, scene = scene_in_use(c);
  char a[32], b[32];
  for (vr = 0; scene != M->primary && vr < M->n_variables; ++vr) {
    const heli_variable* v = var(vr);
    double d;
    if (!accepted(c, vr) || v->type != HELI_REAL || !(c->s.real[vr] == v->start)) continue;
    d = default_real(c, vr);
    if (isnan(d) || d == v->start) continue;
    report(c, fmi2Warning, "fmi2ExitInitializationMode: %s '%s' = %s %s was set: it equals its XML start (the "
           "default of scene '%s'), while scene '%s' defaults to %s %s; the value set is used", causality_name(v),
           v->name, repr(c->s.real[vr], a), v->unit, M->scenes[M->primary].name, M->scenes[scene].name,
           repr(d, b), v->unit);
    ++n;
  }
  return n;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component component) {
  instance* c = checked(component, "fmi2ExitInitializationMode");
  char why[4 * MSG_LEN];
  int scene;
  if (!c) return fmi2Error;
  if (c->s.phase != INITIALIZATION)
    return wrong_phase(c, "fmi2ExitInitializationMode", "call fmi2EnterInitializationMode first");
  recheck(c);
  scene = scene_in_use(c);
  if (refused_parameters(c, why, sizeof why) || initial_state(c, scene, c->trial, why)) {
    report(c, fmi2Error, "exitInitializationMode failed: %s", why);
    return fmi2Error;
  }
  memcpy(c->s.x, c->trial, sizeof c->s.x);
  memset(c->s.comp, 0, sizeof c->s.comp);
  c->s.loaded = 1;
  c->s.scene = scene;
  c->s.method = method_in_use(c);
  c->s.t = c->s.start_time;
  c->s.cache_valid = 0;
  freeze(c);
  c->s.phase = STEPPING;
  return start_values_warned(c) ? fmi2Warning : fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component component) {
  instance* c = checked(component, "fmi2Terminate");
  if (!c) return fmi2Error;
  if (c->s.phase != STEPPING && c->s.phase != INITIALIZATION)
    return wrong_phase(c, "fmi2Terminate", "there is no simulation to terminate");
  c->s.phase = TERMINATED;
  return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component component) {
  instance* c = checked(component, "fmi2Reset");
  if (!c) return fmi2Error;
  clear_snapshot(&c->s);
  return fmi2OK;
}

/* -- getting and setting values ------------------------------------------------------------------ */

static const char* type_name(int type) { return type == HELI_STRING ? "String" : "Real"; }

static int lookup(instance* c, const char* call, fmi2ValueReference vr, const char* type) {
  if (vr >= (fmi2ValueReference) M->n_variables) {
    report(c, fmi2Error, "%s: unknown value reference %u (this FMU has value references 0 to %d)", call, vr,
           M->n_variables - 1);
    return 0;
  }
  if (strcmp(type_name(var((int) vr)->type), type)) {
    report(c, fmi2Error, "%s: value reference %u is the %s variable '%s', not %s %s", call, vr,
           type_name(var((int) vr)->type), var((int) vr)->name, strchr("AEIOU", type[0]) ? "an" : "a", type);
    return 0;
  }
  return 1;
}

static int null_arrays(instance* c, const char* call, size_t n, const void* vr, const void* values) {
  if (n == 0 || (vr && values)) return 0;
  report(c, fmi2Error, "%s: %s array is NULL for %u values", call, vr ? "the value" : "the value reference",
         (unsigned) n);
  return 1;
}

fmi2Status fmi2GetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
  instance* c = checked(component, "fmi2GetReal");
  size_t k;
  if (!c || null_arrays(c, "fmi2GetReal", n, vr, value)) return fmi2Error;
  for (k = 0; k < n; ++k) {
    const heli_variable* v;
    if (!lookup(c, "fmi2GetReal", vr[k], "Real")) return fmi2Error;
    v = var((int) vr[k]);
    if (v->position < 0) value[k] = value_real(c, (int) vr[k]);
    else if (c->s.loaded && group_of(c)->state_of[vr[k]] >= 0) value[k] = c->s.x[group_of(c)->state_of[vr[k]]];
    else if (ensure_cache(c, "fmi2GetReal")) return fmi2Error;
    else value[k] = c->s.cache[v->position];
  }
  return fmi2OK;
}

static fmi2Status set_one_real(instance* c, int vr, double value) {
  const heli_variable* v = var(vr);
  char a[32];
  if (v->position >= 0) {
    report(c, fmi2Error, "fmi2SetReal: %s '%s' (value reference %d) cannot be set (attempted %s)",
           causality_name(v), v->name, vr, repr(value, a));
    return fmi2Error;
  }
  c->s.real[vr] = value;
  c->s.set[vr] = 1; /* recorded, never inferred from the value (a value equal to the XML start is a setting too) */
  c->s.error[vr][0] = 0;
  c->s.cache_valid = 0;
  if (check_real(c, vr, value, c->s.error[vr]) || check_frozen(c, vr)) {
    report(c, fmi2Error, "%s", c->s.error[vr]);
    return fmi2Error;
  }
  return fmi2OK;
}

static fmi2Status worse(fmi2Status a, fmi2Status b) { return a > b ? a : b; }

static int settable_now(instance* c, const char* call) {
  if (c->s.phase != TERMINATED) return 1;
  wrong_phase(c, call, "call fmi2Reset first");
  return 0;
}

fmi2Status fmi2SetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
  instance* c = checked(component, "fmi2SetReal");
  fmi2Status st = fmi2OK;
  size_t k;
  if (!c || null_arrays(c, "fmi2SetReal", n, vr, value) || !settable_now(c, "fmi2SetReal")) return fmi2Error;
  for (k = 0; k < n; ++k)
    st = worse(st, lookup(c, "fmi2SetReal", vr[k], "Real") ? set_one_real(c, (int) vr[k], value[k]) : fmi2Error);
  return st;
}

fmi2Status fmi2GetString(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2String value[]) {
  instance* c = checked(component, "fmi2GetString");
  size_t k;
  if (!c || null_arrays(c, "fmi2GetString", n, vr, value)) return fmi2Error;
  for (k = 0; k < n; ++k) {
    if (!lookup(c, "fmi2GetString", vr[k], "String")) return fmi2Error;
    value[k] = string_value(c, (int) vr[k]);
  }
  return fmi2OK;
}

static fmi2Status set_one_string(instance* c, int vr, const char* text) {
  const heli_variable* v = var(vr);
  if (!text) {
    report(c, fmi2Error, "fmi2SetString: the value of parameter '%s' (value reference %d) is NULL", v->name, vr);
    return fmi2Error;
  }
  if (vr == M->vr_evaluator && !strcmp(text, "vm")) {
    report(c, fmi2Error, "fmi2SetString: parameter 'evaluator' = '%s': the native FMU has no virtual machine "
           "(it runs its compiled model only); use 'compiled' or the pythonfmu FMU", text);
    return fmi2Error;
  }
  copy_text(c->s.text[vr], text, TEXT_LEN);
  c->s.set[vr] = 1;
  c->s.error[vr][0] = 0;
  c->s.cache_valid = 0;
  if (check_string(vr, text, c->s.error[vr]) || check_frozen(c, vr)) {
    report(c, fmi2Error, "%s", c->s.error[vr]);
    return fmi2Error;
  }
  return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2String value[]) {
  instance* c = checked(component, "fmi2SetString");
  fmi2Status st = fmi2OK;
  size_t k;
  if (!c || null_arrays(c, "fmi2SetString", n, vr, value) || !settable_now(c, "fmi2SetString")) return fmi2Error;
  for (k = 0; k < n; ++k)
    st = worse(st, lookup(c, "fmi2SetString", vr[k], "String") ? set_one_string(c, (int) vr[k], value[k]) : fmi2Error);
  return st;
}

/* This FMU has no Integer or Boolean variables: every value reference is refused. */
static fmi2Status no_such_type(fmi2Component component, const char* call, const char* type,
                               const fmi2ValueReference vr[], size_t n) {
  instance* c = checked(component, call);
  size_t k;
  if (!c || null_arrays(c, call, n, vr, vr)) return fmi2Error;
  for (k = 0; k < n; ++k)
    if (!lookup(c, call, vr[k], type)) return fmi2Error;
  return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer value[]) {
  (void) value;
  return no_such_type(c, "fmi2GetInteger", "Integer", vr, n);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer value[]) {
  (void) value;
  return no_such_type(c, "fmi2SetInteger", "Integer", vr, n);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean value[]) {
  (void) value;
  return no_such_type(c, "fmi2GetBoolean", "Boolean", vr, n);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean value[]) {
  (void) value;
  return no_such_type(c, "fmi2SetBoolean", "Boolean", vr, n);
}

/* -- stepping ------------------------------------------------------------------------------------ */

static int refused_step(instance* c, double t) {
  char a[32];
  int vr, n = 0;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!c->s.error[vr][0]) continue;
    report(c, fmi2Discard, "step at t = %s s refused: %s", repr(t, a), c->s.error[vr]);
    ++n;
  }
  return n;
}

/* Misuse of the step's arguments: fmi2Error (fmi2Discard would ask the master to retry a smaller step). */
static int step_problem(instance* c, double t, double dt) {
  char a[32], b[32];
  if (!(isfinite(dt) && dt > 0))
    report(c, fmi2Error, "fmi2DoStep: communication step size communicationStepSize = %s s must be positive and "
           "finite", repr(dt, a));
  else if (!isfinite(t))
    report(c, fmi2Error, "fmi2DoStep: currentCommunicationPoint = %s s is not finite", repr(t, a));
  else if (fabs(t - c->s.t) > TIME_TOLERANCE * fmax(1.0, fabs(c->s.t)))
    report(c, fmi2Error, "fmi2DoStep: currentCommunicationPoint = %s s does not match the FMU's time %s s (restore a saved "
           "FMU state to go back in time)", repr(t, a), repr(c->s.t, b));
  else return 0;
  return 1;
}

/* Number of sub-steps of dt, or 0 (with a message) beyond MAX_SUBSTEPS; never overflows. */
static heli_int substeps(instance* c, double dt, double h_max) {
  char a[32], b[32], d[32];
  double r = dt / h_max * (1.0 - SUBSTEP_TOLERANCE);
  if (r <= M->max_substeps) return r <= 1 ? 1 : (heli_int) ceil(r);
  report(c, fmi2Discard, "communication step size communicationStepSize = %s s with max_step = %s s needs %s "
         "sub-steps, more than the limit of %.0f; the step was discarded (use a shorter communication step "
         "or a larger max_step)", repr(dt, a), repr(h_max, b), repr(ceil(r), d), M->max_substeps);
  return 0;
}

static const char* method_name(int method) { return method == HELI_RK8 ? "rk8" : "rk4"; }

static void tail(instance* c, double t, char* out) {
  char a[32], b[32];
  snprintf(out, MSG_LEN, "max_step = %s s may be beyond %s's stability limit, or the inputs drove the model out of "
           "its range; the step was discarded (the state stays at t = %s s)", repr(use_real(c, M->vr_max_step), a),
           method_name(c->s.method), repr(t, b));
}

/* Redo the failed step up to its last good sub-step and name the state that became non-finite. */
static void divergence(instance* c, const heli_group* g, double t, double h, heli_int n, heli_int done, int status) {
  char a[32], b[32], d[32], rest[MSG_LEN];
  heli_int k = 0, i = 0;
  double tk = t + (double) done * h;
  memcpy(c->trial, c->s.x, sizeof c->trial);
  memcpy(c->trial_comp, c->s.comp, sizeof c->trial_comp);
  if (done > 0) g->run[c->s.method](c->s.x, t, h, 0, done, done, c->p, c->trial, c->trial_comp, 1, &k);
  tail(c, t, rest);
  if (status != 1 || eval_incr(c, g, c->s.method, c->trial, tk, h, c->p, c->dx)) {
    report(c, fmi2Discard, "the model evaluation failed at t = %s s (sub-step %lld of %lld, h = %s s); the step "
           "was discarded", repr(tk, a), done + 1, n, repr(h, b));
    return;
  }
  for (k = 0; k < g->nx; ++k) c->dx[k] += c->trial[k];
  for (k = g->nx - 1; k >= 0; --k)
    if (!isfinite(c->dx[k])) i = k; /* the first non-finite state, else the first state */
  report(c, fmi2Discard, "the simulation diverged at t = %s s (sub-step %lld of %lld, h = %s s): state '%s' = %s; %s",
         repr(tk, a), done + 1, n, repr(h, b), g->state_names[i], repr(c->dx[i], d), rest);
}

/* 0 if the state c->trial reached at t1 is sound (hinge angles within range, finite
   energy), else 1 with a message. */
static int unsound(instance* c, const heli_group* g, double t, double t1) {
  char a[32], b[32], d[32], rest[MSG_LEN];
  double total;
  int vr;
  tail(c, t, rest);
  for (vr = 0; vr < M->n_variables; ++vr) {
    const heli_variable* v = var(vr);
    double value = g->state_of[vr] >= 0 ? c->trial[g->state_of[vr]] : 0.0;
    if (v->hinge && !(fabs(value) <= M->hinge_angle)) {
      report(c, fmi2Discard, "the simulation left the hinge range at t = %s s: state '%s' = %s rad is outside "
             "[-%s, %s] rad; %s", repr(t1, a), v->name, repr(value, b), repr(M->hinge_angle, d), repr(M->hinge_angle, d), rest);
      return 1;
    }
  }
  if (eval_energy(c, g, c->trial, t1, c->p)) {
    report(c, fmi2Discard, "the generated function energy reported an error at t = %s s; %s", repr(t1, a), rest);
    return 1;
  }
  total = c->energy[g->n_energy - 1];
  if (!isfinite(total)) {
    report(c, fmi2Discard, "the simulation diverged at t = %s s: the total energy 'total_energy' = %s J is not "
           "finite; %s", repr(t1, a), repr(total, b), rest);
    return 1;
  }
  return 0;
}

static fmi2Status advance(instance* c, double t, double dt) {
  const heli_group* g = &M->groups[M->scenes[c->s.scene].group];
  heli_int n, done = 0;
  double h;
  int status;
  fill_params(c, c->s.scene, c->p);
  if (!(n = substeps(c, dt, use_real(c, M->vr_max_step)))) return fmi2Discard;
  h = dt / (double) n;
  memcpy(c->trial_comp, c->s.comp, sizeof c->trial_comp);
  status = g->run[c->s.method](c->s.x, t, h, 0, n, n, c->p, c->trial, c->trial_comp, 1, &done);
  if (status) {
    divergence(c, g, t, h, n, done, status);
    return fmi2Discard;
  }
  if (unsound(c, g, t, t + dt)) return fmi2Discard;
  memcpy(c->s.x, c->trial, sizeof c->s.x);
  memcpy(c->s.comp, c->trial_comp, sizeof c->s.comp);
  c->s.cache_valid = 0; /* the other outputs are evaluated when asked for */
  c->s.t = t + dt;
  return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component component, fmi2Real t, fmi2Real dt, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  instance* c = checked(component, "fmi2DoStep");
  (void) noSetFMUStatePriorToCurrentPoint;
  if (!c) return fmi2Error;
  if (c->s.phase != STEPPING)
    return wrong_phase(c, "fmi2DoStep", "call fmi2ExitInitializationMode first (and no fmi2Terminate before)");
  if (step_problem(c, t, dt)) return fmi2Error;
  if (refused_step(c, t)) return fmi2Discard;
  return advance(c, t, dt);
}

fmi2Status fmi2CancelStep(fmi2Component component) {
  instance* c = checked(component, "fmi2CancelStep");
  if (c) report(c, fmi2Error, "fmi2CancelStep: this FMU never runs a step asynchronously (no fmi2Pending)");
  return fmi2Error;
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component component, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real value[]) {
  instance* c = checked(component, "fmi2SetRealInputDerivatives");
  (void) vr, (void) n, (void) order, (void) value;
  if (c) report(c, fmi2Error, "fmi2SetRealInputDerivatives: not supported (canInterpolateInputs = false)");
  return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component component, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real value[]) {
  instance* c = checked(component, "fmi2GetRealOutputDerivatives");
  (void) vr, (void) n, (void) order, (void) value;
  if (c) report(c, fmi2Error, "fmi2GetRealOutputDerivatives: not supported (maxOutputDerivativeOrder = 0)");
  return fmi2Error;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component component, const fmi2ValueReference unknown[], size_t nu,
                                        const fmi2ValueReference known[], size_t nk, const fmi2Real dv_known[],
                                        fmi2Real dv_unknown[]) {
  instance* c = checked(component, "fmi2GetDirectionalDerivative");
  (void) unknown, (void) nu, (void) known, (void) nk, (void) dv_known, (void) dv_unknown;
  if (c) report(c, fmi2Error, "fmi2GetDirectionalDerivative: not supported (providesDirectionalDerivative = false)");
  return fmi2Error;
}

/* -- status queries ------------------------------------------------------------------------------ */

static fmi2Status no_status(fmi2Component component, const char* call, int kind) {
  instance* c = checked(component, call);
  if (!c) return fmi2Error;
  report(c, fmi2Discard, "%s: status kind %d is not available (fmi2DoStep never returns fmi2Pending)", call, kind);
  return fmi2Discard;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status* value) {
  (void) value;
  return no_status(c, "fmi2GetStatus", (int) s);
}

fmi2Status fmi2GetRealStatus(fmi2Component component, const fmi2StatusKind s, fmi2Real* value) {
  instance* c = checked(component, "fmi2GetRealStatus");
  if (!c) return fmi2Error;
  if (s != fmi2LastSuccessfulTime || !value) return no_status(component, "fmi2GetRealStatus", (int) s);
  *value = c->s.t;
  return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer* value) {
  (void) value;
  return no_status(c, "fmi2GetIntegerStatus", (int) s);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component component, const fmi2StatusKind s, fmi2Boolean* value) {
  if (!checked(component, "fmi2GetBooleanStatus")) return fmi2Error;
  if (s != fmi2Terminated || !value) return no_status(component, "fmi2GetBooleanStatus", (int) s);
  *value = fmi2False; /* the FMU never asks to end the simulation */
  return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String* value) {
  (void) value;
  return no_status(c, "fmi2GetStringStatus", (int) s);
}

/* -- FMU state ----------------------------------------------------------------------------------- */

static saved_state* saved_of(instance* c, fmi2FMUstate state, const char* call) {
  saved_state* s = (saved_state*) state;
  if (s && s->magic == SAVED_MAGIC) return s;
  report(c, fmi2Error, "%s: %s is not an FMU state of this FMU", call, s ? "the state given" : "the state (NULL)");
  return NULL;
}

fmi2Status fmi2GetFMUstate(fmi2Component component, fmi2FMUstate* state) {
  instance* c = checked(component, "fmi2GetFMUstate");
  saved_state* s;
  if (!c) return fmi2Error;
  if (!state) {
    report(c, fmi2Error, "fmi2GetFMUstate: the pointer for the state is NULL");
    return fmi2Error;
  }
  s = *state ? saved_of(c, *state, "fmi2GetFMUstate") : (saved_state*) malloc(sizeof(saved_state));
  if (!s) {
    if (!*state) report(c, fmi2Error, "fmi2GetFMUstate: out of memory");
    return fmi2Error;
  }
  s->magic = SAVED_MAGIC;
  s->s = c->s;
  *state = s;
  return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component component, fmi2FMUstate state) {
  instance* c = checked(component, "fmi2SetFMUstate");
  saved_state* s;
  if (!c || !(s = saved_of(c, state, "fmi2SetFMUstate"))) return fmi2Error;
  c->s = s->s;
  return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component component, fmi2FMUstate* state) {
  instance* c = checked(component, "fmi2FreeFMUstate");
  saved_state* s;
  if (!c) return fmi2Error;
  if (!state || !*state) return fmi2OK;
  if (!(s = saved_of(c, *state, "fmi2FreeFMUstate"))) return fmi2Error;
  s->magic = 0;
  free(s);
  *state = NULL;
  return fmi2OK;
}

static unsigned long long checksum(const void* data, size_t size) {
  const unsigned char* b = (const unsigned char*) data;
  unsigned long long h = 1469598103934665603ull; /* FNV-1a */
  size_t k;
  for (k = 0; k < size; ++k) h = (h ^ b[k]) * 1099511628211ull;
  return h;
}

static size_t blob_size(void) { return sizeof(blob_header) + sizeof(snapshot); }

fmi2Status fmi2SerializedFMUstateSize(fmi2Component component, fmi2FMUstate state, size_t* size) {
  instance* c = checked(component, "fmi2SerializedFMUstateSize");
  if (!c || !saved_of(c, state, "fmi2SerializedFMUstateSize")) return fmi2Error;
  if (!size) {
    report(c, fmi2Error, "fmi2SerializedFMUstateSize: the pointer for the size is NULL");
    return fmi2Error;
  }
  *size = blob_size();
  return fmi2OK;
}

static void fill_header(blob_header* h, const snapshot* s) {
  memset(h, 0, sizeof *h);
  memcpy(h->magic, BLOB_MAGIC, sizeof h->magic);
  h->version = BLOB_VERSION;
  h->size = (unsigned) blob_size();
  copy_text(h->guid, M->guid, sizeof h->guid);
  h->scene = s->loaded ? s->scene : -1;
  h->group = s->loaded ? M->scenes[s->scene].group : -1;
  h->nx = s->loaded ? M->groups[h->group].nx : 0;
  h->checksum = checksum(s, sizeof *s);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component component, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
  instance* c = checked(component, "fmi2SerializeFMUstate");
  saved_state* s;
  blob_header h;
  if (!c || !(s = saved_of(c, state, "fmi2SerializeFMUstate"))) return fmi2Error;
  if (!bytes || size < blob_size()) {
    report(c, fmi2Error, "fmi2SerializeFMUstate: the buffer of %u bytes is too small for the %u bytes of the state",
           (unsigned) size, (unsigned) blob_size());
    return fmi2Error;
  }
  fill_header(&h, &s->s);
  memcpy(bytes, &h, sizeof h);
  memcpy(bytes + sizeof h, &s->s, sizeof s->s);
  return fmi2OK;
}

/* What is wrong with a serialized state's header, or NULL. */
static const char* header_problem(const blob_header* h, size_t size) {
  if (memcmp(h->magic, BLOB_MAGIC, sizeof h->magic)) return "it does not start with this FMU's magic header";
  if (h->version != BLOB_VERSION) return "its format version differs from this FMU's";
  if (h->size != blob_size() || size != blob_size()) return "its size does not match this FMU's states";
  if (strncmp(h->guid, M->guid, sizeof h->guid)) return "it was saved by another FMU (GUID differs)";
  if (h->scene < -1 || h->scene >= M->n_scenes) return "its scene is not one of this FMU's";
  if (h->scene >= 0 && (h->group != M->scenes[h->scene].group || h->nx != M->groups[h->group].nx))
    return "its model group does not match its scene";
  return NULL;
}

/* What is wrong with a snapshot whose checksum matched, or NULL. */
static const char* snapshot_problem(const blob_header* h, snapshot* s) {
  int vr;
  if (h->checksum != checksum(s, sizeof *s)) return "its checksum does not match (the data are damaged)";
  if (s->phase < 0 || s->phase >= PHASES || s->method < 0 || s->method >= HELI_METHODS)
    return "its phase or integrator is not valid";
  if ((s->loaded ? s->scene : -1) != h->scene) return "its scene does not match its header";
  for (vr = 0; vr < HELI_NV; ++vr) {
    s->text[vr][TEXT_LEN - 1] = 0;
    s->error[vr][MSG_LEN - 1] = 0;
  }
  return NULL;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component component, const fmi2Byte bytes[], size_t size, fmi2FMUstate* state) {
  instance* c = checked(component, "fmi2DeSerializeFMUstate");
  blob_header h;
  saved_state* s;
  const char* problem;
  if (!c) return fmi2Error;
  if (!bytes || !state || size < sizeof h) {
    report(c, fmi2Error, "fmi2DeSerializeFMUstate: not a serialized state of this FMU: %u bytes%s", (unsigned) size,
           !bytes || !state ? " (or a NULL pointer)" : ", fewer than its header");
    return fmi2Error;
  }
  memcpy(&h, bytes, sizeof h);
  if ((problem = header_problem(&h, size))) {
    report(c, fmi2Error, "fmi2DeSerializeFMUstate: not a serialized state of this FMU: %s", problem);
    return fmi2Error;
  }
  if (!(s = (saved_state*) malloc(sizeof *s))) {
    report(c, fmi2Error, "fmi2DeSerializeFMUstate: out of memory");
    return fmi2Error;
  }
  memcpy(&s->s, bytes + sizeof h, sizeof s->s);
  if ((problem = snapshot_problem(&h, &s->s))) {
    free(s);
    report(c, fmi2Error, "fmi2DeSerializeFMUstate: the serialized state is corrupt: %s", problem);
    return fmi2Error;
  }
  s->magic = SAVED_MAGIC;
  *state = s;
  return fmi2OK;
}
