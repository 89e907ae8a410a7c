/* SPDX-License-Identifier: MIT */
/*
 * Coefficients of the Chebyshev iteration for A P = M (Saad, Iterative
 * Methods for Sparse Linear Systems, Alg. 12.1, written on iterates):
 *   x_{k+1} = x_k + c1 (x_k - x_{k-1}) + c2 r_k,   r_k = M - A x_k,
 * with theta = (b + a) / 2, delta = (b - a) / 2, sigma = theta / delta,
 * rho_0 = 1 / sigma and rho_k = 1 / (2 sigma - rho_{k-1}):
 * step 0 is x_1 = x_0 + r_0 / theta; step k >= 1 has c1 = rho_k rho_{k-1},
 * c2 = 2 rho_k / delta. The device runs each step fused with the residual
 * and its norms (device_ops.cheb_step), so a step costs one stencil product
 * and moves one vector more than the seeds' step.
 *
 * Bounds (README "Solvers"): b = 1 exactly (rows of A are non-negative and
 * sum to 1, so no eigenvalue exceeds 1 and constants have eigenvalue 1).
 * a starts from the scheme's value on the regular lattice times a margin
 * (Loop 1/4, Catmull-Clark 1/9); an estimate above lambda_min does not
 * diverge (modes below a still contract, only slower), one below it costs
 * sqrt of the ratio in speed. When the residual falls more slowly than the
 * Chebyshev bound for [a, 1] predicts (by CHEB_SLACK), the observed rate
 * gives the eigenvalue that dominates; a is lowered below it and the
 * recurrence restarts from the current iterate.
 */
#include "solve/solve.h"

#include <math.h>
#include <string.h>

#define CHEB_SLACK 10.0
#define CHEB_MIN_STEPS 6  /* steps after a (re)start before judging the rate */
#define CHEB_FLOOR 1e-6   /* smallest lower bound tried */

static void set_interval(chebyshev *c, double a)
{
    c->a = a;
    c->theta = (1.0 + a) / 2.0;
    c->delta = (1.0 - a) / 2.0;
    c->sigma = c->theta / c->delta;
    double s = sqrt(1.0 / a);
    c->tau = (s - 1.0) / (s + 1.0);
    c->step = 0;
}

double chebyshev_prior(limn_scheme scheme)
{
    /* regular-lattice lambda_min (DESIGN §1) with a 15% margin for
       irregular vertices: measured lambda_min on the shared medium meshes is
       0.21-0.24 (Loop) and 0.083-0.29 (Catmull-Clark) */
    return scheme == LIMN_SCHEME_LOOP ? 0.85 * 0.25 : 0.85 / 9.0;
}

int chebyshev_lead_steps(limn_scheme scheme)
{
    /* one step of the seeds' iteration first multiplies the error by
       (1 - lambda), which removes what the Chebyshev polynomial leaves at the
       top of the interval. Measured to 1e-6 on the shared medium meshes
       (perf/chebyshev_bounds.py): Catmull-Clark 14 -> 11 products on
       blub and bob, 15 -> 14 on horse, 19 on beast either way; Loop loses
       one product on 4 of 6 meshes, so it starts at once. */
    return scheme == LIMN_SCHEME_CATMARK ? 1 : 0;
}

void chebyshev_init(chebyshev *c, double a, int lead_steps)
{
    memset(c, 0, sizeof *c);
    set_interval(c, a);
    c->lead = lead_steps;
}

void chebyshev_coefficients(chebyshev *c, double *c1, double *c2)
{
    if (c->lead > 0) {
        c->lead--;
        c->in_lead = 1;
        *c1 = 0.0;
        *c2 = 1.0;
        return;
    }
    c->in_lead = 0;
    if (c->step == 0) {
        c->rho = 1.0 / c->sigma;
        *c1 = 0.0;
        *c2 = 1.0 / c->theta;
    } else {
        double rho = 1.0 / (2.0 * c->sigma - c->rho);
        *c1 = rho * c->rho;
        *c2 = 2.0 * rho / c->delta;
        c->rho = rho;
    }
    c->step++;
}

int chebyshev_observe(chebyshev *c, double residual)
{
    int j = c->step - 1; /* the step whose residual this is */
    if (j < 0 || c->in_lead)
        return 0;
    if (j == 0)
        c->first = residual;
    c->history[j % 4] = residual;
    if (j < CHEB_MIN_STEPS || !(c->first > 0.0))
        return 0;
    double tj = pow(c->tau, (double)j);
    double predicted = c->first * 2.0 * tj / (1.0 + tj * tj);
    if (!(residual > CHEB_SLACK * predicted))
        return 0;
    /* a mode at lambda < a decays per step by exp(acosh((theta - lambda) /
       delta) - acosh(sigma)): invert the rate seen over the last 3 steps */
    double earlier = c->history[(j - 3) % 4];
    double q = earlier > 0.0 ? pow(residual / earlier, 1.0 / 3.0) : 1.0;
    double g = acosh(c->sigma) + log(q < 1.0 ? q : 1.0);
    double lambda = c->theta - c->delta * cosh(g > 0.0 ? g : 0.0);
    double a = 0.9 * lambda;
    if (a > 0.7 * c->a)
        a = 0.7 * c->a;
    if (a < CHEB_FLOOR)
        a = CHEB_FLOOR;
    if (a >= c->a)
        return 0;
    int restarts = c->restarts + 1;
    set_interval(c, a);
    c->restarts = restarts;
    return 1;
}
