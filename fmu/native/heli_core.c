/* The model core of the native heli rotor FMU: everything the model does, for FMI 2.0 and 3.0,
   co-simulation and model exchange alike, over the tables and compiled model groups of
   heli_data.c (see heli_model.h, heli_core.h). fmi2Functions.c and fmi3Functions.c only
   translate the standards' calls into these functions. Behaviour follows the pythonfmu slave
   (fmu/pythonfmu/slave.py):

   - The scene (a String parameter) selects the model group and the initial state. Every input
     and parameter that the master did not set is its XML start value (FMI 2.0 section 2.2.7: an
     input or parameter is initialised with its start), in every scene: no start depends on
     another variable, so a master that writes every start value and one that writes none run
     the same. The XML starts are the primary scene's values; in another scene
     exitInitializationMode warns about each value in use that equals its start but differs
     from that scene's own value (hover's trim controls, ...), naming it; a value the scene
     cannot take (a forward speed without a free fuselage) fails initialisation.
   - stopTime: with stopTimeDefined, a step or a time past stopTime (beyond a relative 1e-9 for
     rounding) is fmiXError, and stopTime before startTime is refused at once.
   - The state machines of FMI 2.0 and 3.0: co-simulation steps in Step Mode; model exchange
     enters Event Mode after initialisation, Continuous-Time Mode by EnterContinuousTimeMode;
     a call in a mode where the standard does not allow it is fmiXError with a message naming
     the mode (a co-simulation of this FMU has no Event Mode: eventModeUsed is refused).
   - Co-simulation: inputs are held over a step; doStep splits dt into n = ceil(dt / max_step
     (1 - 1e-6)) equal sub-steps of the core's fixed-step driver (RK4 or RK8, Kahan-compensated).
   - Model exchange: the continuous states are the primary scene's states x, their derivatives
     the model's x' = rhs(x, t, p). The free fuselage's quaternion needs no care from the host's
     integrator: the model uses q / |q| everywhere (rotation, Euler angles), and q' = q (x) (0, w) / 2
     keeps |q| constant along the exact solution, so |q| drifts only by the host's integration
     error and the motion does not depend on it. A model of the family without some of those
     states (a clamped fuselage) holds them constant (derivative 0).
   - Exact derivatives: fmiXGetDirectionalDerivative is one evaluation of CasADi's forward mode of
     (rhs, fmu_outputs), fmi3GetAdjointDerivative one of its reverse mode; never differences.
   - A refused value (NaN, out of range, a fixed parameter changed after initialisation) is
     stored and logged; the next doStep returns Discard until it is corrected (model exchange:
     the derivatives return Error). A step that diverges (non-finite state, hinge angle beyond
     +-pi/2, non-finite energy) is undone and returns Discard.
   - Outputs that are states (hinge angles and rates, fuselage states) are read from the
     state; the others (fmu_outputs: azimuths, thrusts, Euler angles, energy) are evaluated
     once per state, when the first of them is read.
   - Misuse (unknown value reference, wrong type, setting an output, calls out of order, a
     damaged serialized state) returns Error with a message; the instance stays usable.

   Messages with a status above OK always go to the logger and to stderr; OK messages only
   when logging is on. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "heli_core.h"

#define M (&heli_model_data)
#define INSTANCE_MAGIC 0x48454c49u
#define SAVED_MAGIC 0x53415645u
#define BLOB_VERSION 3u
#define TEXT_LEN 128
#define MSG_LEN 512
#define NAD (HELI_NX + HELI_NCOMPUTED > HELI_NX + HELI_NP ? HELI_NX + HELI_NCOMPUTED : HELI_NX + HELI_NP)
#define TIME_TOLERANCE 1e-9 /* relative mismatch allowed between the master's time and ours */
/* A communication step at most this much (relative) longer than n max_step is n sub-steps: a
   master that counts time in whole nanoseconds rounds the default step (max_step) up by up to
   0.5 ns, about 4e-7 of it; a sub-step 1e-6 longer than max_step changes nothing in stability. */
#define SUBSTEP_TOLERANCE 1e-6

/* STEPPING is co-simulation's Step Mode; EVENT and CONTINUOUS are model exchange's modes. */
enum { INSTANTIATED, INITIALIZATION, STEPPING, EVENT, CONTINUOUS, TERMINATED, PHASES };
static const char* const PHASE_NAMES[PHASES] = {"instantiated", "initialization", "step", "event", "continuous-time",
                                                "terminated"};

/* Everything an FMU state holds: settings, refusals, the simulation state. */
typedef struct {
  int phase;
  double start_time, t;
  int stop_defined;
  double stop_time;
  double real[HELI_NV];              /* Real value last set */
  unsigned char set[HELI_NV];        /* set by the master (whatever the value) since instantiation or reset */
  char text[HELI_NV][TEXT_LEN];      /* String value last set */
  char error[HELI_NV][MSG_LEN];      /* why the value set is refused ("" when accepted) */
  double frozen[HELI_NV];            /* fixed parameters in use since initialisation */
  int frozen_choice[HELI_NV];
  int loaded, scene, method;         /* x, comp belong to this scene, integrated by method */
  double x[HELI_NX], comp[HELI_NX];
  int cache_valid, derivatives_valid;
  double cache[HELI_NCOMPUTED];      /* computed variables at (x, t) */
  double xdot[HELI_NX];              /* rhs(x, t, p) (model exchange) */
} snapshot;

typedef struct {
  unsigned magic;
  const heli_model* model;           /* the FMU (build) that saved it */
  const void* owner;                 /* the instance that saved it */
  snapshot s;
} saved_state;

struct heli_instance {
  unsigned magic;
  snapshot s;
  const char* api;                   /* "fmi2" or "fmi3": the prefix of the calls messages name */
  int kind;                          /* HELI_COSIMULATION or HELI_MODEL_EXCHANGE */
  char* name;
  heli_log_fn logger;
  void* env;
  int logging_on;
  long n_directional, n_adjoint;     /* derivative calls answered (logged) */
  const double** arg;                /* work buffers of the generated functions */
  double** res;
  heli_int* iw;
  double* w;
  double p[HELI_NP + 1];
  double trial[HELI_NX], trial_comp[HELI_NX], dx[HELI_NX], energy[HELI_NENERGY];
  double seed_x[HELI_NX], seed_p[HELI_NP + 1], ad_in[NAD], ad_out[NAD];
  char message[4 * MSG_LEN * 4];
};

typedef struct {
  char magic[8];
  unsigned version, size;
  char guid[64];
  int scene, group, nx, pad;
  unsigned long long checksum;
} blob_header;

static const char BLOB_MAGIC[8] = "HELIFMU";

/* After initialisation, before termination: Step Mode, Event Mode or Continuous-Time Mode. */
static int initialized(const heli_instance* c) {
  return c->s.phase == STEPPING || c->s.phase == EVENT || c->s.phase == CONTINUOUS;
}

/* -- messages ------------------------------------------------------------------------------ */

