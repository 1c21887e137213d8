/*
 * FMI 2.0 co-simulation front end for an FMU built with pythonfmu.
 *
 * This library is binaries/linux64/<modelIdentifier>.so of the FMU. pythonfmu's own
 * library sits next to it as binaries/linux64/pythonfmu/<modelIdentifier>.so and is loaded
 * (RTLD_LOCAL | RTLD_NOW) at the first fmi2Instantiate; every call is checked here and then
 * forwarded to it. What this adds to pythonfmu's wrapper:
 *
 *  - fmuResourceLocation is percent-decoded completely (file:///p, file:/p,
 *    file://localhost/p; a plain absolute path is taken as it is), the folder must exist;
 *  - a host that is not a Python process gets NULL and a message, not a crash;
 *  - the slave's messages are forwarded with status >= warning always, ok/info ones only
 *    when the host turned logging on (and the category is selected);
 *  - the worst status the slave logged during a call raises the call's status: an error
 *    logged during fmi2SetReal gives fmi2Error, a discard gives fmi2Discard;
 *  - after pythonfmu returned fmi2Fatal (its instance has dropped its Python objects) the
 *    instance is dead: every later call answers fmi2Error without calling pythonfmu, and
 *    fmi2FreeInstance leaves it allocated (deleting it would crash);
 *  - NULL instance or arrays, and calls out of the order of the FMI 2.0 state machine,
 *    give fmi2Error and a message naming the call;
 *  - the GUID given to fmi2Instantiate must be this FMU's (HELI_GUID, compiled in: derived
 *    from the content the FMU was built from), and fmi2SetDebugLogging accepts only the log
 *    categories of the model description;
 *  - fmi2GetBooleanStatus(fmi2Terminated) is false: this FMU never asks the master to end
 *    (pythonfmu answers true after any fmi2Discard);
 *  - FMU states are this library's records around pythonfmu's: fmi2GetFMUstate into an
 *    existing state releases pythonfmu's old one (pythonfmu would leak it), a state carries
 *    the instance's phase, which fmi2SetFMUstate restores, and fmi2SerializeFMUstate refuses
 *    a buffer smaller than fmi2SerializedFMUstateSize;
 *  - at the process's exit, pythonfmu's hold on its Python state is released before its own
 *    exit handlers run: pythonfmu 0.7.0 releases it twice otherwise (its static destructor,
 *    then its library destructor, on the destroyed shared_ptr), a heap corruption that
 *    aborts a C host at exit (upstream PythonFMU #211/#213, unreleased).
 *
 * Messages are FMI format strings: a '%' in a message text is written as "%%".
 * The FMI 2.0 headers come from the build machine (fmpy's c-code folder).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "fmi2Functions.h"

#ifndef HELI_GUID
#error "compile with -DHELI_GUID='\"{...}\"' (the GUID of the FMU's model description)"
#endif
#define INNER_DIR "pythonfmu"
#define STATE_MAGIC 0x53484d53u /* a state record of this library */
#define BLOB_TAG "HELISHIM" /* first bytes of a serialized state of this library */
#define NATIVE_HINT "For a host without Python use the native FMU (heli fmu build --native)"
#define TEXT_MAX 4096

/* -- pythonfmu's library ----------------------------------------------------------------- */

typedef struct {
    fmi2GetVersionTYPE *getVersion;
    fmi2SetDebugLoggingTYPE *setDebugLogging;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *freeInstance;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2EnterInitializationModeTYPE *enterInitializationMode;
    fmi2ExitInitializationModeTYPE *exitInitializationMode;
    fmi2TerminateTYPE *terminate;
    fmi2ResetTYPE *reset;
    fmi2GetRealTYPE *getReal;
    fmi2GetIntegerTYPE *getInteger;
    fmi2GetBooleanTYPE *getBoolean;
    fmi2GetStringTYPE *getString;
    fmi2SetRealTYPE *setReal;
    fmi2SetIntegerTYPE *setInteger;
    fmi2SetBooleanTYPE *setBoolean;
    fmi2SetStringTYPE *setString;
    fmi2GetFMUstateTYPE *getFMUstate;
    fmi2SetFMUstateTYPE *setFMUstate;
    fmi2FreeFMUstateTYPE *freeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *serializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *serializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *deSerializeFMUstate;
    fmi2DoStepTYPE *doStep;
    fmi2GetRealStatusTYPE *getRealStatus;
    fmi2GetBooleanStatusTYPE *getBooleanStatus;
} InnerApi;

typedef struct {
    const char *name;
    void **slot;
} InnerSymbol;

static InnerApi api;
static void *api_handle;
static pthread_mutex_t api_lock = PTHREAD_MUTEX_INITIALIZER;

#define SYMBOL(field, fmi_name) {fmi_name, (void **)&api.field}

