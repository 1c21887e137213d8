/* The model core of the native heli rotor FMU, independent of the FMI version (the layout of
   the Modelica Reference-FMUs: one model core, thin per-standard wrappers fmi2Functions.c and
   fmi3Functions.c over it).

   Variables are addressed by slot: the FMI 2.0 value reference. Slots 0 .. n_variables-1 are
   the variables of heli_data.c; slot n_variables + k is the derivative of the k-th continuous
   state (model exchange). Every function returns a status HELI_OK .. HELI_FATAL, numerically
   equal to fmi2Status and fmi3Status, and says what went wrong through the logger; `call` is
   the name of the FMI function that a message names. */
#ifndef HELI_CORE_H
#define HELI_CORE_H

#include <stddef.h>

#include "heli_model.h"

enum { HELI_OK, HELI_WARNING, HELI_DISCARD, HELI_ERROR, HELI_FATAL };
enum { HELI_COSIMULATION, HELI_MODEL_EXCHANGE };

/* The wrapper's logger: the message is plain text (no format). */
typedef void (*heli_log_fn)(void* env, const char* instance, int status, const char* category, const char* message);

typedef struct heli_instance heli_instance;

/* -- life cycle ---------------------------------------------------------------------------- */
heli_instance* heli_instantiate(const char* api, const char* name, int kind, const char* token, heli_log_fn log,
                                void* env, int logging_on);
heli_instance* heli_checked(void* component, const char* call); /* NULL (reported) if not an instance */
void heli_free(heli_instance* c);
void heli_report_without(heli_log_fn log, void* env, const char* name, const char* fmt, ...);
int heli_set_debug_logging(heli_instance* c, int on, size_t n, const char* const categories[]);
int heli_setup(heli_instance* c, const char* call, double start_time, int stop_defined, double stop_time);
int heli_enter_initialization(heli_instance* c, const char* call);
int heli_exit_initialization(heli_instance* c, const char* call);
int heli_terminate(heli_instance* c, const char* call);
int heli_reset(heli_instance* c, const char* call);
int heli_kind(const heli_instance* c);
void* heli_environment(const heli_instance* c); /* the wrapper's env given to heli_instantiate */
int heli_no_status(heli_instance* c, const char* call, int kind, const void* value); /* no such status */
int heli_last_successful_time(heli_instance* c, const char* call, double* value);
int heli_terminated_status(heli_instance* c, const char* call, int* value);
double heli_time(const heli_instance* c);

/* -- values ---------------------------------------------------------------------------------- */
int heli_slot_type(int slot); /* HELI_REAL or HELI_STRING; -1 if no such slot */
int heli_lookup(heli_instance* c, const char* call, unsigned slot, const char* type);
int heli_no_values(heli_instance* c, const char* call, size_t n, const void* refs, const void* values);
int heli_settable_now(heli_instance* c, const char* call);
int heli_gettable_now(heli_instance* c, const char* call);
int heli_get_real(heli_instance* c, const char* call, int slot, double* value);
int heli_set_real(heli_instance* c, const char* call, int slot, double value);
const char* heli_get_string(heli_instance* c, int slot);
int heli_set_string(heli_instance* c, const char* call, int slot, const char* value);
int heli_no_such_type(heli_instance* c, const char* call, const char* type, const unsigned refs[], size_t n);
int heli_refuse(heli_instance* c, const char* call, const char* why); /* HELI_ERROR with "call: why" */

/* -- co-simulation --------------------------------------------------------------------------- */
int heli_do_step(heli_instance* c, const char* call, double t, double dt);

/* -- model exchange: continuous states in the FMI 2.0 order (heli_model.me_state) ------------ */
int heli_event_mode(heli_instance* c, const char* call);           /* fmiXEnterEventMode */
int heli_discrete_states(heli_instance* c, const char* call);      /* fmi2NewDiscreteStates, fmi3UpdateDiscreteStates */
int heli_continuous_time_mode(heli_instance* c, const char* call); /* fmiXEnterContinuousTimeMode */
int heli_step_mode(heli_instance* c, const char* call);            /* fmi3EnterStepMode */
int heli_set_time(heli_instance* c, const char* call, double t);
int heli_set_states(heli_instance* c, const char* call, const double x[], size_t n);
int heli_get_states(heli_instance* c, const char* call, double x[], size_t n);
int heli_get_derivatives(heli_instance* c, const char* call, double dx[], size_t n);
int heli_get_nominals(heli_instance* c, const char* call, double x[], size_t n);
int heli_completed_integrator_step(heli_instance* c, const char* call, int* terminate);

/* -- exact derivatives (CasADi's forward and reverse mode of the generated functions) --------- */
int heli_directional(heli_instance* c, const char* call, const unsigned unknown[], size_t nu,
                     const unsigned known[], size_t nk, const double seed[], double sensitivity[]);
int heli_adjoint(heli_instance* c, const char* call, const unsigned unknown[], size_t nu, const unsigned known[],
                 size_t nk, const double seed[], double sensitivity[]);

/* -- FMU state -------------------------------------------------------------------------------- */
int heli_get_state(heli_instance* c, const char* call, void** state);
int heli_set_state(heli_instance* c, const char* call, void* state);
int heli_free_state(heli_instance* c, const char* call, void** state);
int heli_serialized_size(heli_instance* c, const char* call, void* state, size_t* size);
int heli_serialize(heli_instance* c, const char* call, void* state, unsigned char bytes[], size_t size);
int heli_deserialize(heli_instance* c, const char* call, const unsigned char bytes[], size_t size, void** state);

#endif