static const char* status_name(int st) {
  static const char* const names[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
  return (unsigned) st < 6 ? names[st] : "unknown";
}

static const char* category(int st) {
  static const char* const names[] = {"logAll", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                      "logStatusFatal", "logAll"};
  return (unsigned) st < 6 ? names[st] : "logAll";
}

static void emit(heli_log_fn logger, void* env, const char* name, int st, const char* text) {
  if (logger) logger(env, name ? name : "", st, category(st), text);
  if (st > HELI_OK) {
    fprintf(stderr, "%s (%s) %s: %s\n", M->identifier, name ? name : "no instance", status_name(st), text);
    fflush(stderr);
  }
}

static void report(heli_instance* c, int st, const char* fmt, ...) {
  va_list ap;
  if (st == HELI_OK && !c->logging_on) return;
  va_start(ap, fmt);
  vsnprintf(c->message, sizeof c->message, fmt, ap);
  va_end(ap);
  emit(c->logger, c->env, c->name, st, c->message);
}

/* A report before an instance exists (or for a call without one). */
void heli_report_without(heli_log_fn log, void* env, const char* name, const char* fmt, ...) {
  char text[MSG_LEN];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  emit(log, env, name, HELI_ERROR, text);
}

int heli_refuse(heli_instance* c, const char* call, const char* why) {
  report(c, HELI_ERROR, "%s: %s", call, why);
  return HELI_ERROR;
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

static int is_fmi3(const heli_instance* c) { return c->api[3] == '3'; }

static int n_slots(void) { return M->n_variables + M->n_states; }

/* The name of a slot as the calling standard knows it, into buf (TEXT_LEN): FMI 2.0 the scalar
   ("blade2.flap", "der(blade2.flap)"); FMI 3.0 the variable and element ("blade.flap[2]"). Its
   value reference in that standard goes to *ref. */
static const char* slot_label(const heli_instance* c, int slot, char* buf, unsigned* ref) {
  int k, j;
  for (k = 0; is_fmi3(c) && k < M->n_variables3; ++k) {
    const heli_variable3* v = &M->variables3[k];
    for (j = 0; j < v->n; ++j) {
      if (v->slots[j] != slot) continue;
      *ref = (unsigned) k;
      if (v->n == 1) snprintf(buf, TEXT_LEN, "%s", v->name);
      else snprintf(buf, TEXT_LEN, "%s[%d]", v->name, j + 1);
      return buf;
    }
  }
  *ref = (unsigned) slot;
  if (slot < M->n_variables) snprintf(buf, TEXT_LEN, "%s", var(slot)->name);
  else snprintf(buf, TEXT_LEN, "der(%s)", var(M->me_state[slot - M->n_variables])->name);
  return buf;
}

/* The label of the model's state i (group g) as the calling standard names it. */
static const char* state_label(const heli_instance* c, const heli_group* g, int i, char* buf) {
  unsigned ref;
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr)
    if (g->state_of[vr] == i) return slot_label(c, vr, buf, &ref);
  snprintf(buf, TEXT_LEN, "%s", g->state_names[i]);
  return buf;
}

/* The number of continuous state k (FMI 2.0 order) in the calling standard's order. */
static int state_number(const heli_instance* c, int k) {
  int j;
  for (j = 0; is_fmi3(c) && j < M->n_states; ++j)
    if (M->me_order3[j] == k) return j;
  return k;
}

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

static int accepted(const heli_instance* c, int vr) { return c->s.set[vr] && !c->s.error[vr][0]; }

/* The String value in use, as an index into the allowed values. */
static int string_choice(const heli_instance* c, int vr) {
  int k = accepted(c, vr) ? choice_of(vr, c->s.text[vr]) : -1;
  return k >= 0 ? k : choice_of(vr, var(vr)->start_text);
}

static const char* string_value(const heli_instance* c, int vr) {
  return c->s.set[vr] ? c->s.text[vr] : var(vr)->start_text;
}

static int scene_in_use(const heli_instance* c) {
  int k = M->vr_scene >= 0 ? string_choice(c, M->vr_scene) : -1;
  return k >= 0 ? k : M->primary;
}

static int method_in_use(const heli_instance* c) {
  int k = M->vr_integrator >= 0 ? string_choice(c, M->vr_integrator) : -1;
  return k >= 0 && !strcmp(var(M->vr_integrator)->allowed[k], "rk8") ? HELI_RK8 : HELI_RK4;
}

/* 1 when initial_state = "periodic" is in use (the scene may still lack a periodic start). */
static int periodic_in_use(const heli_instance* c) {
  int k = M->vr_initial_state >= 0 ? string_choice(c, M->vr_initial_state) : -1;
  return k >= 0 && !strcmp(var(M->vr_initial_state)->allowed[k], "periodic");
}

/* What the scene starts with by itself (the start value of an FMU built for it alone), for the
   warnings of another scene; NAN where it has none. */
static double scene_default(const heli_instance* c, int scene, int vr) {
  const heli_scene* sc = &M->scenes[scene];
  int periodic = sc->periodic_x0 && periodic_in_use(c);
  if (vr == M->vr_max_step) return 2 * 3.141592653589793 / fabs(sc->omega) / sc->steps_per_rev;
  if (vr == M->vr_forward_speed) return sc->free_body ? (periodic ? sc->trim_speed : sc->fs_default) : 0.0;
  return periodic ? sc->periodic_defaults[vr] : sc->defaults[vr];
}

/* A Real input or parameter not set by the master: its XML start, whatever the scene. */
static double default_real(const heli_instance* c, int vr) {
  (void) c;
  return var(vr)->start;
}

/* The value in use: the one set unless refused, else the scene's default. */
static double use_real(const heli_instance* c, int vr) { return accepted(c, vr) ? c->s.real[vr] : default_real(c, vr); }

/* What a getter returns: the value last set, else the scene's default. */
static double value_real(const heli_instance* c, int vr) { return c->s.set[vr] ? c->s.real[vr] : default_real(c, vr); }

/* -- checking values ------------------------------------------------------------------------ */

/* 0 if value is acceptable for vr in the scene in use, else 1 with the reason in msg. */
static int check_real(const heli_instance* c, int vr, double value, char* msg) {
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
static int check_frozen(heli_instance* c, int vr) {
  char a[32], b[32], msg[MSG_LEN];
  const heli_variable* v = var(vr);
  if (!initialized(c) || !is_fixed_parameter(vr)) return 0;
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

static const heli_group* group_of(const heli_instance* c) { return &M->groups[M->scenes[c->s.scene].group]; }

/* A generated function f(x, t, p, ...) -> out: the extra arguments (seeds) follow p. */
static int eval_xtp(heli_instance* c, heli_eval_fn f, const double* x, double t, const double* p, const double* extra1,
                    const double* extra2, double* out) {
  double tt = t;
  c->arg[0] = x;
  c->arg[1] = &tt;
  c->arg[2] = p;
  c->arg[3] = extra1;
  c->arg[4] = extra2;
  c->res[0] = out;
  return f(c->arg, c->res, c->iw, c->w, 0);
}

static int eval_outputs(heli_instance* c, const heli_group* g, const double* x, double t, const double* p, double* out) {
  return eval_xtp(c, g->outputs, x, t, p, NULL, NULL, out);
}

static int eval_energy(heli_instance* c, const heli_group* g, const double* x, double t, const double* p) {
  return eval_xtp(c, g->energy, x, t, p, NULL, NULL, c->energy);
}

static int eval_incr(heli_instance* c, const heli_group* g, int method, const double* x, double t, double h,
                     const double* p, double* out) {
  double tt = t, hh = h;
  c->arg[0] = x;
  c->arg[1] = &tt;
  c->arg[2] = &hh;
  c->arg[3] = p;
  c->res[0] = out;
  return g->incr[method](c->arg, c->res, c->iw, c->w, 0);
}

static void fill_params(const heli_instance* c, int scene, double* p) {
  const heli_scene* sc = &M->scenes[scene];
  int i;
  for (i = 0; i < sc->n_params; ++i) p[i] = use_real(c, sc->param_vr[i]);
}

/* Initial state of a scene (its own, or its periodic trim with initial_state = "periodic"), with
   initial_forward_speed: body velocity R(q0)^T (V, 0, 0). */
static int initial_state(heli_instance* c, int scene, double* x, char* msg) {
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
  if (vr < 0) return 0;
  speed = use_real(c, vr);
  if (!sc->free_body) {
    if (speed == 0.0) return 0;
    snprintf(msg, MSG_LEN, "parameter 'initial_forward_speed' = %s m/s%s: the scene '%s' has no free fuselage; "
             "set it to 0.0", repr(speed, a), c->s.set[vr] ? "" : " (its start value)", sc->name);
    return 1;
  }
  if (speed == (periodic ? sc->trim_speed : sc->fs_default)) return 0; /* the start's own state */
  dir = periodic ? sc->periodic_fs_dir : sc->fs_dir;
  for (j = 0; j < 3; ++j) x[sc->fs_v[j]] = dir[j] * speed;
  return 0;
}

/* The state at which values and derivatives are evaluated, and its scene: the current state (before
   initialisation: the scene's initial state, in c->trial). */
static const double* current_state(heli_instance* c, int* scene) {
  char msg[MSG_LEN];
  *scene = c->s.loaded ? c->s.scene : scene_in_use(c);
  if (c->s.loaded) return c->s.x;
  initial_state(c, *scene, c->trial, msg);
  return c->trial;
}

/* The computed variables at the current state. */
static int ensure_cache(heli_instance* c, const char* call) {
  char a[32];
  int scene;
  const double* x;
  if (c->s.cache_valid) return HELI_OK;
  x = current_state(c, &scene);
  fill_params(c, scene, c->p);
  if (eval_outputs(c, &M->groups[M->scenes[scene].group], x, c->s.t, c->p, c->s.cache)) {
    report(c, HELI_ERROR, "%s failed: the generated function fmu_outputs reported an error at t = %s s", call,
           repr(c->s.t, a));
    return HELI_ERROR;
  }
  c->s.cache_valid = 1;
  return HELI_OK;
}

static void invalidate(heli_instance* c) { c->s.cache_valid = c->s.derivatives_valid = 0; }

/* -- instances ---------------------------------------------------------------------------------- */

heli_instance* heli_checked(void* component, const char* call) {
  heli_instance* c = (heli_instance*) component;
  if (c && c->magic == INSTANCE_MAGIC) return c;
  heli_report_without(NULL, NULL, NULL, "%s called without a valid instance (%s): instantiate the FMU first", call,
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

static int allocate_work(heli_instance* c) {
  heli_int n[4] = {5, 1, 1, 1};
  int g, m;
  for (g = 0; g < M->n_groups; ++g) {
    const heli_group* gr = &M->groups[g];
    grow(n, gr->outputs_work);
    grow(n, gr->energy_work);
    grow(n, gr->rhs_work);
    grow(n, gr->ad_fwd_work);
    grow(n, gr->ad_adj_work);
    for (m = 0; m < HELI_METHODS; ++m) grow(n, gr->incr_work[m]);
  }
  c->arg = (const double**) calloc((size_t) n[0] + 1, sizeof(double*));
  c->res = (double**) calloc((size_t) n[1] + 1, sizeof(double*));
  c->iw = (heli_int*) calloc((size_t) n[2] + 1, sizeof(heli_int));
  c->w = (double*) calloc((size_t) n[3] + 1, sizeof(double));
  return c->arg && c->res && c->iw && c->w;
}

static void release(heli_instance* c) {
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

heli_instance* heli_instantiate(const char* api, const char* name, int kind, const char* token, heli_log_fn log,
                                void* env, int logging_on) {
  heli_instance* c;
  if (!name || !*name) {
    heli_report_without(log, env, NULL, "%sInstantiate: instanceName is %s: give the instance a name", api,
                        name ? "empty" : "NULL");
    return NULL;
  }
  if (!token || strcmp(token, M->guid)) {
    heli_report_without(log, env, name, "%sInstantiate: %s '%s' does not match this FMU's '%s'", api,
                        api[3] == '2' ? "GUID" : "instantiationToken", token ? token : "(NULL)", M->guid);
    return NULL;
  }
  if (!heli_libm_ready()) {
    heli_report_without(log, env, name, "%sInstantiate: %s; rebuild the library from sources/ with "
                        "-DHELI_LIBM_LINKED and -lm", api, heli_libm_problem());
    return NULL;
  }
  c = (heli_instance*) calloc(1, sizeof(heli_instance));
  if (!c || !(c->name = (char*) malloc(strlen(name) + 1)) || !allocate_work(c)) {
    release(c);
    heli_report_without(log, env, name, "%sInstantiate: out of memory", api);
    return NULL;
  }
  strcpy(c->name, name);
  c->magic = INSTANCE_MAGIC;
  c->api = api;
  c->kind = kind;
  c->logger = log;
  c->env = env;
  c->logging_on = logging_on;
  clear_snapshot(&c->s);
  report(c, HELI_OK, "%sInstantiate: %s, %s, %d scenes, %d model groups", api, M->identifier,
         kind == HELI_MODEL_EXCHANGE ? "model exchange" : "co-simulation", M->n_scenes, M->n_groups);
  return c;
}

void heli_free(heli_instance* c) {
  if (!c) return;
  if (c->n_directional || c->n_adjoint)
    report(c, HELI_OK, "%sFreeInstance: %ld directional and %ld adjoint derivative calls answered", c->api,
           c->n_directional, c->n_adjoint);
  release(c);
}

int heli_kind(const heli_instance* c) { return c->kind; }

void* heli_environment(const heli_instance* c) { return c->env; }

int heli_no_status(heli_instance* c, const char* call, int kind, const void* value) {
  if (!value) return heli_refuse(c, call, "the pointer for the value is NULL");
  report(c, HELI_DISCARD, "%s: status kind %d is not available (%sDoStep never returns %sPending)", call, kind,
         c->api, c->api);
  return HELI_DISCARD;
}

/* fmi2GetRealStatus(fmi2LastSuccessfulTime): the time of the last step taken (startTime before the first). */
int heli_last_successful_time(heli_instance* c, const char* call, double* value) {
  if (!value) return heli_refuse(c, call, "the pointer for the value is NULL");
  if (c->kind != HELI_COSIMULATION) return heli_refuse(c, call, "this instance is for model exchange (a status of "
                                                       "co-simulation)");
  *value = c->s.t;
  return HELI_OK;
}

/* fmi2GetBooleanStatus(fmi2Terminated): false, always (the FMU never asks to end the simulation). */
int heli_terminated_status(heli_instance* c, const char* call, int* value) {
  if (!value) return heli_refuse(c, call, "the pointer for the value is NULL");
  *value = 0;
  return HELI_OK;
}

double heli_time(const heli_instance* c) { return c->s.t; }

static int known_category(const char* name) {
  static const char* const names[] = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                                      "logAll"};
  size_t k;
  for (k = 0; name && k < sizeof names / sizeof names[0]; ++k)
    if (!strcmp(name, names[k])) return 1;
  return 0;
}

int heli_set_debug_logging(heli_instance* c, int on, size_t n, const char* const categories[]) {
  size_t k;
  for (k = 0; k < n; ++k) {
    if (!categories || !known_category(categories[k])) {
      report(c, HELI_ERROR, "%sSetDebugLogging: unknown log category '%s'", c->api, categories && categories[k] ?
             categories[k] : "(NULL)");
      return HELI_ERROR;
    }
  }
  c->logging_on = on;
  return HELI_OK;
}

/* -- life cycle ---------------------------------------------------------------------------------- */

static int wrong_phase(heli_instance* c, const char* call, const char* need) {
  report(c, HELI_ERROR, "%s called in %s mode: %s", call, PHASE_NAMES[c->s.phase], need);
  return HELI_ERROR;
}

int heli_setup(heli_instance* c, const char* call, double start_time, int stop_defined, double stop_time) {
  char a[32], b[32], need[64];
  if (c->s.phase != INSTANTIATED) {
    snprintf(need, sizeof need, "it must come right after %sInstantiate", c->api);
    return wrong_phase(c, call, need);
  }
  if (!isfinite(start_time)) {
    report(c, HELI_ERROR, "%s: startTime = %s s is not finite", call, repr(start_time, a));
    return HELI_ERROR;
  }
  if (stop_defined && !(stop_time >= start_time)) {
    report(c, HELI_ERROR, "%s: stopTime = %s s is %s startTime = %s s (stopTimeDefined = true)", call,
           repr(stop_time, a), isnan(stop_time) ? "not a number, with" : "before", repr(start_time, b));
    return HELI_ERROR;
  }
  c->s.start_time = c->s.t = start_time;
  c->s.stop_defined = stop_defined != 0;
  c->s.stop_time = stop_time;
  invalidate(c);
  return HELI_OK;
}

/* 1 (reported, HELI_ERROR) when a step from `from` to `to` (from NAN: a time set to `to`) goes past
   stopTime: the standards require fmiXError; beyond a relative TIME_TOLERANCE only, for rounding. */
static int past_stop(heli_instance* c, const char* call, double from, double to) {
  char a[32], b[32], d[32];
  if (!c->s.stop_defined || to <= c->s.stop_time + TIME_TOLERANCE * fmax(1.0, fabs(c->s.stop_time))) return 0;
  if (isnan(from))
    report(c, HELI_ERROR, "%s: time = %s s is past stopTime = %s s (stopTimeDefined = true): the FMU computes "
           "nothing beyond it", call, repr(to, a), repr(c->s.stop_time, b));
  else
    report(c, HELI_ERROR, "%s: the step from %s s to %s s ends past stopTime = %s s (stopTimeDefined = true); the "
           "step was not taken", call, repr(from, a), repr(to, d), repr(c->s.stop_time, b));
  return 1;
}

int heli_enter_initialization(heli_instance* c, const char* call) {
  char need[96];
  if (c->s.phase != INSTANTIATED) {
    snprintf(need, sizeof need, "it must come after %sInstantiate (or %sReset)", c->api, c->api);
    return wrong_phase(c, call, need);
  }
  c->s.phase = INITIALIZATION;
  return HELI_OK;
}

/* Ranges depend on the scene: check every Real set again against the final one. */
static void recheck(heli_instance* c) {
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!c->s.set[vr] || var(vr)->type != HELI_REAL) continue;
    c->s.error[vr][0] = 0;
    check_real(c, vr, c->s.real[vr], c->s.error[vr]);
  }
}

/* The messages of refused parameters, joined with "; "; 0 if there are none. */
static int refused_parameters(const heli_instance* c, char* out, size_t size) {
  size_t used = 0;
  int vr, n = 0;
  out[0] = 0;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (var(vr)->causality != HELI_PARAMETER || !c->s.error[vr][0] || used >= size) continue;
    used += (size_t) snprintf(out + used, size - used, "%s%s", n++ ? "; " : "", c->s.error[vr]);
  }
  return n;
}

static void freeze(heli_instance* c) {
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!is_fixed_parameter(vr)) continue;
    if (var(vr)->type == HELI_STRING) c->s.frozen_choice[vr] = string_choice(c, vr);
    else c->s.frozen[vr] = use_real(c, vr);
  }
}