static const InnerSymbol symbols[] = {
    SYMBOL(getVersion, "fmi2GetVersion"),
    SYMBOL(setDebugLogging, "fmi2SetDebugLogging"),
    SYMBOL(instantiate, "fmi2Instantiate"),
    SYMBOL(freeInstance, "fmi2FreeInstance"),
    SYMBOL(setupExperiment, "fmi2SetupExperiment"),
    SYMBOL(enterInitializationMode, "fmi2EnterInitializationMode"),
    SYMBOL(exitInitializationMode, "fmi2ExitInitializationMode"),
    SYMBOL(terminate, "fmi2Terminate"),
    SYMBOL(reset, "fmi2Reset"),
    SYMBOL(getReal, "fmi2GetReal"),
    SYMBOL(getInteger, "fmi2GetInteger"),
    SYMBOL(getBoolean, "fmi2GetBoolean"),
    SYMBOL(getString, "fmi2GetString"),
    SYMBOL(setReal, "fmi2SetReal"),
    SYMBOL(setInteger, "fmi2SetInteger"),
    SYMBOL(setBoolean, "fmi2SetBoolean"),
    SYMBOL(setString, "fmi2SetString"),
    SYMBOL(getFMUstate, "fmi2GetFMUstate"),
    SYMBOL(setFMUstate, "fmi2SetFMUstate"),
    SYMBOL(freeFMUstate, "fmi2FreeFMUstate"),
    SYMBOL(serializedFMUstateSize, "fmi2SerializedFMUstateSize"),
    SYMBOL(serializeFMUstate, "fmi2SerializeFMUstate"),
    SYMBOL(deSerializeFMUstate, "fmi2DeSerializeFMUstate"),
    SYMBOL(doStep, "fmi2DoStep"),
    SYMBOL(getRealStatus, "fmi2GetRealStatus"),
    SYMBOL(getBooleanStatus, "fmi2GetBooleanStatus"),
};

/* Path of pythonfmu's library: <folder of this library>/pythonfmu/<this library's name>. */
static int inner_path(char *out, size_t n, char *err, size_t errn)
{
    Dl_info self;
    if (!dladdr((void *)&inner_path, &self) || !self.dli_fname) {
        snprintf(err, errn, "cannot find the path of the FMU's own library (dladdr failed)");
        return 0;
    }
    const char *slash = strrchr(self.dli_fname, '/');
    int dir_len = slash ? (int)(slash - self.dli_fname) : 1;
    const char *dir = slash ? self.dli_fname : ".";
    const char *base = slash ? slash + 1 : self.dli_fname;
    if (snprintf(out, n, "%.*s/%s/%s", dir_len, dir, INNER_DIR, base) >= (int)n) {
        snprintf(err, errn, "the path of the FMU's library is too long: %s", self.dli_fname);
        return 0;
    }
    return 1;
}

static int resolve_symbols(void *handle, const char *path, char *err, size_t errn)
{
    for (size_t i = 0; i < sizeof symbols / sizeof symbols[0]; i++) {
        void *f = dlsym(handle, symbols[i].name);
        if (!f) {
            snprintf(err, errn, "pythonfmu's library %s has no function %s", path, symbols[i].name);
            return 0;
        }
        *symbols[i].slot = f;
    }
    const char *version = api.getVersion();
    if (!version || strcmp(version, fmi2Version) != 0) {
        snprintf(err, errn, "pythonfmu's library %s implements FMI %s, not %s", path, version ? version : "(none)",
                 fmi2Version);
        return 0;
    }
    return 1;
}

/* Loads pythonfmu's library once for as long as this library is loaded (see unload_inner). */
/* When the host unloads this library (fmpy does after fmi2FreeInstance), pythonfmu's goes
 * with it, as it did when the host loaded pythonfmu's directly: its own unload hook then runs
 * while the host's Python is alive, not during the process's exit, where it would race with
 * the interpreter's finalisation. */
__attribute__((destructor)) static void unload_inner(void)
{
    pthread_mutex_lock(&api_lock);
    if (api_handle) {
        dlclose(api_handle);
        api_handle = NULL;
    }
    pthread_mutex_unlock(&api_lock);
}

/* pythonfmu's extern "C" finalizePythonInterpreter(): releases its global shared_ptr<PyState>. */
static void (*release_python_state)(void);

/* Runs at exit() before pythonfmu's own exit handlers (registered after its library was
 * loaded, so called before its static destructors), or when the host unloads this library:
 * pythonfmu's global pointer is then empty, and neither its static destructor nor its library
 * destructor releases the state (a second time). */
static void release_before_exit(void)
{
    if (release_python_state) {
        release_python_state();
    }
}

static int load_inner(char *err, size_t errn)
{
    char path[PATH_MAX];
    int ok = 1;
    pthread_mutex_lock(&api_lock);
    if (!api_handle) {
        ok = inner_path(path, sizeof path, err, errn);
        void *handle = ok ? dlopen(path, RTLD_LOCAL | RTLD_NOW) : NULL;
        if (ok && !handle) {
            const char *why = dlerror();
            snprintf(err, errn, "%s", why ? why : path);
            ok = 0;
        }
        if (ok && !resolve_symbols(handle, path, err, errn)) {
            ok = 0;
        }
        if (ok) {
            api_handle = handle;
            *(void **)&release_python_state = dlsym(handle, "finalizePythonInterpreter");
            if (release_python_state && atexit(release_before_exit) != 0) {
                release_python_state = NULL;
            }
        }
    }
    pthread_mutex_unlock(&api_lock);
    return ok;
}

/* -- instances ----------------------------------------------------------------------------- */

typedef enum { INSTANTIATED, INITIALIZATION_MODE, STEPPING, TERMINATED } Phase;

/* The experiment of fmi2SetupExperiment and the time reached: what this library answers and checks
 * itself (pythonfmu neither enforces stopTime nor keeps the last successful time). */
typedef struct {
    double start, stop, time; /* time: of the last step taken (startTime before the first) */
    int stop_defined;
} Experiment;

/* Relative slack of the stop time: a step ending this close to it is no step past it (rounding). */
#define TIME_TOLERANCE 1e-9

