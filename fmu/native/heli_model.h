/* Tables that describe the heli rotor FMU's variables, scenes and compiled model groups.
   heli_data.c (generated at build time from the spec) defines heli_model_data; heli_core.c
   runs the model on top of it, fmi2Functions.c and fmi3Functions.c are its FMI interfaces. */
#ifndef HELI_MODEL_H
#define HELI_MODEL_H

#include "heli_config.h"
#include "heli_libm.h"

typedef long long heli_int;

/* The core's fixed-step driver: n steps of h from t0 + k0 h, Kahan terms in comp (in/out);
   0 ok, 1 non-finite state, 2 evaluation error, 3 out of memory. */
typedef int (*heli_run_fn)(const double* x0, double t0, double h, heli_int k0, heli_int n, heli_int every,
                           const double* p, double* out, double* comp, int compensated, heli_int* done);
/* A CasADi-generated function and its work-size query. */
typedef int (*heli_eval_fn)(const double** arg, double** res, heli_int* iw, double* w, int mem);
typedef int (*heli_work_fn)(heli_int* n_arg, heli_int* n_res, heli_int* n_iw, heli_int* n_w);

enum { HELI_REAL, HELI_STRING };
enum { HELI_INPUT, HELI_PARAMETER, HELI_OUTPUT, HELI_LOCAL };
enum { HELI_FIXED, HELI_TUNABLE, HELI_CONTINUOUS };
enum { HELI_RK4, HELI_RK8, HELI_METHODS };

typedef struct {
  const char* name;
  int type, causality, variability;
  const char* unit;          /* "" when dimensionless and undeclared */
  double min, max;           /* -INFINITY / INFINITY when not declared */
  double start;              /* XML start of a Real input or parameter, else NAN */
  const char* start_text;    /* XML start of a String parameter, else NULL */
  int n_allowed;
  const char* const* allowed; /* the values a String parameter accepts */
  int position;              /* index in the computed values (outputs, locals), else -1 */
  int hinge;                 /* a hinge angle that must stay within +-pi/2 */
} heli_variable;

typedef struct {
  const char* name;
  int nx;
  heli_run_fn run[HELI_METHODS];
  heli_eval_fn incr[HELI_METHODS];
  heli_work_fn incr_work[HELI_METHODS];
  heli_eval_fn outputs;       /* fmu_outputs(x, t, p): every computed variable in order */
  heli_work_fn outputs_work;
  heli_eval_fn energy;        /* energy(x, t, p): its parts, the total last */
  heli_work_fn energy_work;
  int n_energy;
  heli_eval_fn rhs;           /* rhs(x, t, p): x' (model exchange) */
  heli_work_fn rhs_work;
  heli_eval_fn ad_fwd;        /* ad_fwd(x, t, p, dx, dp): (dx', dy), CasADi's forward mode of (rhs, fmu_outputs) */
  heli_work_fn ad_fwd_work;
  heli_eval_fn ad_adj;        /* ad_adj(x, t, p, b): (bx, bp), its reverse mode: the transposed Jacobian times b */
  heli_work_fn ad_adj_work;
  int me_ok;                  /* every state of this model is one of the FMU's continuous states */
  const char* const* state_names;
  const int* state_of;        /* by value reference: the index in x of a computed variable that
                                 is a state of this model, else -1 */
} heli_group;

typedef struct {
  const char* name;
  int group;                  /* index into heli_model.groups */
  const double* x0;
  double omega;
  int steps_per_rev;
  int n_params;
  const int* param_vr;        /* value reference of each entry of the model's parameter vector */
  const double* defaults;     /* by value reference; NAN where the scene has no default */
  const double* low;          /* range by value reference */
  const double* high;
  int free_body;              /* has a free fuselage: initial_forward_speed applies */
  int fs_v[3];                /* state indices of its body velocity */
  double fs_dir[3];           /* level flight in body axes at the scene's own start: R(q0)^T e_x */
  double fs_default;          /* the scene's own initial forward speed (m/s) */
  const double* periodic_x0;  /* initial_state = "periodic": the trim's state, NULL when the scene has none */
  const double* periodic_defaults; /* by value reference: the defaults with the trim's controls */
  double periodic_fs_dir[3];  /* level flight in body axes at the trim's attitude */
  double trim_speed;          /* the trim's flight speed (m/s): initial_forward_speed that keeps its state */
} heli_scene;

/* An FMI 3.0 variable: a scalar or an array of slots (FMI 2.0 value references; -1 is time). */
typedef struct {
  const char* name;
  int n;
  const int* slots;
} heli_variable3;

typedef struct {
  const char* identifier;
  const char* guid;
  int primary;
  int n_variables;
  const heli_variable* variables;
  int n_scenes;
  const heli_scene* scenes;
  int n_groups;
  const heli_group* groups;
  int n_computed;
  double max_substeps;        /* most sub-steps one doStep may take */
  double hinge_angle;         /* largest hinge angle (rad) a step may reach */
  int vr_scene, vr_evaluator, vr_integrator, vr_max_step, vr_omega, vr_forward_speed, vr_energy,
      vr_initial_state; /* -1 if absent */
  int n_states;               /* continuous states (model exchange): the primary scene's states */
  const int* me_state;        /* the slot of each, in the FMI 2.0 order (the primary model's x) */
  int n_variables3;
  const heli_variable3* variables3; /* by FMI 3.0 value reference */
  const int* me_order3;       /* FMI 3.0 continuous state k is FMI 2.0 state me_order3[k] */
} heli_model;

extern const heli_model heli_model_data;

#endif