/* In a scene other than the primary one: a warning for each Real input or parameter in use at its
   XML start (the primary scene's value), set or not, where the scene's own value differs; the
   start is used (a master writing every start value and one writing none run the same). */
static int start_values_warned(heli_instance* c, const char* call) {
  int vr, n = 0, scene = scene_in_use(c);
  const char* name = M->scenes[scene].name;
  char a[32], b[32];
  for (vr = 0; scene != M->primary && vr < M->n_variables; ++vr) {
    const heli_variable* v = var(vr);
    double own;
    if (v->type != HELI_REAL || v->causality == HELI_OUTPUT || v->causality == HELI_LOCAL || !(use_real(c, vr) == v->start))
      continue;
    own = scene_default(c, scene, vr);
    if (isnan(own) || own == v->start) continue;
    report(c, HELI_WARNING, "%s: scene '%s' runs with %s '%s' = %s %s, its start value (that of scene '%s'); "
           "scene '%s' by itself has %s %s: set it to that, or use the FMU built for scene '%s' "
           "(heli fmu build --scenes %s)", call, name, causality_name(v), v->name, repr(v->start, a), v->unit,
           M->scenes[M->primary].name, name, repr(own, b), v->unit, name, name);
    ++n;
  }
  return n;
}

/* Model exchange: the host integrates, so the settings of the FMU's own integrator do nothing; a
   warning for each set to another value than its default (a master may apply every XML start). */
