/* A scripted FMI 2.0 and 3.0 host (co-simulation and model exchange) for the tests: it loads FMU
   libraries (dlopen; LoadLibrary on Windows), reads one command per line from the file given
   (or stdin), calls the FMU's standard functions only, and prints one JSON object per command:

     {"line": n, "cmd": "step", "status": 0, "seconds": 1.2e-06, "values": [...], "log": [[3, "logStatusError", "..."]]}

   `status` is the FMI status of the call (-1: no status, e.g. an instance that was not created),
   `seconds` the wall time of the call(s), `log` the messages the FMU logged during the command.
   It builds for Linux (x86_64, aarch64) and, with mingw, for Windows; with -DSCRIPT_HOST_PYTHON
   (linked to libpython) it starts Python itself, for an FMU whose slave is Python.

   Commands (L library, I instance, S state slot, B blob slot: small integers; VR value references):
     load L PATH                         open a shared library
     fmi2 I L cs|me NAME GUID URI [log]  fmi2Instantiate into I (which becomes the current instance)
     fmi3 I L cs|me NAME TOKEN PATH [log]  fmi3InstantiateCoSimulation / ModelExchange
     use I                               make I the current instance
     setup TOLDEF TOL START STOPDEF STOP fmi2SetupExperiment (FMI 3.0: the arguments of enter)
     enter | exit | terminate | reset | free
     setr VR.. = V..   getr VR.. [nvalues N]   Real (FMI 3.0: Float64) values
     sets VR TEXT   gets VR               TEXT: s:<text without spaces> or x:<hex bytes>
     step T H                            DoStep (FMI 3.0: values = [lastSuccessfulTime])
     steps N T0 H VR..                   N steps t_k = T0 + k H, reading VR.. after each (values, row by row)
     settime T | eventmode | newdiscrete | ctmode | completed | enterstep
     getx N | setx N V.. | getdx N       continuous states and derivatives
     euler N T0 H NX VR..                model exchange: N explicit Euler steps, reading VR.. after each
     realstatus KIND [null] | boolstatus KIND [null]
     getstate S | setstate S | freestate S
     serialize S B [SIZE|null]           into blob B (SIZE: the buffer's size, default the one asked)
     deserialize B S
     blob B cut N | grow N | flip BYTE MASK | save FILE | load FILE   change, write or read a blob */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef SCRIPT_HOST_PYTHON
#include <Python.h>
#endif

#include "fmi2Functions.h"
#include "fmi3Functions.h"
#include "host_platform.h"

#define SLOTS 16
#define MAX_VALUES 4096
#define MAX_TOKENS 4200
#define LOG_MAX 64
#define TEXT_MAX 2048

/* -- libraries and their symbols ------------------------------------------------------------ */


static void* libs[SLOTS];

/* A function of the current instance's library (NULL when it lacks it). */
#define FN(type, name) ((type*) find_symbol(libs[cur->lib], name))

/* -- output ------------------------------------------------------------------------------------ */

typedef struct {
  int status;
  char category[64];
  char text[TEXT_MAX];
} message;

static message logged[LOG_MAX];
static int n_logged;

static void keep(int status, const char* category, const char* text) {
  if (n_logged == LOG_MAX) return;
  logged[n_logged].status = status;
  snprintf(logged[n_logged].category, sizeof logged[0].category, "%s", category ? category : "");
  snprintf(logged[n_logged].text, sizeof logged[0].text, "%s", text ? text : "(NULL)");
  ++n_logged;
}

static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                 fmi2String message, ...) {
  char text[TEXT_MAX];
  va_list ap;
  (void) env, (void) name;
  va_start(ap, message);
  vsnprintf(text, sizeof text, message ? message : "(NULL)", ap);
  va_end(ap);
  keep((int) status, category, text);
}

static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message) {
  (void) env;
  keep((int) status, category, message);
}

static void json_string(const char* s) {
  putchar('"');
  for (; *s; ++s) {
    unsigned char ch = (unsigned char) *s;
    if (ch == '"' || ch == '\\') printf("\\%c", ch);
    else if (ch < 0x20) printf("\\u%04x", ch);
    else putchar(ch);
  }
  putchar('"');
}