typedef struct {
    fmi2Component inner;
    fmi2CallbackFunctions host;     /* the host's callbacks */
    fmi2CallbackFunctions to_inner; /* given to pythonfmu, which keeps a pointer to it */
    char *name;
    fmi2Boolean logging_on;
    char **categories; /* categories the host selected for ok/info messages; none: all */
    size_t n_categories;
    fmi2Status worst; /* worst status pythonfmu logged during the current call */
    int dead;         /* pythonfmu answered fmi2Fatal: never call it again */
    Phase phase;
    Experiment run;   /* start and stop time, and the time of the last step taken */
} Instance;

static const char *status_name(fmi2Status s)
{
    static const char *names[] = {"ok", "warning", "discard", "error", "fatal", "pending"};
    return (unsigned)s < 6 ? names[s] : "unknown";
}

static const char *default_category(fmi2Status s)
{
    static const char *names[] = {"logAll", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                  "logStatusFatal", "logStatusPending"};
    return (unsigned)s < 6 ? names[s] : "logAll";
}

/* Copies text with every '%' doubled: the host reads a message as a format string. */
static void escape_percent(const char *text, char *out, size_t n)
{
    size_t j = 0;
    for (const char *p = text; *p && j + 2 < n; p++) {
        out[j++] = *p;
        if (*p == '%') {
            out[j++] = '%';
        }
    }
    out[j] = '\0';
}

static void emit(const fmi2CallbackFunctions *cb, const char *name, fmi2Status status, const char *category,
                 const char *text)
{
    char escaped[2 * TEXT_MAX];
    const char *cat = category && *category ? category : default_category(status);
    if (cb && cb->logger) {
        escape_percent(text, escaped, sizeof escaped);
        cb->logger(cb->componentEnvironment, name ? name : "", status, cat, escaped);
    } else if (status >= fmi2Warning) {
        fprintf(stderr, "%s [%s] %s: %s\n", name ? name : "", status_name(status), cat, text);
    }
}

/* A message of this library, formatted like printf, always forwarded (its status is >= warning). */
static void tell(const fmi2CallbackFunctions *cb, const char *name, fmi2Status status, const char *fmt, ...)
{
    char text[TEXT_MAX];
    va_list args;
    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    emit(cb, name, status, NULL, text);
}

#define SAY(s, status, ...) tell(&(s)->host, (s)->name, (status), __VA_ARGS__)

static int category_selected(const Instance *s, const char *category)
{
    if (s->n_categories == 0) {
        return 1;
    }
    for (size_t i = 0; i < s->n_categories; i++) {
        if (category && strcmp(s->categories[i], category) == 0) {
            return 1;
        }
    }
    return 0;
}

static int wanted(const Instance *s, fmi2Status status, const char *category)
{
    if (status >= fmi2Warning && status <= fmi2Fatal) {
        return 1;
    }
    return s->logging_on && category_selected(s, category);
}

/* The logger pythonfmu calls: records the worst status, forwards what the host wants.
 * pythonfmu passes the message text without format arguments. */
static void from_inner(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                       fmi2String message, ...)
{
    Instance *s = (Instance *)env;
    (void)name;
    if (!s) {
        return;
    }
    if (status > s->worst && status <= fmi2Fatal) {
        s->worst = status;
    }
    if (wanted(s, status, category)) {
        emit(&s->host, s->name, status, category, message ? message : "");
    }
}

/* The instance for a call, or NULL (the call answers fmi2Error) if it is NULL or dead. */
static Instance *live(fmi2Component c, const char *call)
{
    Instance *s = (Instance *)c;
    if (!s) {
        fprintf(stderr, "%s: called with a NULL fmi2Component\n", call);
        return NULL;
    }
    if (s->dead) {
        SAY(s, fmi2Error, "%s: instance '%s' is unusable since pythonfmu reported fmi2Fatal earlier (see the "
            "messages then); only fmi2FreeInstance is possible", call, s->name);
        return NULL;
    }
    s->worst = fmi2OK;
    return s;
}

/* The status of a forwarded call: the worse of pythonfmu's answer and what was logged. */
static fmi2Status finish(Instance *s, const char *call, fmi2Status status)
{
    fmi2Status result = status;
    if (s->worst > result && status <= fmi2Fatal) {
        result = s->worst;
    }
    if (result == fmi2Fatal) {
        s->dead = 1;
        SAY(s, fmi2Error, "%s: pythonfmu reported fmi2Fatal; instance '%s' is unusable from now on: every "
            "further call except fmi2FreeInstance answers fmi2Error", call, s->name);
    }
    s->worst = fmi2OK;
    return result;
}

static int advanced(fmi2Status status)
{
    return status == fmi2OK || status == fmi2Warning;
}

static const char *phase_name(Phase p)
{
    static const char *names[] = {"instantiated (before fmi2EnterInitializationMode)", "initialization mode",
                                  "stepping (after fmi2ExitInitializationMode)", "terminated"};
    return names[p];
}

/* fmi2Error unless the instance is in one of the phases of the bit mask `allowed`. */
static int in_phase(Instance *s, const char *call, unsigned allowed)
{
    if (allowed & (1u << s->phase)) {
        return 1;
    }
    SAY(s, fmi2Error, "%s: not allowed while instance '%s' is %s", call, s->name, phase_name(s->phase));
    return 0;
}

#define ANY_PHASE 0xFu
#define PHASE(p) (1u << (p))