static int integrator_settings_warned(heli_instance* c, const char* call) {
  const int vrs[2] = {M->vr_max_step, M->vr_integrator};
  int k, n = 0;
  for (k = 0; c->kind == HELI_MODEL_EXCHANGE && k < 2; ++k) {
    if (vrs[k] < 0 || !accepted(c, vrs[k])) continue;
    if (var(vrs[k])->type == HELI_REAL ? c->s.real[vrs[k]] == default_real(c, vrs[k])
                                       : !strcmp(c->s.text[vrs[k]], var(vrs[k])->start_text))
      continue;
    report(c, HELI_WARNING, "%s: parameter '%s' was set, but it sets the FMU's own integrator, which model exchange "
           "does not use (the host integrates the continuous states): it has no effect", call, var(vrs[k])->name);
    ++n;
  }
  return n;
}

int heli_exit_initialization(heli_instance* c, const char* call) {
  char why[4 * MSG_LEN], need[96];
  int scene, warned;
  if (c->s.phase != INITIALIZATION) {
    snprintf(need, sizeof need, "call %sEnterInitializationMode first", c->api);
    return wrong_phase(c, call, need);
  }
  recheck(c);
  scene = scene_in_use(c);
  if (refused_parameters(c, why, sizeof why) || initial_state(c, scene, c->trial, why)) {
    report(c, HELI_ERROR, "exitInitializationMode failed: %s", why);
    return HELI_ERROR;
  }
  if (c->kind == HELI_MODEL_EXCHANGE && !M->groups[M->scenes[scene].group].me_ok) {
    report(c, HELI_ERROR, "exitInitializationMode failed: scene '%s' has states that are not among this FMU's "
           "continuous states (those of scene '%s'); use it in co-simulation, or build an FMU with it as the first "
           "scene", M->scenes[scene].name, M->scenes[M->primary].name);
    return HELI_ERROR;
  }
  memcpy(c->s.x, c->trial, sizeof c->s.x);
  memset(c->s.comp, 0, sizeof c->s.comp);
  c->s.loaded = 1;
  c->s.scene = scene;
  c->s.method = method_in_use(c);
  c->s.t = c->s.start_time;
  invalidate(c);
  freeze(c);
  c->s.phase = c->kind == HELI_MODEL_EXCHANGE ? EVENT : STEPPING; /* model exchange starts in Event Mode */
  warned = start_values_warned(c, call);
  warned += integrator_settings_warned(c, call);
  return warned ? HELI_WARNING : HELI_OK;
}

int heli_terminate(heli_instance* c, const char* call) {
  if (!initialized(c))
    return wrong_phase(c, call, c->s.phase == TERMINATED ? "it is terminated already"
                                                         : "there is no simulation to terminate (initialise first)");
  c->s.phase = TERMINATED;
  return HELI_OK;
}

int heli_reset(heli_instance* c, const char* call) {
  (void) call;
  clear_snapshot(&c->s);
  return HELI_OK;
}

/* -- getting and setting values ------------------------------------------------------------------ */

int heli_slot_type(int slot) {
  if (slot < 0 || slot >= n_slots()) return -1;
  return slot < M->n_variables ? var(slot)->type : HELI_REAL;
}

static const char* type_name(const heli_instance* c, int type) {
  return type == HELI_STRING ? "String" : c->api[3] == '3' ? "Float64" : "Real";
}

int heli_lookup(heli_instance* c, const char* call, unsigned slot, const char* type) {
  char buf[TEXT_LEN];
  unsigned ref;
  int t;
  if (slot >= (unsigned) n_slots()) {
    report(c, HELI_ERROR, "%s: unknown value reference %u (this FMU has value references 0 to %d)", call, slot,
           n_slots() - 1);
    return 0;
  }
  t = heli_slot_type((int) slot);
  if (strcmp(type_name(c, t), type)) {
    slot_label(c, (int) slot, buf, &ref);
    report(c, HELI_ERROR, "%s: value reference %u is the %s variable '%s', not %s %s", call, ref, type_name(c, t), buf,
           strchr("AEIOU", type[0]) ? "an" : "a", type);
    return 0;
  }
  return 1;
}

int heli_no_values(heli_instance* c, const char* call, size_t n, const void* refs, const void* values) {
  if (n == 0 || (refs && values)) return 0;
  report(c, HELI_ERROR, "%s: %s array is NULL for %u values", call, refs ? "the value" : "the value reference",
         (unsigned) n);
  return 1;
}

static int ensure_derivatives(heli_instance* c, const char* call);

