/* SPDX-License-Identifier: MIT */
/* The convergence monitor shared by every solver (the stationary and
   semi-iterative loop, CG and SGS, the float corrections), texture and the MPI
   layer: one stop / stall / cap / non-finite rule and one mapping of its
   verdicts to limn statuses and messages (monitor.c). */
#ifndef LIMN_MONITOR_H
#define LIMN_MONITOR_H

#include "limn.h"

/* The usual stall rule: the residual shrank by less than 1% over 25 residuals. */
#define MONITOR_STALL_WINDOW 25
#define MONITOR_STALL_RATIO 0.99
#define MONITOR_WINDOW_MAX 25

typedef enum monitor_verdict {
    MONITOR_CONTINUE,
    MONITOR_CONVERGED,  /* residual <= tolerance */
    MONITOR_STALLED,    /* residual > ratio * the one window residuals earlier */
    MONITOR_CAPPED,     /* iteration >= cap */
    MONITOR_NON_FINITE, /* NaN or Inf */
} monitor_verdict;

typedef struct monitor {
    double tolerance; /* absolute */
    int cap;          /* iterations */
    int window;       /* stall window, 0..MONITOR_WINDOW_MAX (0: no stall test) */
    double ratio;     /* stall ratio */
    double history[MONITOR_WINDOW_MAX];
    double first;    /* first finite unconverged residual (-1: none yet) */
    double residual; /* the last one seen */
    double earlier;  /* on a stall: the residual window steps earlier */
    int steps;       /* residuals seen */
    int k;           /* index of the last one (steps - 1) */
    int iteration;   /* the iteration count given with the last one */
} monitor;

void monitor_init(monitor *m, double tolerance, int cap, int window, double ratio);

/* Judges one residual (max |r|) of iteration `iteration`, in this order:
   non-finite, converged, stalled, capped. The stall test compares with the
   residual `window` calls earlier. */
monitor_verdict monitor_step(monitor *m, double residual_max, int iteration);

/* Which loop fails, for the wording of its message. */
typedef enum monitor_loop {
    MONITOR_LOOP_STATIONARY, /* paper / weighted / chebyshev, one process or MPI */
    MONITOR_LOOP_CG,         /* cg, sgs, mpi_cg */
    MONITOR_LOOP_MIXED,      /* the float precision's outer loop */
    MONITOR_LOOP_TEXTURE,    /* a scalar noise interpolation of limn_texture */
} monitor_loop;

typedef struct monitor_words {
    monitor_loop loop;
    const char *what;         /* non-finite: what overflowed, e.g. "the residual" */
    double diag;              /* scale of relative errors (0: absolute) */
    double tolerance;         /* relative tolerance for the cap message */
    limn_scheme scheme;       /* with alpha: the alpha = 0 hint */
    double alpha;
    int catmark_alpha0;       /* CG's form of the alpha hint */
    int in_float;             /* the overflow hint names --precision double */
    int level;                /* texture: the level */
} monitor_words;

/* The one mapping of a failing verdict to a status and message: NON_FINITE
   -> the overflow message (LIMN_ERR_NO_CONVERGENCE), STALLED ->
   LIMN_ERR_SINGULAR, CAPPED -> LIMN_ERR_NO_CONVERGENCE; other verdicts are
   LIMN_OK. */
limn_status monitor_fail(limn_context *ctx, const monitor *m, monitor_verdict v,
                         const monitor_words *w);

/* Iterations of the weighted method spent estimating lambda_min, and the
   estimate: omega = 2 / (lambda + 1), lambda = 1 - (contraction of |r|_2
   from l2_probe, WEIGHTED_PROBE - 2 steps earlier, to l2_now). */
#define WEIGHTED_PROBE 8
double monitor_weighted_omega(double l2_probe, double l2_now);

#endif
