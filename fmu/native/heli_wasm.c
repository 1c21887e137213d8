/* The WebAssembly entry points of the native heli rotor FMU's model core, for the browser page
   of `heli fly` (fmu/native/wasm.py builds it; viewer/fly/web/worker.js calls it).

   One instance of the model core (heli_core.h) driven as an FMI 2.0 co-simulation master would
   drive the FMU: set the scene and the inputs, initialise, step with heli_do_step, read values
   by value reference. So a page's run is the FMU's run, and a step that diverges ends with the
   FMU's own message (hw_message). Beyond the FMI calls, the page needs two things of the
   core: to start from a state computed when the page was written (hw_load: a periodic trim at
   another speed than the scene's own) and the body poses for the 3D view (hw_poses: the model's
   generated `poses` function, heli_wasm_data.c). Both need the instance's state, so this file
   includes the core's source instead of linking it.

   Arrays cross the boundary through one buffer of doubles (hw_buffer) and strings through one
   of chars (hw_text). Every function returns the core's status (HELI_OK .. HELI_FATAL) unless
   it says otherwise. */
#include "heli_core.c"

#define HW_EXPORT(name) __attribute__((export_name(#name), visibility("default")))
#define HW_BUFFER 8192
#define HW_TEXT 4096

typedef struct {
  heli_eval_fn poses;
  heli_work_fn work;
  int n;
} heli_wasm_poses;

extern const heli_wasm_poses heli_wasm_poses_of[]; /* by model group (heli_wasm_data.c) */

static heli_instance* instance;
static double buffer[HW_BUFFER];
static char text[HW_TEXT], message[HW_TEXT];
static int message_status;

/* The core's logger: keep the latest message above OK (a discarded step's reason). */
static void keep(void* env, const char* name, int status, const char* category, const char* what) {
  (void) env, (void) name, (void) category;
  if (status == HELI_OK) return;
  message_status = status;
  copy_text(message, what, sizeof message);
}

HW_EXPORT(hw_buffer) double* hw_buffer(void) { return buffer; }

HW_EXPORT(hw_buffer_size) int hw_buffer_size(void) { return HW_BUFFER; }

HW_EXPORT(hw_text) char* hw_text(void) { return text; }

HW_EXPORT(hw_text_size) int hw_text_size(void) { return HW_TEXT; }

/* The latest message above OK ("" if none since hw_open) and its status (hw_message_status). */
HW_EXPORT(hw_message) const char* hw_message(void) { return message; }

HW_EXPORT(hw_message_status) int hw_message_status(void) { return message_status; }

HW_EXPORT(hw_free) void hw_free(void) {
  heli_free(instance);
  instance = NULL;
}

/* A fresh co-simulation instance (the previous one freed). */
HW_EXPORT(hw_open) int hw_open(void) {
  hw_free();
  message[0] = 0;
  message_status = HELI_OK;
  instance = heli_instantiate("fmi2", "page", HELI_COSIMULATION, M->guid, keep, NULL, 0);
  return instance ? HELI_OK : HELI_FATAL;
}

HW_EXPORT(hw_set_real) int hw_set_real(int vr, double value) {
  if (!heli_lookup(instance, "fmi2SetReal", (unsigned) vr, "Real")) return HELI_ERROR;
  return heli_set_real(instance, "fmi2SetReal", vr, value);
}

/* Set the String parameter vr to the text in hw_text. */
HW_EXPORT(hw_set_string) int hw_set_string(int vr) {
  if (!heli_lookup(instance, "fmi2SetString", (unsigned) vr, "String")) return HELI_ERROR;
  return heli_set_string(instance, "fmi2SetString", vr, text);
}

/* Initialise at time 0 (a fresh instance's start time: a flight has no stop time to set up) with
   the values set so far in force. */
HW_EXPORT(hw_start) int hw_start(void) {
  int status = heli_enter_initialization(instance, "fmi2EnterInitializationMode");
  if (status == HELI_OK) status = heli_exit_initialization(instance, "fmi2ExitInitializationMode");
  return status;
}

/* Number of states of the model in use (after hw_start). */
HW_EXPORT(hw_nx) int hw_nx(void) { return group_of(instance)->nx; }

/* Replace the state by the first hw_nx() entries of hw_buffer (after hw_start, at time 0). */
HW_EXPORT(hw_load) int hw_load(void) {
  int i, n = hw_nx();
  if (instance->s.phase != STEPPING) return heli_refuse(instance, "hw_load", "call hw_start first");
  for (i = 0; i < n; ++i)
    if (!isfinite(buffer[i])) return heli_refuse(instance, "hw_load", "a state is not finite");
  memcpy(instance->s.x, buffer, sizeof(double) * (size_t) n);
  memset(instance->s.comp, 0, sizeof instance->s.comp);
  invalidate(instance);
  return HELI_OK;
}

/* One communication step from t to t + dt (sub-stepped by the FMU's max_step). */
HW_EXPORT(hw_step) int hw_step(double t, double dt) { return heli_do_step(instance, "fmi2DoStep", t, dt); }

/* n steps of dt from the instance's time (t_k = t0 + k dt); the first status above OK ends them.
   For the benchmark: the same loop runs natively and in WebAssembly. */
HW_EXPORT(hw_run) int hw_run(int n, double dt) {
  int k, status = HELI_OK;
  double t0 = heli_time(instance);
  for (k = 0; k < n && status == HELI_OK; ++k) status = hw_step(t0 + k * dt, dt);
  return status;
}

HW_EXPORT(hw_time) double hw_time(void) { return heli_time(instance); }

/* Values of the n value references in hw_buffer[0..n) (as doubles), written in their place. */
HW_EXPORT(hw_get) int hw_get(int n) {
  int k, status = HELI_OK;
  double value;
  for (k = 0; k < n && k < HW_BUFFER && status == HELI_OK; ++k) {
    int vr = (int) buffer[k];
    if (!heli_lookup(instance, "fmi2GetReal", (unsigned) vr, "Real")) return HELI_ERROR;
    status = heli_get_real(instance, "fmi2GetReal", vr, &value);
    buffer[k] = value;
  }
  return status;
}

/* The state into hw_buffer; returns hw_nx(). */
HW_EXPORT(hw_state) int hw_state(void) {
  memcpy(buffer, instance->s.x, sizeof(double) * (size_t) hw_nx());
  return hw_nx();
}

/* Body poses at the current state into hw_buffer: per body its origin (3, m) and rotation
   body -> world (3 x 3, row by row), world frame; returns their number of values (-1: failed). */
HW_EXPORT(hw_poses) int hw_poses(void) {
  const heli_wasm_poses* f = &heli_wasm_poses_of[M->scenes[instance->s.scene].group];
  static const double* arg[8];
  static double* res[4];
  static heli_int iw[256];
  static double w[HW_BUFFER];
  double t = heli_time(instance);
  heli_int n[4];
  f->work(&n[0], &n[1], &n[2], &n[3]);
  if (n[0] > 8 || n[1] > 4 || n[2] > 256 || n[3] > HW_BUFFER || f->n > HW_BUFFER) return -1;
  fill_params(instance, instance->s.scene, instance->p);
  arg[0] = instance->s.x;
  arg[1] = &t;
  arg[2] = instance->p;
  res[0] = buffer;
  return f->poses(arg, res, iw, w, 0) ? -1 : f->n;
}