static const heli_group* group_in_use(const heli_instance* c) {
  return &M->groups[M->scenes[c->s.loaded ? c->s.scene : scene_in_use(c)].group];
}

/* Index in x of the k-th continuous state in the model in use, or -1 (not modelled: held). */
static int state_index(const heli_instance* c, int k) { return group_in_use(c)->state_of[M->me_state[k]]; }

int heli_get_real(heli_instance* c, const char* call, int slot, double* value) {
  const heli_variable* v;
  if (slot >= M->n_variables) {
    int k = slot - M->n_variables, i;
    if ((i = state_index(c, k)) < 0) {
      *value = 0.0; /* a state this model holds */
      return HELI_OK;
    }
    if (ensure_derivatives(c, call)) return HELI_ERROR;
    *value = c->s.xdot[i];
    return HELI_OK;
  }
  v = var(slot);
  if (v->position < 0) *value = value_real(c, slot);
  else if (c->s.loaded && group_of(c)->state_of[slot] >= 0) *value = c->s.x[group_of(c)->state_of[slot]];
  else if (ensure_cache(c, call)) return HELI_ERROR;
  else *value = c->s.cache[v->position];
  return HELI_OK;
}

/* The continuous state that the variable `slot` is (model exchange), or -1. */
static int me_state_of(const heli_instance* c, int slot) {
  int k;
  for (k = 0; c->kind == HELI_MODEL_EXCHANGE && k < M->n_states; ++k)
    if (M->me_state[k] == slot) return k;
  return -1;
}

/* Model exchange, after initialisation: a continuous state set by its value reference (as some hosts,
   e.g. CasADi's FMU import, do instead of SetContinuousStates). */
static int set_state_variable(heli_instance* c, const char* call, int k, double value) {
  char a[32], buf[TEXT_LEN];
  unsigned ref;
  int i = state_index(c, k);
  if (!isfinite(value)) {
    report(c, HELI_ERROR, "%s: continuous state '%s' = %s is not finite", call,
           slot_label(c, M->me_state[k], buf, &ref), repr(value, a));
    return HELI_ERROR;
  }
  if (i >= 0) c->s.x[i] = value; /* a state the model holds keeps its value */
  invalidate(c);
  return HELI_OK;
}

int heli_set_real(heli_instance* c, const char* call, int slot, double value) {
  char a[32], buf[TEXT_LEN];
  unsigned ref;
  int k = c->s.loaded && initialized(c) ? me_state_of(c, slot) : -1;
  if (k >= 0) return set_state_variable(c, call, k, value);
  if (slot >= M->n_variables || var(slot)->position >= 0) {
    slot_label(c, slot, buf, &ref);
    report(c, HELI_ERROR, "%s: %s '%s' (value reference %u) cannot be set (attempted %s)", call,
           slot >= M->n_variables ? "derivative" : causality_name(var(slot)), buf, ref, repr(value, a));
    return HELI_ERROR;
  }
  c->s.real[slot] = value;
  c->s.set[slot] = 1; /* recorded, never inferred from the value (a value equal to the XML start is a setting too) */
  c->s.error[slot][0] = 0;
  invalidate(c);
  if (check_real(c, slot, value, c->s.error[slot]) || check_frozen(c, slot)) {
    report(c, HELI_ERROR, "%s", c->s.error[slot]);
    return HELI_ERROR;
  }
  return HELI_OK;
}

/* Values can be read from Initialization Mode on (the standards forbid it in Instantiated). */
int heli_gettable_now(heli_instance* c, const char* call) {
  char need[64];
  if (c->s.phase != INSTANTIATED) return 1;
  snprintf(need, sizeof need, "call %sEnterInitializationMode first", c->api);
  wrong_phase(c, call, need);
  return 0;
}

int heli_settable_now(heli_instance* c, const char* call) {
  char need[64];
  if (c->s.phase != TERMINATED) return 1;
  snprintf(need, sizeof need, "call %sReset first", c->api);
  wrong_phase(c, call, need);
  return 0;
}

const char* heli_get_string(heli_instance* c, int slot) { return string_value(c, slot); }

int heli_set_string(heli_instance* c, const char* call, int slot, const char* text) {
  const heli_variable* v = var(slot);
  if (!text) {
    report(c, HELI_ERROR, "%s: the value of parameter '%s' (value reference %d) is NULL", call, v->name, slot);
    return HELI_ERROR;
  }
  if (slot == M->vr_evaluator && !strcmp(text, "vm")) {
    report(c, HELI_ERROR, "%s: parameter 'evaluator' = '%s': the native FMU has no virtual machine "
           "(it runs its compiled model only); use 'compiled' or the pythonfmu FMU", call, text);
    return HELI_ERROR;
  }
  copy_text(c->s.text[slot], text, TEXT_LEN);
  c->s.set[slot] = 1;
  c->s.error[slot][0] = 0;
  invalidate(c);
  if (check_string(slot, text, c->s.error[slot]) || check_frozen(c, slot)) {
    report(c, HELI_ERROR, "%s", c->s.error[slot]);
    return HELI_ERROR;
  }
  return HELI_OK;
}

/* A type this FMU has no variables of: every value reference is refused. */
int heli_no_such_type(heli_instance* c, const char* call, const char* type, const unsigned refs[], size_t n) {
  size_t k;
  if (heli_no_values(c, call, n, refs, refs)) return HELI_ERROR;
  for (k = 0; k < n; ++k)
    if (!heli_lookup(c, call, refs[k], type)) return HELI_ERROR;
  return HELI_OK;
}

/* -- stepping ------------------------------------------------------------------------------------ */

static int refused_step(heli_instance* c, double t) {
  char a[32];
  int vr, n = 0;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!c->s.error[vr][0]) continue;
    report(c, HELI_DISCARD, "step at t = %s s refused: %s", repr(t, a), c->s.error[vr]);
    ++n;
  }
  return n;
}

/* Misuse of the step's arguments: HELI_ERROR (HELI_DISCARD would ask the master to retry a smaller step). */
static int step_problem(heli_instance* c, const char* call, double t, double dt) {
  char a[32], b[32];
  if (!(isfinite(dt) && dt > 0))
    report(c, HELI_ERROR, "%s: communication step size communicationStepSize = %s s must be positive and "
           "finite", call, repr(dt, a));
  else if (!isfinite(t))
    report(c, HELI_ERROR, "%s: currentCommunicationPoint = %s s is not finite", call, repr(t, a));
  else if (fabs(t - c->s.t) > TIME_TOLERANCE * fmax(1.0, fabs(c->s.t)))
    report(c, HELI_ERROR, "%s: currentCommunicationPoint = %s s does not match the FMU's time %s s (restore a saved "
           "FMU state to go back in time)", call, repr(t, a), repr(c->s.t, b));
  else return 0;
  return 1;
}

/* Number of sub-steps of dt, or 0 (with a message) beyond MAX_SUBSTEPS; never overflows. */
static heli_int substeps(heli_instance* c, double dt, double h_max) {
  char a[32], b[32], d[32];
  double r = dt / h_max * (1.0 - SUBSTEP_TOLERANCE);
  if (r <= M->max_substeps) return r <= 1 ? 1 : (heli_int) ceil(r);
  report(c, HELI_DISCARD, "communication step size communicationStepSize = %s s with max_step = %s s needs %s "
         "sub-steps, more than the limit of %.0f; the step was discarded (use a shorter communication step "
         "or a larger max_step)", repr(dt, a), repr(h_max, b), repr(ceil(r), d), M->max_substeps);
  return 0;
}

static const char* method_name(int method) { return method == HELI_RK8 ? "rk8" : "rk4"; }

static void tail(heli_instance* c, double t, char* out) {
  char a[32], b[32];
  if (c->kind == HELI_MODEL_EXCHANGE) {
    snprintf(out, MSG_LEN, "the host's integration or the inputs drove the model out of its range");
    return;
  }
  snprintf(out, MSG_LEN, "max_step = %s s may be beyond %s's stability limit, or the inputs drove the model out of "
           "its range; the step was discarded (the state stays at t = %s s)", repr(use_real(c, M->vr_max_step), a),
           method_name(c->s.method), repr(t, b));
}