static void json_number(double v) {
  if (isnan(v)) printf("NaN");
  else if (isinf(v)) printf(v > 0 ? "Infinity" : "-Infinity");
  else printf("%.17g", v);
}

/* -- the command's result ------------------------------------------------------------------------ */

static double values[MAX_VALUES * 8];
static int n_values;
static const char* strings_out[MAX_VALUES];
static int n_strings;

static void value(double v) {
  if (n_values < (int) (sizeof values / sizeof values[0])) values[n_values++] = v;
}

static void print_result(int line, const char* cmd, int status, double seconds) {
  int k;
  printf("{\"line\": %d, \"cmd\": ", line);
  json_string(cmd);
  printf(", \"status\": %d, \"seconds\": %.9g, \"values\": [", status, seconds);
  for (k = 0; k < n_values; ++k) {
    if (k) printf(", ");
    json_number(values[k]);
  }
  printf("], \"strings\": [");
  for (k = 0; k < n_strings; ++k) {
    if (k) printf(", ");
    if (strings_out[k]) json_string(strings_out[k]);
    else printf("null");
  }
  printf("], \"log\": [");
  for (k = 0; k < n_logged; ++k) {
    printf("%s[%d, ", k ? ", " : "", logged[k].status);
    json_string(logged[k].category);
    printf(", ");
    json_string(logged[k].text);
    printf("]");
  }
  printf("]}\n");
  fflush(stdout);
}

/* -- instances, states, blobs --------------------------------------------------------------------- */

typedef struct {
  int lib, version, me;
  void* c;
  double start, stop, tol;
  int stop_defined, tol_defined;
} instance;

typedef struct {
  unsigned char* data;
  size_t size;
} blob;

static instance instances[SLOTS];
static instance* cur = &instances[0];
static void* states[SLOTS];
static blob blobs[SLOTS];
static const fmi2CallbackFunctions CALLBACKS = {logger2, calloc, free, NULL, NULL};

static int slot(const char* text) {
  int k = atoi(text);
  return k >= 0 && k < SLOTS ? k : 0;
}

/* The bytes of TEXT ("s:abc" or "x:61ff"), into out (NUL-terminated). */
static const char* decode_text(const char* text, char* out, size_t size) {
  size_t n = 0;
  unsigned v;
  if (!strncmp(text, "x:", 2)) {
    for (text += 2; text[0] && text[1] && n + 1 < size && sscanf(text, "%2x", &v) == 1; text += 2) out[n++] = (char) v;
    out[n] = 0;
    return out;
  }
  snprintf(out, size, "%s", strncmp(text, "s:", 2) ? text : text + 2);
  return out;
}

/* -- the commands ----------------------------------------------------------------------------------- */

static int instantiate(char** t, int n, int version) {
  instance* in;
  int me, logging;
  if (n < 7) return -1;
  in = &instances[slot(t[1])];
  memset(in, 0, sizeof *in);
  in->lib = slot(t[2]);
  in->version = version;
  me = !strcmp(t[3], "me");
  in->me = me;
  logging = n > 7 && !strcmp(t[7], "log");
  cur = in;
  if (!libs[in->lib]) return -1;
  if (version == 2)
    in->c = FN(fmi2InstantiateTYPE, "fmi2Instantiate")(t[4], me ? fmi2ModelExchange : fmi2CoSimulation, t[5], t[6],
                                                         &CALLBACKS, fmi2False, logging);
  else if (me)
    in->c = FN(fmi3InstantiateModelExchangeTYPE, "fmi3InstantiateModelExchange")(t[4], t[5], t[6], fmi3False, logging,
                                                                                 NULL, logger3);
  else
    in->c = FN(fmi3InstantiateCoSimulationTYPE, "fmi3InstantiateCoSimulation")(t[4], t[5], t[6], fmi3False, logging,
                                                                               fmi3False, fmi3False, NULL, 0, NULL,
                                                                               logger3, NULL);
  value(in->c != NULL);
  return in->c ? 0 : -1;
}

