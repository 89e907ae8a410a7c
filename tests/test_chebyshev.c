/* SPDX-License-Identifier: MIT */
/*
 * The Chebyshev iteration (host/solve/solve_chebyshev.c + the cheb_step kernel)
 * against its closed form. On a diagonal operator with eigenvalues lambda_i
 * the residual after k steps is exactly
 *     r_k(lambda) = T_k((theta - lambda) / delta) / T_k(sigma) * r_0(lambda),
 * T_k the Chebyshev polynomial, for every lambda (inside [a, 1] or not), so
 * each component is checked to rounding (1e-12 relative to r_0 over the few
 * dozen steps). Both backends run the same steps and must agree bit for bit.
 * Then the restart rule: with an eigenvalue far below a the schedule lowers
 * a and still converges, in fewer steps than the seeds' iteration.
 */
#include "support.h"

#include "device/device.h"
#include "solve/solve.h"
#include "device/choice/choice.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define N 64

/* T_k(x) for any real x (|x| > 1 included) by the three-term recurrence. */
static double chebyshev_t(int k, double x)
{
    double t0 = 1.0, t1 = x;
    if (k == 0)
        return 1.0;
    for (int j = 1; j < k; j++) {
        double t2 = 2.0 * x * t1 - t0;
        t0 = t1;
        t1 = t2;
    }
    return t1;
}

typedef struct diag_system {
    struct device *dev;
    device_csr a;
    device_buffer *m, *p[2];
    double lambda[N];
} diag_system;

/* A = diag(lambda), M = 1 in x, 2 in y, 0 in z: r_0 = M - A M = (1 - lambda) M. */
static void diag_open(limn_context *ctx, const char *device, const double *lambda,
                      diag_system *s)
{
    memset(s, 0, sizeof *s);
    assert_int_equal(limn_context_set_device(ctx, device), LIMN_OK);
    assert_int_equal(device_get(ctx, &s->dev), LIMN_OK);
    uint32_t ro[N + 1], col[N];
    double w[N], m[4 * N];
    for (int i = 0; i < N; i++) {
        ro[i] = (uint32_t)i;
        col[i] = (uint32_t)i;
        w[i] = lambda[i];
        s->lambda[i] = lambda[i];
        m[4 * i] = 1.0;
        m[4 * i + 1] = 2.0;
        m[4 * i + 2] = 0.0;
        m[4 * i + 3] = 0.0;
    }
    ro[N] = N;
    stencil_csr host = {.rows = N, .cols = N, .row_offsets = ro, .columns = col, .weights = w};
    assert_int_equal(device_csr_upload(s->dev, &host, &s->a), LIMN_OK);
    assert_int_equal(s->dev->ops->buffer_create(s->dev, sizeof m, m, &s->m), LIMN_OK);
    assert_int_equal(s->dev->ops->buffer_create(s->dev, sizeof m, m, &s->p[0]), LIMN_OK);
    assert_int_equal(s->dev->ops->buffer_create(s->dev, sizeof m, NULL, &s->p[1]), LIMN_OK);
}

static void diag_close(diag_system *s)
{
    device_csr_release(s->dev, &s->a);
    s->dev->ops->buffer_release(s->dev, s->m);
    s->dev->ops->buffer_release(s->dev, s->p[0]);
    s->dev->ops->buffer_release(s->dev, s->p[1]);
}

/* Runs `steps` steps of the plain recurrence; returns the last iterate. */
static void run(diag_system *s, chebyshev *c, int steps, double *last_max, double *p_out)
{
    int cur = 0;
    for (int k = 0; k < steps; k++) {
        double c1, c2;
        device_norms nr;
        chebyshev_coefficients(c, &c1, &c2);
        assert_int_equal(s->dev->ops->stationary->cheb_step(s->dev, &s->a, s->m, s->p[cur], s->p[1 - cur],
                                                c1, c2, &nr),
                         LIMN_OK);
        *last_max = nr.max;
        cur = 1 - cur;
    }
    assert_int_equal(s->dev->ops->buffer_read(s->dev, s->p[cur], 4 * N * sizeof(double), p_out),
                     LIMN_OK);
}