/* Redo the failed step up to its last good sub-step and name the state that became non-finite. */
static void divergence(heli_instance* c, const heli_group* g, double t, double h, heli_int n, heli_int done, int status) {
  char a[32], b[32], d[32], rest[MSG_LEN], buf[TEXT_LEN];
  heli_int k = 0, i = 0;
  double tk = t + (double) done * h;
  memcpy(c->trial, c->s.x, sizeof c->trial);
  memcpy(c->trial_comp, c->s.comp, sizeof c->trial_comp);
  if (done > 0) g->run[c->s.method](c->s.x, t, h, 0, done, done, c->p, c->trial, c->trial_comp, 1, &k);
  tail(c, t, rest);
  if (status != 1 || eval_incr(c, g, c->s.method, c->trial, tk, h, c->p, c->dx)) {
    report(c, HELI_DISCARD, "the model evaluation failed at t = %s s (sub-step %lld of %lld, h = %s s); the step "
           "was discarded", repr(tk, a), done + 1, n, repr(h, b));
    return;
  }
  for (k = 0; k < g->nx; ++k) c->dx[k] += c->trial[k];
  for (k = g->nx - 1; k >= 0; --k)
    if (!isfinite(c->dx[k])) i = k; /* the first non-finite state, else the first state */
  report(c, HELI_DISCARD, "the simulation diverged at t = %s s (sub-step %lld of %lld, h = %s s): state '%s' = %s; %s",
         repr(tk, a), done + 1, n, repr(h, b), state_label(c, g, (int) i, buf), repr(c->dx[i], d), rest);
}

/* 0 if the state c->trial reached at t1 is sound (hinge angles within range, finite
   energy), else 1 with a message (formatted only then: the numbers' shortest repr costs more than
   the step's model evaluations). */
static int unsound(heli_instance* c, const heli_group* g, double t, double t1) {
  char a[32], b[32], d[32], rest[MSG_LEN], buf[TEXT_LEN];
  unsigned ref;
  double total;
  int vr;
  for (vr = 0; vr < M->n_variables; ++vr) {
    const heli_variable* v = var(vr);
    double value = g->state_of[vr] >= 0 ? c->trial[g->state_of[vr]] : 0.0;
    if (v->hinge && !(fabs(value) <= M->hinge_angle)) {
      tail(c, t, rest);
      report(c, HELI_DISCARD, "the simulation left the hinge range at t = %s s: state '%s' = %s rad is outside "
             "[-%s, %s] rad; %s", repr(t1, a), slot_label(c, vr, buf, &ref), repr(value, b), repr(M->hinge_angle, d),
             repr(M->hinge_angle, d), rest);
      return 1;
    }
  }
  if (eval_energy(c, g, c->trial, t1, c->p)) {
    tail(c, t, rest);
    report(c, HELI_DISCARD, "the generated function energy reported an error at t = %s s; %s", repr(t1, a), rest);
    return 1;
  }
  total = c->energy[g->n_energy - 1];
  if (!isfinite(total)) {
    tail(c, t, rest);
    report(c, HELI_DISCARD, "the simulation diverged at t = %s s: the total energy 'total_energy' = %s J is not "
           "finite; %s", repr(t1, a), repr(total, b), rest);
    return 1;
  }
  return 0;
}

static int advance(heli_instance* c, double t, double dt) {
  const heli_group* g = &M->groups[M->scenes[c->s.scene].group];
  heli_int n, done = 0;
  double h;
  int status;
  fill_params(c, c->s.scene, c->p);
  if (!(n = substeps(c, dt, use_real(c, M->vr_max_step)))) return HELI_DISCARD;
  h = dt / (double) n;
  memcpy(c->trial_comp, c->s.comp, sizeof c->trial_comp);
  status = g->run[c->s.method](c->s.x, t, h, 0, n, n, c->p, c->trial, c->trial_comp, 1, &done);
  if (status) {
    divergence(c, g, t, h, n, done, status);
    return HELI_DISCARD;
  }
  if (unsound(c, g, t, t + dt)) return HELI_DISCARD;
  memcpy(c->s.x, c->trial, sizeof c->s.x);
  memcpy(c->s.comp, c->trial_comp, sizeof c->s.comp);
  invalidate(c); /* the other outputs are evaluated when asked for */
  c->s.t = t + dt;
  return HELI_OK;
}

int heli_do_step(heli_instance* c, const char* call, double t, double dt) {
  char need[128];
  if (c->kind != HELI_COSIMULATION) return heli_refuse(c, call, "this instance is for model exchange: the host "
                                                       "integrates the continuous states");
  if (c->s.phase != STEPPING) {
    snprintf(need, sizeof need, "call %sExitInitializationMode first (and no %sTerminate before)", c->api, c->api);
    return wrong_phase(c, call, need);
  }
  if (step_problem(c, call, t, dt) || past_stop(c, call, c->s.t, c->s.t + dt)) return HELI_ERROR;
  if (refused_step(c, t)) return HELI_DISCARD;
  return advance(c, t, dt);
}

/* -- model exchange --------------------------------------------------------------------------------- */

#define IN(phase) (1u << (phase))
#define AFTER_SETUP (IN(INITIALIZATION) | IN(EVENT) | IN(CONTINUOUS) | IN(TERMINATED))

/* What a model-exchange call needs, for the message of a call in the wrong mode. */
static const char* me_need(unsigned allowed) {
  if (allowed == IN(CONTINUOUS)) return "it belongs to Continuous-Time Mode (EnterContinuousTimeMode first)";
  if (allowed == IN(EVENT)) return "it belongs to Event Mode (after ExitInitializationMode, or EnterEventMode)";
  if (allowed == (IN(EVENT) | IN(CONTINUOUS))) return "it needs Event or Continuous-Time Mode (initialise first, "
                                                      "no Terminate before)";
  return "it needs Initialization, Event or Continuous-Time Mode (or Terminated)";
}

/* A model-exchange call: 1 (reported) unless the instance is for model exchange and in one of the
   modes `allowed` (a mask of IN(phase)): the modes of the FMI 2.0 and 3.0 state machines. */
static int me_problem(heli_instance* c, const char* call, unsigned allowed) {
  if (c->kind != HELI_MODEL_EXCHANGE) {
    heli_refuse(c, call, "this instance is for co-simulation: instantiate it for model exchange");
    return 1;
  }
  if (allowed & IN(c->s.phase)) return 0;
  wrong_phase(c, call, me_need(allowed));
  return 1;
}

static int length_problem(heli_instance* c, const char* call, size_t n, const void* array) {
  if (n == (size_t) M->n_states && array) return 0;
  report(c, HELI_ERROR, "%s: %u values%s, but this FMU has %d continuous states", call, (unsigned) n,
         array ? "" : " (NULL array)", M->n_states);
  return 1;
}

/* Event Mode and its iteration: this FMU has no events, nothing changes but the mode. */
int heli_event_mode(heli_instance* c, const char* call) {
  if (me_problem(c, call, IN(EVENT) | IN(CONTINUOUS))) return HELI_ERROR;
  c->s.phase = EVENT;
  return HELI_OK;
}

int heli_discrete_states(heli_instance* c, const char* call) {
  if (c->kind == HELI_COSIMULATION && is_fmi3(c))
    return heli_refuse(c, call, "this co-simulation has no Event Mode (eventModeUsed = false): there are no discrete "
                                "states to update");
  return me_problem(c, call, IN(EVENT)) ? HELI_ERROR : HELI_OK;
}

int heli_continuous_time_mode(heli_instance* c, const char* call) {
  if (me_problem(c, call, IN(EVENT))) return HELI_ERROR;
  c->s.phase = CONTINUOUS;
  return HELI_OK;
}