static int parse_vrs(char** t, int n, unsigned* vr) {
  int k;
  for (k = 0; k < n && k < MAX_VALUES; ++k) vr[k] = (unsigned) strtoul(t[k], NULL, 10);
  return k;
}

static int set_reals(char** t, int n) {
  unsigned vr[MAX_VALUES];
  double v[MAX_VALUES];
  int k, m = 0, n_in;
  while (m + 1 < n && strcmp(t[m + 1], "=")) ++m;
  parse_vrs(t + 1, m, vr);
  n_in = n - m - 2 > 0 ? n - m - 2 : 0; /* FMI 3.0: as many values as given (arrays have several) */
  for (k = 0; k < n_in && k < MAX_VALUES; ++k) v[k] = strtod(t[m + 2 + k], NULL);
  if (cur->version == 2) return FN(fmi2SetRealTYPE, "fmi2SetReal")(cur->c, vr, (size_t) m, v);
  return FN(fmi3SetFloat64TYPE, "fmi3SetFloat64")(cur->c, vr, (size_t) m, v, (size_t) n_in);
}

static int get_reals(char** t, int n) {
  unsigned vr[MAX_VALUES];
  double v[MAX_VALUES];
  int m = n - 1, k, n_out, st;
  if (m >= 2 && !strcmp(t[n - 2], "nvalues")) m -= 2;
  parse_vrs(t + 1, m, vr);
  n_out = m < n - 1 ? atoi(t[n - 1]) : m;
  if (n_out > MAX_VALUES) n_out = MAX_VALUES;
  if (cur->version == 2) st = FN(fmi2GetRealTYPE, "fmi2GetReal")(cur->c, vr, (size_t) m, v);
  else st = FN(fmi3GetFloat64TYPE, "fmi3GetFloat64")(cur->c, vr, (size_t) m, v, (size_t) n_out);
  for (k = 0; st <= 1 && k < n_out; ++k) value(v[k]);
  return st;
}

static char text_in[TEXT_MAX];
static const char* text_out[1];

static int strings(char** t, int n, int set) {
  unsigned vr;
  const char* text;
  int st;
  if (n < 2 + set) return -1;
  vr = (unsigned) strtoul(t[1], NULL, 10);
  if (set) {
    text = decode_text(t[2], text_in, sizeof text_in);
    if (cur->version == 2) return FN(fmi2SetStringTYPE, "fmi2SetString")(cur->c, &vr, 1, &text);
    return FN(fmi3SetStringTYPE, "fmi3SetString")(cur->c, &vr, 1, &text, 1);
  }
  text_out[0] = NULL;
  if (cur->version == 2) st = FN(fmi2GetStringTYPE, "fmi2GetString")(cur->c, &vr, 1, text_out);
  else st = FN(fmi3GetStringTYPE, "fmi3GetString")(cur->c, &vr, 1, text_out, 1);
  strings_out[n_strings++] = text_out[0];
  return st;
}

static int do_step(double t, double h) {
  fmi3Boolean event = fmi3False, terminate = fmi3False, early = fmi3False;
  fmi3Float64 last = NAN;
  int st;
  if (cur->version == 2) return FN(fmi2DoStepTYPE, "fmi2DoStep")(cur->c, t, h, fmi2True);
  st = FN(fmi3DoStepTYPE, "fmi3DoStep")(cur->c, t, h, fmi3True, &event, &terminate, &early, &last);
  value(last);
  return st;
}