static void closed_form(void **state)
{
    (void)state;
    double lambda[N];
    for (int i = 0; i < N; i++) /* inside [a, 1] and some below a */
        lambda[i] = 0.05 + 0.95 * (double)i / (N - 1);
    const char *devices[] = {"reference", "opencl"};
    double p_first[4 * N];
    for (int d = 0; d < 2; d++) {
        limn_context *ctx = limn_context_create();
        diag_system s;
        diag_open(ctx, devices[d], lambda, &s);
        for (int steps = 1; steps <= 30; steps += 29) {
            chebyshev c;
            chebyshev_init(&c, 0.2, 0);
            double theta = c.theta, delta = c.delta, sigma = c.sigma, last, p[4 * N];
            /* reset the start */
            double m[4 * N];
            assert_int_equal(s.dev->ops->buffer_read(s.dev, s.m, sizeof m, m), LIMN_OK);
            assert_int_equal(s.dev->ops->buffer_write(s.dev, s.p[0], sizeof m, m), LIMN_OK);
            run(&s, &c, steps, &last, p);
            /* the iterate after `steps` steps; its residual is M - lambda p */
            for (int i = 0; i < N; i++) {
                double r0 = (1.0 - lambda[i]) * 1.0;
                double expect = chebyshev_t(steps, (theta - lambda[i]) / delta) /
                                chebyshev_t(steps, sigma) * r0;
                double got = 1.0 - lambda[i] * p[4 * i];
                if (fabs(got - expect) > 1e-12 * fabs(r0) + 1e-15)
                    fail_msg("%s, %d steps, lambda %.3f: residual %.17g, closed form %.17g",
                             devices[d], steps, lambda[i], got, expect);
                double got_y = 2.0 - lambda[i] * p[4 * i + 1];
                assert_true(fabs(got_y - 2.0 * got) <= 1e-12 * fabs(r0) + 1e-15);
            }
            if (steps == 30) {
                if (d == 0)
                    memcpy(p_first, p, sizeof p);
                else
                    assert_memory_equal(p_first, p, sizeof p); /* bit-identical backends */
            }
        }
        diag_close(&s);
        limn_context_destroy(ctx);
    }
}

/* An eigenvalue at 0.002, a hundred times below the Loop prior: the rate
   test must lower a (restart) and the solve must still converge, in far
   fewer steps than the seeds' iteration needs (log(1e-9) / log(0.998)). */
static void restart_below_a(void **state)
{
    double lambda[N];
    for (int i = 0; i < N; i++)
        lambda[i] = i == 0 ? 0.002 : 0.25 + 0.75 * (double)i / (N - 1);
    limn_context *ctx = *state;
    diag_system s;
    diag_open(ctx, "reference", lambda, &s);
    chebyshev c;
    chebyshev_init(&c, chebyshev_prior(LIMN_SCHEME_LOOP), 0);
    double r0 = 0.998 * sqrt(5.0), last = r0, p[4 * N];
    int steps = 0, cur = 0;
    while (last > 1e-9 * r0 && steps < 2000) {
        double c1, c2;
        device_norms nr;
        chebyshev_coefficients(&c, &c1, &c2);
        assert_int_equal(
            s.dev->ops->stationary->cheb_step(s.dev, &s.a, s.m, s.p[cur], s.p[1 - cur], c1, c2, &nr), LIMN_OK);
        chebyshev_observe(&c, nr.max);
        last = nr.max;
        cur = 1 - cur;
        steps++;
    }
    (void)p;
    double paper = log(1e-9) / log(1.0 - 0.002);
    printf("  eigenvalue 0.002 below a = %.4f: %d steps, %d restarts, final a %.5f "
           "(the seeds' iteration: %.0f)\n",
           chebyshev_prior(LIMN_SCHEME_LOOP), steps, c.restarts, c.a, paper);
    assert_true(last <= 1e-9 * r0);
    assert_true(c.restarts >= 1);
    assert_true(c.a < 0.01);
    assert_true(steps * 5 < paper);
    diag_close(&s);
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(closed_form), CONTEXT_TEST(restart_below_a))