/* fmi3EnterStepMode leaves a co-simulation's Event Mode, which this FMU never enters: always refused. */
int heli_step_mode(heli_instance* c, const char* call) {
  if (c->kind == HELI_MODEL_EXCHANGE) return heli_refuse(c, call, "this instance is for model exchange");
  return wrong_phase(c, call, "it leaves Event Mode, which this co-simulation does not have (eventModeUsed = false: "
                              "fmi3ExitInitializationMode enters Step Mode)");
}

int heli_set_time(heli_instance* c, const char* call, double t) {
  char a[32];
  if (me_problem(c, call, IN(EVENT) | IN(CONTINUOUS))) return HELI_ERROR;
  if (!isfinite(t)) {
    report(c, HELI_ERROR, "%s: time = %s s is not finite", call, repr(t, a));
    return HELI_ERROR;
  }
  if (past_stop(c, call, NAN, t)) return HELI_ERROR;
  c->s.t = t;
  invalidate(c);
  return HELI_OK;
}

int heli_set_states(heli_instance* c, const char* call, const double x[], size_t n) {
  char a[32], buf[TEXT_LEN];
  unsigned ref;
  int k, i;
  if (me_problem(c, call, IN(CONTINUOUS)) || length_problem(c, call, n, x)) return HELI_ERROR;
  for (k = 0; k < M->n_states; ++k) {
    if (isfinite(x[k])) continue;
    report(c, HELI_ERROR, "%s: continuous state %d ('%s') = %s is not finite", call, state_number(c, k),
           slot_label(c, M->me_state[k], buf, &ref), repr(x[k], a));
    return HELI_ERROR;
  }
  for (k = 0; k < M->n_states; ++k)
    if ((i = state_index(c, k)) >= 0) c->s.x[i] = x[k]; /* a state the model holds keeps its value */
  invalidate(c);
  return HELI_OK;
}

int heli_get_states(heli_instance* c, const char* call, double x[], size_t n) {
  int k;
  if (me_problem(c, call, AFTER_SETUP) || length_problem(c, call, n, x)) return HELI_ERROR;
  for (k = 0; k < M->n_states; ++k)
    if (heli_get_real(c, call, M->me_state[k], &x[k])) return HELI_ERROR;
  return HELI_OK;
}

int heli_get_nominals(heli_instance* c, const char* call, double x[], size_t n) {
  int k;
  if (c->kind != HELI_MODEL_EXCHANGE) return heli_refuse(c, call, "this instance is for co-simulation");
  if (length_problem(c, call, n, x)) return HELI_ERROR;
  for (k = 0; k < M->n_states; ++k) x[k] = 1.0;
  return HELI_OK;
}

/* x' = rhs(x, t, p) at the current state, once per state. */
static int ensure_derivatives(heli_instance* c, const char* call) {
  char a[32], b[32], buf[TEXT_LEN];
  int vr, n = 0, scene;
  const double* x;
  const heli_group* g;
  if (c->s.derivatives_valid) return HELI_OK;
  for (vr = 0; vr < M->n_variables; ++vr) {
    if (!c->s.error[vr][0]) continue;
    report(c, HELI_ERROR, "%s at t = %s s refused: %s", call, repr(c->s.t, a), c->s.error[vr]);
    ++n;
  }
  if (n) return HELI_ERROR;
  x = current_state(c, &scene);
  g = &M->groups[M->scenes[scene].group];
  fill_params(c, scene, c->p);
  if (eval_xtp(c, g->rhs, x, c->s.t, c->p, NULL, NULL, c->s.xdot)) {
    report(c, HELI_ERROR, "%s failed: the generated function rhs reported an error at t = %s s", call, repr(c->s.t, a));
    return HELI_ERROR;
  }
  for (vr = 0; vr < g->nx; ++vr) {
    if (isfinite(c->s.xdot[vr])) continue;
    report(c, HELI_ERROR, "%s: the derivative of state '%s' is %s at t = %s s: the state is outside the model's range",
           call, state_label(c, g, vr, buf), repr(c->s.xdot[vr], a), repr(c->s.t, b));
    return HELI_ERROR;
  }
  c->s.derivatives_valid = 1;
  return HELI_OK;
}

int heli_get_derivatives(heli_instance* c, const char* call, double dx[], size_t n) {
  int k;
  if (me_problem(c, call, AFTER_SETUP) || length_problem(c, call, n, dx)) return HELI_ERROR;
  for (k = 0; k < M->n_states; ++k)
    if (heli_get_real(c, call, M->n_variables + k, &dx[k])) return HELI_ERROR;
  return HELI_OK;
}

/* After each step of the host's integrator: the state must be sound (hinge angles, energy). */
int heli_completed_integrator_step(heli_instance* c, const char* call, int* terminate) {
  if (me_problem(c, call, IN(CONTINUOUS))) return HELI_ERROR;
  if (terminate) *terminate = 0;
  fill_params(c, c->s.scene, c->p);
  memcpy(c->trial, c->s.x, sizeof c->trial);
  if (unsound(c, group_of(c), c->s.t, c->s.t))
    return heli_refuse(c, call, "the state is outside the model's range (the message before says why)");
  return HELI_OK;
}

/* -- exact derivatives ---------------------------------------------------------------------------- */

/* -2, reported: `slot` cannot be a `role` (known or unknown) of a derivative, which must be `what`. */
static int not_a(heli_instance* c, const char* call, unsigned slot, const char* role, const char* what) {
  char buf[TEXT_LEN];
  unsigned ref;
  if (slot >= (unsigned) n_slots()) {
    report(c, HELI_ERROR, "%s: unknown value reference %u (%s)", call, slot, role);
    return -2;
  }
  slot_label(c, (int) slot, buf, &ref);
  report(c, HELI_ERROR, "%s: %s '%s' (value reference %u) is not %s", call, role, buf, ref, what);
  return -2;
}

/* Where a known goes in the seed (x, p): 0 .. nx-1 a state, nx + j the j-th model parameter (an input);
   -1 a continuous state this model holds (contributes nothing); -2 (reported) not a known. */
static int known_index(heli_instance* c, const char* call, unsigned slot, int scene) {
  const heli_scene* sc = &M->scenes[scene];
  const heli_group* g = &M->groups[sc->group];
  int k;
  if (slot < (unsigned) M->n_variables && var((int) slot)->causality == HELI_INPUT) {
    for (k = 0; k < sc->n_params; ++k)
      if (sc->param_vr[k] == (int) slot) return g->nx + k;
    return -1;
  }
  for (k = 0; c->kind == HELI_MODEL_EXCHANGE && k < M->n_states; ++k)
    if (M->me_state[k] == (int) slot) return g->state_of[slot];
  return not_a(c, call, slot, "known", c->kind == HELI_MODEL_EXCHANGE ? "a continuous state or an input"
                                                                      : "an input (co-simulation)");
}

/* Where an unknown is in the result (x', y): 0 .. nx-1 a derivative, nx + position a computed variable;
   -1 the derivative of a held state (0); -2 (reported) not an unknown. */
static int unknown_index(heli_instance* c, const char* call, unsigned slot, int scene) {
  const heli_group* g = &M->groups[M->scenes[scene].group];
  if (slot < (unsigned) M->n_variables && var((int) slot)->position >= 0) return g->nx + var((int) slot)->position;
  if (slot >= (unsigned) M->n_variables && slot < (unsigned) n_slots() && c->kind == HELI_MODEL_EXCHANGE)
    return g->state_of[M->me_state[slot - (unsigned) M->n_variables]];
  return not_a(c, call, slot, "unknown", c->kind == HELI_MODEL_EXCHANGE ? "an output, a local or a derivative"
                                                                        : "an output or a local");
}

static int derivative_problem(heli_instance* c, const char* call, size_t nu, const void* unknown, size_t nk,
                              const void* known, const void* seed, const void* sensitivity) {
  if (c->s.phase == INSTANTIATED) {
    char need[96];
    snprintf(need, sizeof need, "call %sEnterInitializationMode first", c->api);
    return wrong_phase(c, call, need);
  }
  if ((nu && (!unknown || !sensitivity)) || (nk && (!known || !seed)))
    return heli_refuse(c, call, "a value reference, seed or sensitivity array is NULL");
  return HELI_OK;
}