/* N steps from T0 (t_k = T0 + k H), reading the VRs after each; stops at the first status above warning. */
static int steps(char** t, int n) {
  unsigned vr[MAX_VALUES];
  double v[MAX_VALUES], t0 = strtod(t[2], NULL), h = strtod(t[3], NULL);
  long k, count = strtol(t[1], NULL, 10);
  int m = parse_vrs(t + 4, n - 4, vr), j, st = 0;
  for (k = 0; k < count && st <= 1; ++k) {
    double tk = t0 + (double) k * h;
    int before = n_values;
    st = do_step(tk, t0 + (double) (k + 1) * h - tk);
    n_values = before; /* FMI 3.0's lastSuccessfulTime is not kept per step */
    if (st > 1) break;
    if (m == 0) continue;
    st = cur->version == 2 ? FN(fmi2GetRealTYPE, "fmi2GetReal")(cur->c, vr, (size_t) m, v)
                           : FN(fmi3GetFloat64TYPE, "fmi3GetFloat64")(cur->c, vr, (size_t) m, v, (size_t) m);
    for (j = 0; j < m; ++j) value(v[j]);
  }
  return st;
}

static int set_time(double t) {
  if (cur->version == 2) return FN(fmi2SetTimeTYPE, "fmi2SetTime")(cur->c, t);
  return FN(fmi3SetTimeTYPE, "fmi3SetTime")(cur->c, t);
}

static int states_io(const char* what, double* x, size_t nx) {
  int v2 = cur->version == 2;
  if (!strcmp(what, "getx"))
    return v2 ? FN(fmi2GetContinuousStatesTYPE, "fmi2GetContinuousStates")(cur->c, x, nx)
              : FN(fmi3GetContinuousStatesTYPE, "fmi3GetContinuousStates")(cur->c, x, nx);
  if (!strcmp(what, "setx"))
    return v2 ? FN(fmi2SetContinuousStatesTYPE, "fmi2SetContinuousStates")(cur->c, x, nx)
              : FN(fmi3SetContinuousStatesTYPE, "fmi3SetContinuousStates")(cur->c, x, nx);
  return v2 ? FN(fmi2GetDerivativesTYPE, "fmi2GetDerivatives")(cur->c, x, nx)
            : FN(fmi3GetContinuousStateDerivativesTYPE, "fmi3GetContinuousStateDerivatives")(cur->c, x, nx);
}

static int completed(void) {
  fmi2Boolean e2 = fmi2False, s2 = fmi2False;
  fmi3Boolean e3 = fmi3False, s3 = fmi3False;
  if (cur->version == 2)
    return FN(fmi2CompletedIntegratorStepTYPE, "fmi2CompletedIntegratorStep")(cur->c, fmi2True, &e2, &s2);
  return FN(fmi3CompletedIntegratorStepTYPE, "fmi3CompletedIntegratorStep")(cur->c, fmi3True, &e3, &s3);
}

/* N explicit Euler steps of the continuous states (NX of them) from T0, reading the VRs after each. */
static int euler(char** t, int n) {
  static double x[MAX_VALUES], dx[MAX_VALUES];
  unsigned vr[MAX_VALUES];
  double v[MAX_VALUES], t0 = strtod(t[2], NULL), h = strtod(t[3], NULL);
  long k, count = strtol(t[1], NULL, 10);
  size_t nx = (size_t) atoi(t[4]), i;
  int m = parse_vrs(t + 5, n - 5, vr), j, st = 0;
  for (k = 0; k < count && st <= 1; ++k) {
    st = set_time(t0 + (double) k * h);
    if (st <= 1) st = states_io("getx", x, nx);
    if (st <= 1) st = states_io("getdx", dx, nx);
    for (i = 0; i < nx; ++i) x[i] += h * dx[i];
    if (st <= 1) st = set_time(t0 + (double) (k + 1) * h);
    if (st <= 1) st = states_io("setx", x, nx);
    if (st <= 1) st = completed();
    if (st > 1 || m == 0) continue;
    st = cur->version == 2 ? FN(fmi2GetRealTYPE, "fmi2GetReal")(cur->c, vr, (size_t) m, v)
                           : FN(fmi3GetFloat64TYPE, "fmi3GetFloat64")(cur->c, vr, (size_t) m, v, (size_t) m);
    for (j = 0; j < m; ++j) value(v[j]);
  }
  return st;
}