static int present(Instance *s, const char *call, const void *array, size_t n, const char *what)
{
    if (array || n == 0) {
        return 1;
    }
    SAY(s, fmi2Error, "%s: %s is NULL (with %zu elements)", call, what, n);
    return 0;
}

static int not_null(Instance *s, const char *call, const void *pointer, const char *what)
{
    if (pointer) {
        return 1;
    }
    SAY(s, fmi2Error, "%s: %s is NULL", call, what);
    return 0;
}

static void free_categories(Instance *s)
{
    for (size_t i = 0; i < s->n_categories; i++) {
        free(s->categories[i]);
    }
    free(s->categories);
    s->categories = NULL;
    s->n_categories = 0;
}

static void free_instance_memory(Instance *s)
{
    free_categories(s);
    free(s->name);
    free(s);
}

/* -- fmuResourceLocation --------------------------------------------------------------------- */

static int hex_value(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/* Percent-decodes `in` into `out` (at most as long); 0 on a bad or NUL escape. */
static int percent_decode(const char *in, char *out)
{
    size_t j = 0;
    for (const char *p = in; *p; p++) {
        if (*p != '%') {
            out[j++] = *p;
            continue;
        }
        int hi = hex_value(p[1]), lo = hi < 0 ? -1 : hex_value(p[2]);
        if (hi < 0 || lo < 0 || (hi == 0 && lo == 0)) {
            return 0;
        }
        out[j++] = (char)(hi * 16 + lo);
        p += 2;
    }
    out[j] = '\0';
    return 1;
}

/* The path part of a file URI (file:///p, file:/p, file://localhost/p), or NULL. */
static const char *uri_path(const char *uri)
{
    if (strncasecmp(uri, "file://localhost/", 17) == 0) return uri + 16;
    if (strncasecmp(uri, "file:///", 8) == 0) return uri + 7;
    if (strncasecmp(uri, "file:/", 6) == 0 && uri[6] != '/') return uri + 5;
    return NULL;
}

/* Whether s is UTF-8 as Python's strict decoder takes it: no overlong forms, surrogates or code
 * points beyond U+10FFFF. */
static int valid_utf8(const unsigned char *s)
{
    while (*s) {
        int extra = *s < 0x80 ? 0 : *s >= 0xC2 && *s <= 0xDF ? 1 : (*s >> 4) == 0xE ? 2 : *s >= 0xF0 && *s <= 0xF4 ? 3 : -1;
        unsigned low = 0x80, high = 0xBF; /* the second byte's range */
        if (extra < 0) return 0;
        if (*s == 0xE0) low = 0xA0;
        if (*s == 0xED) high = 0x9F;
        if (*s == 0xF0) low = 0x90;
        if (*s == 0xF4) high = 0x8F;
        for (int k = 1; k <= extra; k++) {
            unsigned lo = k == 1 ? low : 0x80, hi = k == 1 ? high : 0xBF;
            if (s[k] < lo || s[k] > hi) return 0;
        }
        s += 1 + extra;
    }
    return 1;
}

/* The decoded resources folder in `out` (strlen(location) + 1 bytes), else a reason in `err`. */
static int resources_folder(const char *location, char *out, char *err, size_t errn)
{
    const char *path = uri_path(location);
    if (path) {
        if (!percent_decode(path, out)) {
            snprintf(err, errn, "fmuResourceLocation '%s' has an invalid percent escape", location);
            return 0;
        }
    } else if (location[0] == '/') {
        strcpy(out, location); /* a plain path (not a URI): taken as it is */
    } else {
        snprintf(err, errn, "fmuResourceLocation '%s' is not a local file URI (file:///...)", location);
        return 0;
    }
    size_t n = strlen(out);
    while (n > 1 && out[n - 1] == '/') {
        out[--n] = '\0';
    }
    struct stat st;
    if (strstr(out, "%20")) {
        snprintf(err, errn, "the resources folder '%s' contains the characters %%20, which pythonfmu would turn "
                 "into a space; unzip the FMU into a folder without them", out);
    } else if (!valid_utf8((const unsigned char *)out)) {
        snprintf(err, errn, "the resources folder '%s' is not valid UTF-8, which pythonfmu needs", out);
    } else if (stat(out, &st) != 0 || !S_ISDIR(st.st_mode)) {
        snprintf(err, errn, "the resources folder '%s' (from fmuResourceLocation '%s') does not exist", out,
                 location);
    } else {
        return 1;
    }
    return 0;
}

/* -- common functions ------------------------------------------------------------------------ */

const char *fmi2GetTypesPlatform(void)
{
    return fmi2TypesPlatform;
}

const char *fmi2GetVersion(void)
{
    return fmi2Version;
}

static int instantiate_arguments(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                 fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions)
{
    const char *name = instanceName ? instanceName : "";
    if (!functions) {
        fprintf(stderr, "fmi2Instantiate: functions (the callbacks) is NULL\n");
    } else if (!instanceName || !*instanceName) {
        tell(functions, name, fmi2Error, "fmi2Instantiate: instanceName is NULL or empty");
    } else if (fmuType != fmi2CoSimulation) {
        tell(functions, name, fmi2Error, "fmi2Instantiate: instance '%s': this FMU supports co-simulation only "
             "(fmuType = %d)", name, (int)fmuType);
    } else if (!fmuResourceLocation) {
        tell(functions, name, fmi2Error, "fmi2Instantiate: fmuResourceLocation is NULL");
    } else if (!fmuGUID || strcmp(fmuGUID, HELI_GUID) != 0) {
        tell(functions, name, fmi2Error, "fmi2Instantiate: instance '%s': GUID '%s' is not this FMU's '%s' (a model "
             "description of another build?)", name, fmuGUID ? fmuGUID : "(NULL)", HELI_GUID);
    } else {
        return 1;
    }
    return 0;
}

static Instance *new_instance(fmi2String instanceName, const fmi2CallbackFunctions *functions,
                              fmi2Boolean loggingOn)
{
    Instance *s = calloc(1, sizeof *s);
    char *name = strdup(instanceName);
    if (!s || !name) {
        free(s);
        free(name);
        tell(functions, instanceName, fmi2Error, "fmi2Instantiate: out of memory");
        return NULL;
    }
    s->host = *functions;
    s->to_inner = *functions;
    s->to_inner.logger = from_inner;
    s->to_inner.componentEnvironment = s;
    s->name = name;
    s->logging_on = loggingOn;
    s->phase = INSTANTIATED;
    return s;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    char err[TEXT_MAX];
    if (!instantiate_arguments(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions)) {
        return NULL;
    }
    size_t n = strlen(fmuResourceLocation) + 1;
    char *folder = malloc(n), *uri = malloc(n + 7);
    Instance *s = NULL;
    if (!folder || !uri) {
        tell(functions, instanceName, fmi2Error, "fmi2Instantiate: out of memory");
    } else if (!resources_folder(fmuResourceLocation, folder, err, sizeof err)) {
        tell(functions, instanceName, fmi2Error, "fmi2Instantiate: instance '%s': %s", instanceName, err);
    } else if (!load_inner(err, sizeof err)) {
        tell(functions, instanceName, fmi2Error, "fmi2Instantiate: instance '%s': this FMU runs its model in "
             "Python and needs a Python host process with numpy; pythonfmu's library could not be loaded: %s. "
             "%s", instanceName, err, NATIVE_HINT);
    } else if ((s = new_instance(instanceName, functions, loggingOn)) != NULL) {
        snprintf(uri, n + 7, "file://%s", folder);
        /* pythonfmu gets logging on so that every message reaches from_inner, which filters */
        s->inner = api.instantiate(instanceName, fmuType, fmuGUID, uri, &s->to_inner, visible, fmi2True);
        if (!s->inner) {
            SAY(s, fmi2Error, "fmi2Instantiate: pythonfmu could not create instance '%s' (see the messages "
                "before)", instanceName);
            free_instance_memory(s);
            s = NULL;
        }
    }
    free(folder);
    free(uri);
    return s;
}

void fmi2FreeInstance(fmi2Component c)
{
    Instance *s = (Instance *)c;
    if (!s) {
        return;
    }
    if (s->dead) {
        /* pythonfmu's instance has already released its Python objects after the fatal error;
         * deleting it would release them a second time. It is left allocated, and so is this
         * record, whose callbacks it points to. */
        return;
    }
    api.freeInstance(s->inner);
    free_instance_memory(s);
}

static int copy_categories(Instance *s, size_t n, const fmi2String categories[])
{
    char **copy = n ? calloc(n, sizeof *copy) : NULL;
    if (n && !copy) {
        return 0;
    }
    for (size_t i = 0; i < n; i++) {
        if (!categories[i] || !(copy[i] = strdup(categories[i]))) {
            for (size_t k = 0; k < i; k++) free(copy[k]);
            free(copy);
            return 0;
        }
    }
    free_categories(s);
    s->categories = copy;
    s->n_categories = n;
    return 1;
}

static int known_category(const char *name)
{
    static const char *names[] = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                                  "logAll"};
    for (size_t k = 0; name && k < sizeof names / sizeof names[0]; k++) {
        if (strcmp(name, names[k]) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Kept here: pythonfmu keeps logging everything to from_inner, which filters. */
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    const char *call = "fmi2SetDebugLogging";
    Instance *s = live(c, call);
    if (!s || !present(s, call, categories, nCategories, "categories")) {
        return fmi2Error;
    }
    for (size_t k = 0; k < nCategories; k++) {
        if (categories[k] && !known_category(categories[k])) {
            SAY(s, fmi2Error, "%s: unknown log category '%s' (this FMU has logStatusWarning, logStatusDiscard, "
                "logStatusError, logStatusFatal, logAll)", call, categories[k]);
            return fmi2Error;
        }
    }
    if (!copy_categories(s, nCategories, categories)) {
        SAY(s, fmi2Error, "%s: a category is NULL (or out of memory)", call);
        return fmi2Error;
    }
    s->logging_on = loggingOn;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    const char *call = "fmi2SetupExperiment";
    Instance *s = live(c, call);
    if (!s || !in_phase(s, call, PHASE(INSTANTIATED))) {
        return fmi2Error;
    }
    if (stopTimeDefined && !(stopTime >= startTime)) {
        SAY(s, fmi2Error, "%s: stopTime = %.17g s is %s startTime = %.17g s (stopTimeDefined = true)", call, stopTime,
            stopTime != stopTime ? "not a number, with" : "before", startTime);
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.setupExperiment(s->inner, toleranceDefined, tolerance, startTime,
                                                            stopTimeDefined, stopTime));
    if (advanced(status)) {
        s->run = (Experiment){startTime, stopTime, startTime, stopTimeDefined != fmi2False};
    }
    return status;
}

/* The one shape of a phase change: a live instance in phase FROM; pythonfmu's function; phase TO
 * when the call advanced. */
#define FORWARD_TRANSITION(NAME, FIELD, FROM, TO)                      \
    fmi2Status NAME(fmi2Component c)                                   \
    {                                                                  \
        const char *call = #NAME;                                      \
        Instance *s = live(c, call);                                   \
        if (!s || !in_phase(s, call, PHASE(FROM))) {                   \
            return fmi2Error;                                          \
        }                                                              \
        fmi2Status status = finish(s, call, api.FIELD(s->inner));      \
        if (advanced(status)) {                                        \
            s->phase = TO;                                             \
        }                                                              \
        return status;                                                 \
    }

FORWARD_TRANSITION(fmi2EnterInitializationMode, enterInitializationMode, INSTANTIATED, INITIALIZATION_MODE)
FORWARD_TRANSITION(fmi2ExitInitializationMode, exitInitializationMode, INITIALIZATION_MODE, STEPPING)
FORWARD_TRANSITION(fmi2Terminate, terminate, STEPPING, TERMINATED)

fmi2Status fmi2Reset(fmi2Component c)
{
    const char *call = "fmi2Reset";
    Instance *s = live(c, call);
    if (!s) {
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.reset(s->inner));
    if (advanced(status)) {
        s->phase = INSTANTIATED;
        s->run = (Experiment){0.0, 0.0, 0.0, 0};
    }
    return status;
}

/* -- getting and setting values -------------------------------------------------------------- */

#define VALUES_OK(s, call, vr, nvr, value) \
    (present((s), (call), (vr), (nvr), "vr[]") && present((s), (call), (value), (nvr), "value[]"))
#define SETTABLE PHASE(INSTANTIATED) | PHASE(INITIALIZATION_MODE) | PHASE(STEPPING)
#define GETTABLE PHASE(INITIALIZATION_MODE) | PHASE(STEPPING) | PHASE(TERMINATED)

/* The one shape of a value call: a live instance, its arrays present, a phase that allows the
 * call (PHASES); then pythonfmu's function, its status through finish(). */
#define FORWARD_VALUES(NAME, FIELD, VALUE_TYPE, PHASES)                                              \
    fmi2Status NAME(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, VALUE_TYPE value[])  \
    {                                                                                                \
        const char *call = #NAME;                                                                    \
        Instance *s = live(c, call);                                                                 \
        if (!s || !VALUES_OK(s, call, vr, nvr, value) || !in_phase(s, call, PHASES)) {               \
            return fmi2Error;                                                                        \
        }                                                                                            \
        return finish(s, call, api.FIELD(s->inner, vr, nvr, value));                                 \
    }

FORWARD_VALUES(fmi2GetReal, getReal, fmi2Real, GETTABLE)
FORWARD_VALUES(fmi2GetInteger, getInteger, fmi2Integer, GETTABLE)
FORWARD_VALUES(fmi2GetBoolean, getBoolean, fmi2Boolean, GETTABLE)
FORWARD_VALUES(fmi2GetString, getString, fmi2String, GETTABLE)
FORWARD_VALUES(fmi2SetReal, setReal, const fmi2Real, SETTABLE)
FORWARD_VALUES(fmi2SetInteger, setInteger, const fmi2Integer, SETTABLE)
FORWARD_VALUES(fmi2SetBoolean, setBoolean, const fmi2Boolean, SETTABLE)

/* pythonfmu would hand a NULL string to Python as None, and answers fmi2Fatal for bytes that are
 * not UTF-8 (its instance then unusable); both are refused here with fmi2Error. */
static int strings_present(Instance *s, const char *call, const fmi2ValueReference vr[], size_t nvr,
                           const fmi2String value[])
{
    for (size_t i = 0; i < nvr; i++) {
        if (!value[i]) {
            SAY(s, fmi2Error, "%s: value[%zu] (value reference %u) is NULL", call, i, (unsigned)vr[i]);
            return 0;
        }
        if (!valid_utf8((const unsigned char *)value[i])) {
            char hex[3 * 16 + 8] = "";
            size_t k = 0, used = 0;
            for (; value[i][k] && k < 16; k++) {
                used += (size_t)snprintf(hex + used, sizeof hex - used, "%s%02x", k ? " " : "", (unsigned char)value[i][k]);
            }
            if (value[i][k]) strcat(hex, " ...");
            SAY(s, fmi2Error, "%s: value[%zu] (value reference %u) is not UTF-8 text (bytes %s); the value was not set",
                call, i, (unsigned)vr[i], hex);
            return 0;
        }
    }
    return 1;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    const char *call = "fmi2SetString";
    Instance *s = live(c, call);
    if (!s || !VALUES_OK(s, call, vr, nvr, value) || !strings_present(s, call, vr, nvr, value) ||
        !in_phase(s, call, SETTABLE)) {
        return fmi2Error;
    }
    return finish(s, call, api.setString(s->inner, vr, nvr, value));
}

/* -- FMU state ------------------------------------------------------------------------------- */

/* An FMU state of this library: pythonfmu's state, the instance's phase and experiment, and who
 * saved it (this build and instance: a state of another one is refused). */
typedef struct {
    unsigned magic;
    const char *build; /* BUILD of the library that saved it */
    const Instance *owner;
    Phase phase;
    Experiment run;
    fmi2FMUstate inner;
} State;

static const char BUILD[] = HELI_GUID; /* its address tells this library's states from another build's */

/* Header of a serialized state, then pythonfmu's serialized state (the payload) of `payload` bytes,
 * whose FNV-1a digest is `checksum`: a blob of another build (GUID), truncated, extended or with a
 * changed byte is refused. */
typedef struct {
    char tag[8];
    unsigned version;
    int phase;
    char guid[64];
    Experiment run;
    unsigned long long payload, checksum;
} BlobHeader;

#define BLOB_VERSION 2u

static unsigned long long fnv1a(unsigned long long h, const unsigned char *data, size_t size)
{
    for (size_t k = 0; k < size; k++) {
        h = (h ^ data[k]) * 1099511628211ull;
    }
    return h;
}

/* The digest of a blob: its header (checksum field 0) and its payload. */
static unsigned long long checksum(const BlobHeader *header, const unsigned char *payload, size_t size)
{
    BlobHeader h = *header;
    h.checksum = 0;
    return fnv1a(fnv1a(1469598103934665603ull, (const unsigned char *)&h, sizeof h), payload, size);
}

static State *state_of(Instance *s, const char *call, fmi2FMUstate FMUstate)
{
    State *st = (State *)FMUstate;
    if (st && st->magic == STATE_MAGIC && st->build == BUILD && st->owner == s) {
        return st;
    }
    if (st && st->magic == STATE_MAGIC && st->build == BUILD) {
        SAY(s, fmi2Error, "%s: the state given belongs to another instance of this FMU (serialize it there and "
            "deserialize it here to move it)", call);
    } else {
        SAY(s, fmi2Error, "%s: %s is not an FMU state of this FMU%s", call, st ? "the state given" : "the state (NULL)",
            st && st->magic == STATE_MAGIC ? " (it was saved by another FMU library: another build, or another copy)"
                                           : "");
    }
    return NULL;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    const char *call = "fmi2GetFMUstate";
    Instance *s = live(c, call);
    if (!s || !not_null(s, call, FMUstate, "FMUstate (the pointer to the state)")) {
        return fmi2Error;
    }
    State *st = *FMUstate ? state_of(s, call, *FMUstate) : calloc(1, sizeof(State));
    if (!st) {
        if (!*FMUstate) SAY(s, fmi2Error, "%s: out of memory", call);
        return fmi2Error;
    }
    fmi2FMUstate inner = NULL;
    fmi2Status status = finish(s, call, api.getFMUstate(s->inner, &inner));
    if (status > fmi2Warning) {
        if (!*FMUstate) free(st);
        return status;
    }
    if (st->inner) { /* stored into an existing state: pythonfmu's old one goes */
        finish(s, call, api.freeFMUstate(s->inner, &st->inner));
    }
    *st = (State){STATE_MAGIC, BUILD, s, s->phase, s->run, inner};
    *FMUstate = st;
    return status;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    const char *call = "fmi2SetFMUstate";
    Instance *s = live(c, call);
    State *st = s ? state_of(s, call, FMUstate) : NULL;
    if (!st) {
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.setFMUstate(s->inner, st->inner));
    if (advanced(status)) {
        s->phase = st->phase;
        s->run = st->run;
    }
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    const char *call = "fmi2FreeFMUstate";
    Instance *s = live(c, call);
    if (!s || !not_null(s, call, FMUstate, "FMUstate (the pointer to the state)")) {
        return fmi2Error;
    }
    if (!*FMUstate) {
        return fmi2OK; /* nothing to free */
    }
    State *st = state_of(s, call, *FMUstate);
    if (!st) {
        return fmi2Error;
    }
    fmi2Status status = st->inner ? finish(s, call, api.freeFMUstate(s->inner, &st->inner)) : fmi2OK;
    st->magic = 0;
    free(st);
    *FMUstate = NULL;
    return status;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    const char *call = "fmi2SerializedFMUstateSize";
    Instance *s = live(c, call);
    State *st = s ? state_of(s, call, FMUstate) : NULL;
    if (!st || !not_null(s, call, size, "size")) {
        return fmi2Error;
    }
    size_t inner = 0;
    fmi2Status status = finish(s, call, api.serializedFMUstateSize(s->inner, st->inner, &inner));
    *size = sizeof(BlobHeader) + inner;
    return status;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    const char *call = "fmi2SerializeFMUstate";
    Instance *s = live(c, call);
    State *st = s ? state_of(s, call, FMUstate) : NULL;
    size_t inner = 0;
    if (!st || !present(s, call, serializedState, size, "serializedState[]")) {
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.serializedFMUstateSize(s->inner, st->inner, &inner));
    if (status > fmi2Warning) {
        return status;
    }
    if (!serializedState || size < sizeof(BlobHeader) + inner) {
        SAY(s, fmi2Error, "%s: the buffer of %zu bytes%s is too small for the %zu bytes of the state (ask "
            "fmi2SerializedFMUstateSize)", call, size, serializedState ? "" : " (NULL)", sizeof(BlobHeader) + inner);
        return fmi2Error;
    }
    status = finish(s, call, api.serializeFMUstate(s->inner, st->inner, serializedState + sizeof(BlobHeader), inner));
    if (status > fmi2Warning) {
        return status;
    }
    BlobHeader h;
    memset(&h, 0, sizeof h);
    memcpy(h.tag, BLOB_TAG, sizeof h.tag);
    h.version = BLOB_VERSION;
    h.phase = (int)st->phase;
    snprintf(h.guid, sizeof h.guid, "%s", HELI_GUID);
    h.run = st->run;
    h.payload = inner;
    h.checksum = checksum(&h, (const unsigned char *)serializedState + sizeof h, inner);
    memcpy(serializedState, &h, sizeof h);
    return status;
}

/* What is wrong with a serialized state of `size` bytes whose header is h, or NULL. */
static const char *blob_problem(const BlobHeader *h, const fmi2Byte *bytes, size_t size)
{
    if (size < sizeof *h || memcmp(h->tag, BLOB_TAG, sizeof h->tag) != 0) {
        return "it does not start with this FMU's header";
    }
    if (h->version != BLOB_VERSION) return "its format version differs from this FMU's";
    if (strncmp(h->guid, HELI_GUID, sizeof h->guid) != 0) return "it was saved by another FMU (GUID differs)";
    if (h->payload != size - sizeof *h) return "its size does not match its header (truncated or extended)";
    if (h->checksum != checksum(h, (const unsigned char *)bytes + sizeof *h, size - sizeof *h)) {
        return "its checksum does not match (the data are damaged)";
    }
    if (h->phase < INSTANTIATED || h->phase > TERMINATED) return "its phase is not valid";
    return NULL;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    const char *call = "fmi2DeSerializeFMUstate";
    Instance *s = live(c, call);
    BlobHeader h;
    if (!s || !present(s, call, serializedState, size, "serializedState[]") ||
        !not_null(s, call, FMUstate, "FMUstate (the pointer to the state)")) {
        return fmi2Error;
    }
    memset(&h, 0, sizeof h);
    if (size) memcpy(&h, serializedState, size < sizeof h ? size : sizeof h);
    const char *problem = blob_problem(&h, serializedState, size);
    if (problem) {
        SAY(s, fmi2Error, "%s: not a serialized state of this FMU (%zu bytes): %s", call, size, problem);
        return fmi2Error;
    }
    State *st = calloc(1, sizeof(State));
    if (!st) {
        SAY(s, fmi2Error, "%s: out of memory", call);
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.deSerializeFMUstate(s->inner, serializedState + sizeof h,
                                                                size - sizeof h, &st->inner));
    if (status > fmi2Warning) {
        free(st);
        return status;
    }
    *st = (State){STATE_MAGIC, BUILD, s, (Phase)h.phase, h.run, st->inner};
    *FMUstate = st;
    return status;
}

/* -- not supported by this FMU --------------------------------------------------------------- */

static fmi2Status unsupported(fmi2Component c, const char *call)
{
    Instance *s = live(c, call);
    if (s) {
        SAY(s, fmi2Error, "%s: not supported by this FMU", call);
    }
    return fmi2Error;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown_ref, (void)nUnknown, (void)vKnown_ref, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    return unsupported(c, "fmi2CancelStep");
}

/* -- co-simulation --------------------------------------------------------------------------- */

/* Whether the step to `end` goes past the defined stopTime (reported: fmi2Error); a step that is no
 * number at all is the slave's to refuse. */
static int past_stop(Instance *s, const char *call, double from, double end)
{
    const Experiment *r = &s->run;
    double slack = TIME_TOLERANCE * (r->stop > 1.0 || r->stop < -1.0 ? (r->stop > 0 ? r->stop : -r->stop) : 1.0);
    if (!r->stop_defined || end <= r->stop + slack || end != end) {
        return 0;
    }
    SAY(s, fmi2Error, "%s: the step from %.17g s to %.17g s ends past stopTime = %.17g s (stopTimeDefined = true); "
        "the step was not taken", call, from, end, r->stop);
    return 1;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    const char *call = "fmi2DoStep";
    Instance *s = live(c, call);
    if (!s || !in_phase(s, call, PHASE(STEPPING)) ||
        past_stop(s, call, currentCommunicationPoint, currentCommunicationPoint + communicationStepSize)) {
        return fmi2Error;
    }
    fmi2Status status = finish(s, call, api.doStep(s->inner, currentCommunicationPoint, communicationStepSize,
                                                   noSetFMUStatePriorToCurrentPoint));
    if (advanced(status)) {
        s->run.time = currentCommunicationPoint + communicationStepSize;
    }
    return status;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Status *value)
{
    (void)kind, (void)value;
    return unsupported(c, "fmi2GetStatus (no asynchronous steps)");
}

/* fmi2LastSuccessfulTime: the end of the last step taken, startTime before the first (pythonfmu
 * would answer the time of any step asked for, refused or not, and NaN before the first). */
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    const char *call = "fmi2GetRealStatus";
    Instance *s = live(c, call);
    if (!s || !not_null(s, call, value, "value")) {
        return fmi2Error;
    }
    if (kind != fmi2LastSuccessfulTime) {
        SAY(s, fmi2Discard, "%s: status kind %d is not available (fmi2DoStep never returns fmi2Pending)", call,
            (int)kind);
        return fmi2Discard;
    }
    *value = s->run.time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value)
{
    (void)kind, (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}

/* fmi2Terminated: false, always (this FMU never asks the master to end the simulation; a
 * refused step is fmi2Discard and the instance can go on). Other kinds: none. */
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value)
{
    const char *call = "fmi2GetBooleanStatus";
    Instance *s = live(c, call);
    if (!s || !not_null(s, call, value, "value")) {
        return fmi2Error;
    }
    if (kind != fmi2Terminated) {
        SAY(s, fmi2Discard, "%s: status kind %d is not available (fmi2DoStep never returns fmi2Pending)", call,
            (int)kind);
        return fmi2Discard;
    }
    *value = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind kind, fmi2String *value)
{
    (void)kind, (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}