int heli_directional(heli_instance* c, const char* call, const unsigned unknown[], size_t nu,
                     const unsigned known[], size_t nk, const double seed[], double sensitivity[]) {
  int scene, i;
  size_t k;
  const double* x;
  const heli_group* g;
  if (derivative_problem(c, call, nu, unknown, nk, known, seed, sensitivity)) return HELI_ERROR;
  x = current_state(c, &scene);
  g = &M->groups[M->scenes[scene].group];
  memset(c->ad_in, 0, sizeof c->ad_in);
  for (k = 0; k < nk; ++k) {
    if ((i = known_index(c, call, known[k], scene)) == -2) return HELI_ERROR;
    if (i >= 0) c->ad_in[i] += seed[k];
  }
  for (k = 0; k < nu; ++k)
    if (unknown_index(c, call, unknown[k], scene) == -2) return HELI_ERROR;
  fill_params(c, scene, c->p);
  if (eval_xtp(c, g->ad_fwd, x, c->s.t, c->p, c->ad_in, c->ad_in + g->nx, c->ad_out))
    return heli_refuse(c, call, "the generated forward derivative reported an error");
  for (k = 0; k < nu; ++k) {
    i = unknown_index(c, call, unknown[k], scene);
    sensitivity[k] = i >= 0 ? c->ad_out[i] : 0.0;
  }
  report(c, HELI_OK, "%s: call %ld, %u unknowns, %u knowns: one evaluation of the forward-mode derivative", call,
         ++c->n_directional, (unsigned) nu, (unsigned) nk);
  return HELI_OK;
}

int heli_adjoint(heli_instance* c, const char* call, const unsigned unknown[], size_t nu, const unsigned known[],
                 size_t nk, const double seed[], double sensitivity[]) {
  int scene, i;
  size_t k;
  const double* x;
  const heli_group* g;
  /* in the adjoint the seeds belong to the unknowns and the sensitivities to the knowns */
  if (derivative_problem(c, call, nu, unknown, nk, known, sensitivity, seed)) return HELI_ERROR;
  x = current_state(c, &scene);
  g = &M->groups[M->scenes[scene].group];
  memset(c->ad_in, 0, sizeof c->ad_in);
  for (k = 0; k < nu; ++k) {
    if ((i = unknown_index(c, call, unknown[k], scene)) == -2) return HELI_ERROR;
    if (i >= 0) c->ad_in[i] += seed[k];
  }
  for (k = 0; k < nk; ++k)
    if (known_index(c, call, known[k], scene) == -2) return HELI_ERROR;
  fill_params(c, scene, c->p);
  if (eval_xtp(c, g->ad_adj, x, c->s.t, c->p, c->ad_in, NULL, c->ad_out))
    return heli_refuse(c, call, "the generated reverse derivative reported an error");
  for (k = 0; k < nk; ++k) {
    i = known_index(c, call, known[k], scene);
    sensitivity[k] = i >= 0 ? c->ad_out[i] : 0.0;
  }
  report(c, HELI_OK, "%s: call %ld, %u unknowns, %u knowns: one evaluation of the reverse-mode derivative", call,
         ++c->n_adjoint, (unsigned) nu, (unsigned) nk);
  return HELI_OK;
}

/* -- FMU state ----------------------------------------------------------------------------------- */

/* The FMU state `state` if this instance saved it (got or deserialized it), else NULL (reported):
   a state of another FMU, of another build of this one or of another instance is refused. */
static saved_state* saved_of(heli_instance* c, void* state, const char* call) {
  saved_state* s = (saved_state*) state;
  if (s && s->magic == SAVED_MAGIC && s->model == M && s->owner == c) return s;
  if (s && s->magic == SAVED_MAGIC && s->model == M)
    report(c, HELI_ERROR, "%s: the state given belongs to another instance of this FMU (serialize it there and "
           "deserialize it here to move it)", call);
  else
    report(c, HELI_ERROR, "%s: %s is not an FMU state of this FMU%s", call, s ? "the state given" : "the state (NULL)",
           s && s->magic == SAVED_MAGIC ? " (it was saved by another FMU library: another build, or another copy)" : "");
  return NULL;
}

int heli_get_state(heli_instance* c, const char* call, void** state) {
  saved_state* s;
  if (!state) return heli_refuse(c, call, "the pointer for the state is NULL");
  s = *state ? saved_of(c, *state, call) : (saved_state*) malloc(sizeof(saved_state));
  if (!s) {
    if (!*state) heli_refuse(c, call, "out of memory");
    return HELI_ERROR;
  }
  s->magic = SAVED_MAGIC;
  s->model = M;
  s->owner = c;
  s->s = c->s;
  *state = s;
  return HELI_OK;
}

int heli_set_state(heli_instance* c, const char* call, void* state) {
  saved_state* s = saved_of(c, state, call);
  if (!s) return HELI_ERROR;
  c->s = s->s;
  return HELI_OK;
}

int heli_free_state(heli_instance* c, const char* call, void** state) {
  saved_state* s;
  if (!state || !*state) return HELI_OK;
  if (!(s = saved_of(c, *state, call))) return HELI_ERROR;
  s->magic = 0;
  free(s);
  *state = NULL;
  return HELI_OK;
}

static unsigned long long checksum(const void* data, size_t size) {
  const unsigned char* b = (const unsigned char*) data;
  unsigned long long h = 1469598103934665603ull; /* FNV-1a */
  size_t k;
  for (k = 0; k < size; ++k) h = (h ^ b[k]) * 1099511628211ull;
  return h;
}

static size_t blob_size(void) { return sizeof(blob_header) + sizeof(snapshot); }

int heli_serialized_size(heli_instance* c, const char* call, void* state, size_t* size) {
  if (!saved_of(c, state, call)) return HELI_ERROR;
  if (!size) return heli_refuse(c, call, "the pointer for the size is NULL");
  *size = blob_size();
  return HELI_OK;
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

int heli_serialize(heli_instance* c, const char* call, void* state, unsigned char bytes[], size_t size) {
  saved_state* s;
  blob_header h;
  if (!(s = saved_of(c, state, call))) return HELI_ERROR;
  if (!bytes) {
    report(c, HELI_ERROR, "%s: the buffer for the %u bytes of the state is NULL", call, (unsigned) blob_size());
    return HELI_ERROR;
  }
  if (size < blob_size()) {
    report(c, HELI_ERROR, "%s: the buffer of %u bytes is too small for the %u bytes of the state (ask "
           "%sSerializedFMU%sSize)", call, (unsigned) size, (unsigned) blob_size(), c->api, is_fmi3(c) ? "State" : "state");
    return HELI_ERROR;
  }
  fill_header(&h, &s->s);
  memcpy(bytes, &h, sizeof h);
  memcpy(bytes + sizeof h, &s->s, sizeof s->s);
  return HELI_OK;
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

int heli_deserialize(heli_instance* c, const char* call, const unsigned char bytes[], size_t size, void** state) {
  blob_header h;
  saved_state* s;
  const char* problem;
  if (!bytes || !state || size < sizeof h) {
    report(c, HELI_ERROR, "%s: not a serialized state of this FMU: %u bytes%s", call, (unsigned) size,
           !bytes || !state ? " (or a NULL pointer)" : ", fewer than its header");
    return HELI_ERROR;
  }
  memcpy(&h, bytes, sizeof h);
  if ((problem = header_problem(&h, size))) {
    report(c, HELI_ERROR, "%s: not a serialized state of this FMU: %s", call, problem);
    return HELI_ERROR;
  }
  if (!(s = (saved_state*) malloc(sizeof *s))) return heli_refuse(c, call, "out of memory");
  memcpy(&s->s, bytes + sizeof h, sizeof s->s);
  if ((problem = snapshot_problem(&h, &s->s))) {
    free(s);
    report(c, HELI_ERROR, "%s: the serialized state is corrupt: %s", call, problem);
    return HELI_ERROR;
  }
  s->magic = SAVED_MAGIC;
  s->model = M;
  s->owner = c;
  *state = s;
  return HELI_OK;
}