static int mode(const char* what) {
  int v2 = cur->version == 2;
  if (!strcmp(what, "eventmode")) {
    if (v2) return FN(fmi2EnterEventModeTYPE, "fmi2EnterEventMode")(cur->c);
    return FN(fmi3EnterEventModeTYPE, "fmi3EnterEventMode")(cur->c);
  }
  if (!strcmp(what, "ctmode")) {
    if (v2) return FN(fmi2EnterContinuousTimeModeTYPE, "fmi2EnterContinuousTimeMode")(cur->c);
    return FN(fmi3EnterContinuousTimeModeTYPE, "fmi3EnterContinuousTimeMode")(cur->c);
  }
  if (!strcmp(what, "enterstep")) return FN(fmi3EnterStepModeTYPE, "fmi3EnterStepMode")(cur->c);
  if (!strcmp(what, "completed")) return completed();
  if (v2) {
    fmi2EventInfo info;
    return FN(fmi2NewDiscreteStatesTYPE, "fmi2NewDiscreteStates")(cur->c, &info);
  } else {
    fmi3Boolean a, b, c, d, e;
    fmi3Float64 next;
    return FN(fmi3UpdateDiscreteStatesTYPE, "fmi3UpdateDiscreteStates")(cur->c, &a, &b, &c, &d, &e, &next);
  }
}

static int continuous(char** t, int n) {
  static double x[MAX_VALUES];
  size_t nx = (size_t) atoi(t[1]), k;
  int st;
  if (nx > MAX_VALUES) nx = MAX_VALUES;
  for (k = 0; !strcmp(t[0], "setx") && k < nx && (int) k + 2 < n; ++k) x[k] = strtod(t[k + 2], NULL);
  st = states_io(t[0], x, nx);
  for (k = 0; strcmp(t[0], "setx") && st <= 1 && k < nx; ++k) value(x[k]);
  return st;
}

static int status_query(char** t, int n) {
  int kind = atoi(t[1]), null = n > 2 && !strcmp(t[2], "null"), st;
  if (!strcmp(t[0], "realstatus")) {
    fmi2Real v = NAN;
    st = FN(fmi2GetRealStatusTYPE, "fmi2GetRealStatus")(cur->c, (fmi2StatusKind) kind, null ? NULL : &v);
    value(v);
  } else {
    fmi2Boolean v = 7;
    st = FN(fmi2GetBooleanStatusTYPE, "fmi2GetBooleanStatus")(cur->c, (fmi2StatusKind) kind, null ? NULL : &v);
    value((double) v);
  }
  return st;
}

static int fmu_state(char** t, int n) {
  int s = slot(t[1]), v2 = cur->version == 2;
  (void) n;
  if (!strcmp(t[0], "getstate"))
    return v2 ? FN(fmi2GetFMUstateTYPE, "fmi2GetFMUstate")(cur->c, &states[s])
              : FN(fmi3GetFMUStateTYPE, "fmi3GetFMUState")(cur->c, &states[s]);
  if (!strcmp(t[0], "setstate"))
    return v2 ? FN(fmi2SetFMUstateTYPE, "fmi2SetFMUstate")(cur->c, states[s])
              : FN(fmi3SetFMUStateTYPE, "fmi3SetFMUState")(cur->c, states[s]);
  return v2 ? FN(fmi2FreeFMUstateTYPE, "fmi2FreeFMUstate")(cur->c, &states[s])
            : FN(fmi3FreeFMUStateTYPE, "fmi3FreeFMUState")(cur->c, &states[s]);
}

static int serialize(char** t, int n) {
  int s = slot(t[1]), v2 = cur->version == 2, st;
  blob* b = &blobs[slot(t[2])];
  size_t size = 0, given;
  st = v2 ? FN(fmi2SerializedFMUstateSizeTYPE, "fmi2SerializedFMUstateSize")(cur->c, states[s], &size)
          : FN(fmi3SerializedFMUStateSizeTYPE, "fmi3SerializedFMUStateSize")(cur->c, states[s], &size);
  if (st > 1) return st;
  value((double) size);
  given = n > 3 && strcmp(t[3], "null") ? (size_t) strtoul(t[3], NULL, 10) : size;
  free(b->data);
  b->data = (unsigned char*) calloc(given > size ? given : size, 1);
  b->size = given;
  st = v2 ? FN(fmi2SerializeFMUstateTYPE, "fmi2SerializeFMUstate")(cur->c, states[s],
                                                                   n > 3 && !strcmp(t[3], "null") ? NULL
                                                                   : (fmi2Byte*) b->data, given)
          : FN(fmi3SerializeFMUStateTYPE, "fmi3SerializeFMUState")(cur->c, states[s],
                                                                   n > 3 && !strcmp(t[3], "null") ? NULL
                                                                   : (fmi3Byte*) b->data, given);
  return st;
}

static int deserialize(char** t) {
  blob* b = &blobs[slot(t[1])];
  int s = slot(t[2]);
  if (cur->version == 2)
    return FN(fmi2DeSerializeFMUstateTYPE, "fmi2DeSerializeFMUstate")(cur->c, (const fmi2Byte*) b->data, b->size,
                                                                       &states[s]);
  return FN(fmi3DeserializeFMUStateTYPE, "fmi3DeserializeFMUState")(cur->c, (const fmi3Byte*) b->data, b->size,
                                                                    &states[s]);
}

static int blob_command(char** t, int n) {
  blob* b = &blobs[slot(t[1])];
  FILE* f;
  long size;
  if (n < 4) return -1;
  if (!strcmp(t[2], "cut")) {
    size_t cut = (size_t) strtoul(t[3], NULL, 10);
    b->size = cut < b->size ? b->size - cut : 0;
  } else if (!strcmp(t[2], "grow")) {
    size_t more = (size_t) strtoul(t[3], NULL, 10);
    b->data = (unsigned char*) realloc(b->data, b->size + more + 1);
    memset(b->data + b->size, 0, more);
    b->size += more;
  } else if (!strcmp(t[2], "flip") && n > 4) {
    size_t at = (size_t) strtoul(t[3], NULL, 10);
    if (at < b->size) b->data[at] ^= (unsigned char) strtoul(t[4], NULL, 0);
  } else if (!strcmp(t[2], "save") && (f = fopen(t[3], "wb"))) {
    fwrite(b->data, 1, b->size, f);
    fclose(f);
  } else if (!strcmp(t[2], "load") && (f = fopen(t[3], "rb"))) {
    fseek(f, 0, SEEK_END);
    size = ftell(f);
    fseek(f, 0, SEEK_SET);
    free(b->data);
    b->data = (unsigned char*) malloc((size_t) size + 1);
    b->size = fread(b->data, 1, (size_t) size, f);
    fclose(f);
  } else {
    return -1;
  }
  value((double) b->size);
  return 0;
}

static int life_cycle(const char* what) {
  int v2 = cur->version == 2;
  if (!strcmp(what, "setup")) return 0;
  if (!strcmp(what, "enter")) {
    if (v2) return FN(fmi2EnterInitializationModeTYPE, "fmi2EnterInitializationMode")(cur->c);
    return FN(fmi3EnterInitializationModeTYPE, "fmi3EnterInitializationMode")(
        cur->c, cur->tol_defined, cur->tol, cur->start, cur->stop_defined, cur->stop);
  }
  if (!strcmp(what, "exit"))
    return v2 ? FN(fmi2ExitInitializationModeTYPE, "fmi2ExitInitializationMode")(cur->c)
              : FN(fmi3ExitInitializationModeTYPE, "fmi3ExitInitializationMode")(cur->c);
  if (!strcmp(what, "terminate"))
    return v2 ? FN(fmi2TerminateTYPE, "fmi2Terminate")(cur->c) : FN(fmi3TerminateTYPE, "fmi3Terminate")(cur->c);
  if (!strcmp(what, "reset"))
    return v2 ? FN(fmi2ResetTYPE, "fmi2Reset")(cur->c) : FN(fmi3ResetTYPE, "fmi3Reset")(cur->c);
  if (v2) FN(fmi2FreeInstanceTYPE, "fmi2FreeInstance")(cur->c);
  else FN(fmi3FreeInstanceTYPE, "fmi3FreeInstance")(cur->c);
  cur->c = NULL;
  return 0;
}

/* One command; its status (-1 when the command itself is wrong or has no FMI status). */
static int run(char** t, int n) {
  const char* c = t[0];
  if (!strcmp(c, "load")) {
    libs[slot(t[1])] = n > 2 ? open_library(t[2]) : NULL;
    return libs[slot(t[1])] ? 0 : -1;
  }
  if (!strcmp(c, "fmi2") || !strcmp(c, "fmi3")) return instantiate(t, n, c[3] - '0');
  if (!strcmp(c, "use")) {
    cur = &instances[slot(t[1])];
    return 0;
  }
  if (!strcmp(c, "blob")) return blob_command(t, n);
  if (!cur->c && strcmp(c, "free")) return -1;
  if (!strcmp(c, "setup") && n >= 6) {
    cur->tol_defined = atoi(t[1]), cur->tol = strtod(t[2], NULL), cur->start = strtod(t[3], NULL);
    cur->stop_defined = atoi(t[4]), cur->stop = strtod(t[5], NULL);
    if (cur->version == 3) return 0;
    return FN(fmi2SetupExperimentTYPE, "fmi2SetupExperiment")(cur->c, cur->tol_defined, cur->tol, cur->start,
                                                              cur->stop_defined, cur->stop);
  }
  if (!strcmp(c, "enter") || !strcmp(c, "exit") || !strcmp(c, "terminate") || !strcmp(c, "reset") ||
      !strcmp(c, "free"))
    return cur->c ? life_cycle(c) : -1;
  if (!strcmp(c, "setr")) return set_reals(t, n);
  if (!strcmp(c, "getr")) return get_reals(t, n);
  if (!strcmp(c, "sets") || !strcmp(c, "gets")) return strings(t, n, c[0] == 's' && c[1] == 'e');
  if (!strcmp(c, "step") && n >= 3) return do_step(strtod(t[1], NULL), strtod(t[2], NULL));
  if (!strcmp(c, "steps") && n >= 4) return steps(t, n);
  if (!strcmp(c, "settime") && n >= 2) return set_time(strtod(t[1], NULL));
  if (!strcmp(c, "euler") && n >= 5) return euler(t, n);
  if (!strcmp(c, "getx") || !strcmp(c, "setx") || !strcmp(c, "getdx")) return n >= 2 ? continuous(t, n) : -1;
  if (!strcmp(c, "realstatus") || !strcmp(c, "boolstatus")) return n >= 2 ? status_query(t, n) : -1;
  if (!strcmp(c, "getstate") || !strcmp(c, "setstate") || !strcmp(c, "freestate")) return n >= 2 ? fmu_state(t, n) : -1;
  if (!strcmp(c, "serialize") && n >= 3) return serialize(t, n);
  if (!strcmp(c, "deserialize") && n >= 3) return deserialize(t);
  return mode(c);
}

static int tokens(char* line, char** t) {
  int n = 0;
  char* p = strtok(line, " \t\r\n");
  for (; p && n < MAX_TOKENS; p = strtok(NULL, " \t\r\n")) t[n++] = p;
  return n;
}

static char text[1 << 20];
static char command[1 << 20];
static char* t[MAX_TOKENS];

int main(int argc, char** argv) {
  FILE* in = argc > 1 ? fopen(argv[1], "r") : stdin;
  int line = 0, n, st;
  double t0;
  if (!in) {
    fprintf(stderr, "usage: script_host [SCRIPT] (commands on stdin without one)\n");
    return 2;
  }
#ifdef SCRIPT_HOST_PYTHON
  Py_Initialize();
#endif
  while (fgets(text, sizeof text, in)) {
    ++line;
    strcpy(command, text);
    if ((n = tokens(text, t)) == 0 || t[0][0] == '#') continue;
    n_values = n_strings = n_logged = 0;
    command[strcspn(command, "\r\n")] = 0;
    t0 = now();
    st = run(t, n);
    print_result(line, command, st, now() - t0);
  }
#ifdef SCRIPT_HOST_PYTHON
  Py_FinalizeEx();
#endif
  return 0;
}
