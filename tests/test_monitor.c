/* SPDX-License-Identifier: MIT */
/*
 * The convergence monitor (host/solve/monitor.c) on synthetic residual
 * sequences: a geometric decrease converges at the predicted step, a plateau
 * stalls after exactly the window, the cap, NaN and Inf; then the mapping of
 * each verdict to its status and message, and the weighted omega estimate.
 */
#include "support.h"

#include "solve/monitor.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

/* Steps m with the residuals first * q^k, k = 0, 1, ... until its verdict;
   returns the verdict, the step it came at in *k. */
static monitor_verdict run_geometric(monitor *m, double first, double q, int *k)
{
    monitor_verdict v;
    *k = 0;
    while ((v = monitor_step(m, first * pow(q, *k), *k)) == MONITOR_CONTINUE)
        ++*k;
    return v;
}

/* A fresh monitor (tolerance, cap, stall window) stepped on first * q^k ends
   with the verdict want at step want_k. */
static void expect_geometric(monitor *m, double tol, int max_iter, int window, double first,
                             double q, monitor_verdict want, int want_k)
{
    monitor_init(m, tol, max_iter, window, MONITOR_STALL_RATIO);
    int k;
    monitor_verdict v = run_geometric(m, first, q, &k);
    assert_int_equal(v, want);
    assert_int_equal(k, want_k);
}

/* residual 0.5^k from 1: <= 1e-3 first at k = 10 (0.5^10 = 9.77e-4) */
static void geometric_converges(void **s)
{
    (void)s;
    monitor m;
    expect_geometric(&m, 1e-3, 1000, MONITOR_STALL_WINDOW, 1.0, 0.5, MONITOR_CONVERGED, 10);
    assert_int_equal(m.steps, 11);
    assert_true(m.first == 1.0);
}

/* a constant residual: the stall test first looks WINDOW residuals back at
   step WINDOW, so it stalls there, not earlier; a residual shrinking by more
   than the ratio per window never stalls, and window 0 has no stall test */
static void plateau_stalls_after_window(void **s)
{
    (void)s;
    for (int w = 1; w <= MONITOR_WINDOW_MAX; w += 8) {
        monitor m;
        expect_geometric(&m, 1e-9, 1000, w, 2.0, 1.0, MONITOR_STALLED, w);
        assert_true(m.earlier == 2.0 && m.residual == 2.0);
    }
    monitor m;
    monitor_init(&m, 1e-9, 200, MONITOR_STALL_WINDOW, 0.5);
    monitor_verdict v = MONITOR_CONTINUE;
    int k;
    for (k = 0; k < 150 && v == MONITOR_CONTINUE; k++) /* halves every 24: below 0.5 per 25 */
        v = monitor_step(&m, pow(0.5, k / 24.0), k);
    assert_int_equal(v, MONITOR_CONTINUE);
    /* no stall test with window 0 */
    monitor_init(&m, 1e-9, 100, 0, MONITOR_STALL_RATIO);
    for (k = 0; k < 50; k++)
        assert_int_equal(monitor_step(&m, 1.0, k), MONITOR_CONTINUE);
}

static void cap(void **s)
{
    (void)s;
    monitor m;
    expect_geometric(&m, 1e-12, 7, MONITOR_STALL_WINDOW, 1.0, 0.9, MONITOR_CAPPED, 7);
    /* the cap reads the iteration given, not the residuals seen */
    monitor_init(&m, 1e-12, 7, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    assert_int_equal(monitor_step(&m, 1.0, 6), MONITOR_CONTINUE);
    assert_int_equal(monitor_step(&m, 0.5, 7), MONITOR_CAPPED);
    /* convergence wins over the cap, and so does a stall */
    assert_int_equal(monitor_step(&m, 1e-13, 9), MONITOR_CONVERGED);
    monitor_init(&m, 1e-12, 1, 1, MONITOR_STALL_RATIO);
    assert_int_equal(monitor_step(&m, 1.0, 0), MONITOR_CONTINUE);
    assert_int_equal(monitor_step(&m, 1.0, 1), MONITOR_STALLED);
}

static void non_finite(void **s)
{
    (void)s;
    double bad[] = {NAN, INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++) {
        monitor m;
        monitor_init(&m, 1e-3, 100, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
        assert_int_equal(monitor_step(&m, 1.0, 0), MONITOR_CONTINUE);
        assert_int_equal(monitor_step(&m, bad[i], 1), MONITOR_NON_FINITE);
    }
}

static void expect(limn_context *ctx, limn_status got, limn_status want, const char *a,
                   const char *b)
{
    assert_int_equal(got, want);
    const char *msg = limn_context_message(ctx);
    if (!strstr(msg, a) || (b && !strstr(msg, b)))
        fail_msg("missing '%s' / '%s' in: %s", a, b ? b : "", msg);
}

static void status_and_message(void **s)
{
    (void)s;
    limn_context *ctx = limn_context_create();
    monitor m;
    monitor_words w = {MONITOR_LOOP_STATIONARY, "the residual", 2.0, 1e-6, LIMN_SCHEME_CATMARK,
                       0.0, 0, 0, 0};
    monitor_init(&m, 2e-6, 1000, 3, MONITOR_STALL_RATIO);
    monitor_verdict v = MONITOR_CONTINUE;
    for (int k = 0; v == MONITOR_CONTINUE; k++)
        v = monitor_step(&m, 1.0, k);
    assert_int_equal(v, MONITOR_STALLED);
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_SINGULAR,
           "the residual stopped shrinking: 1 (relative 0.5) after 3 iterations, 1 3 "
           "iterations earlier",
           "--alpha 0.5");
    w.loop = MONITOR_LOOP_CG;
    w.catmark_alpha0 = 1;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_SINGULAR,
           "stopped shrinking under conjugate gradients", "--alpha 0.5");
    w.loop = MONITOR_LOOP_TEXTURE;
    w.level = 2;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_SINGULAR,
           "interpolating the noise of level 2 stopped converging", "use --alpha 0.5");

    /* the cap: 1, 0.5, 0.25, 0.125 -> rate 0.5, about 16 more to 2e-6 */
    monitor_init(&m, 2e-6, 3, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    v = MONITOR_CONTINUE;
    for (int k = 0; v == MONITOR_CONTINUE; k++)
        v = monitor_step(&m, pow(0.5, k), k);
    assert_int_equal(v, MONITOR_CAPPED);
    w.loop = MONITOR_LOOP_STATIONARY;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE,
           "no convergence in 3 iterations: max relative error 0.0625, tolerance 1e-06; the "
           "error shrinks by 0.5000 per iteration, so about 16 more are needed",
           "raise --max-iter");
    w.loop = MONITOR_LOOP_MIXED;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE,
           "the error shrinks by 0.5000 per iteration: raise --max-iter", NULL);
    w.loop = MONITOR_LOOP_CG;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE,
           "no convergence in 3 conjugate-gradient steps: max error 0.125, tolerance 2e-06",
           NULL);
    w.loop = MONITOR_LOOP_TEXTURE; /* the common rule: a cap is NO_CONVERGENCE */
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE,
           "stopped converging (residual 0.125 after 3 iterations)", NULL);

    /* non-finite: the overflow hint, float's names --precision double */
    monitor_init(&m, 1e-6, 100, MONITOR_STALL_WINDOW, MONITOR_STALL_RATIO);
    monitor_step(&m, 1.0, 0);
    v = monitor_step(&m, NAN, 1);
    w = (monitor_words){MONITOR_LOOP_STATIONARY, "the residual", 1.0, 1e-6, LIMN_SCHEME_LOOP,
                        0.0, 0, 0, 0};
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE,
           "non-finite values in the iteration (overflow?): the residual became non-finite "
           "after 1 iteration;",
           "scale the mesh down");
    w.in_float = 1;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE, "(overflow?)",
           "--precision double");
    w.scheme = LIMN_SCHEME_CATMARK;
    w.alpha = 0.9;
    expect(ctx, monitor_fail(ctx, &m, v, &w), LIMN_ERR_NO_CONVERGENCE, "over 6/7", NULL);
    assert_int_equal(monitor_fail(ctx, &m, MONITOR_CONTINUE, &w), LIMN_OK);
    assert_int_equal(monitor_fail(ctx, &m, MONITOR_CONVERGED, &w), LIMN_OK);
    limn_context_destroy(ctx);
}

/* contraction rho over WEIGHTED_PROBE - 2 steps: omega = 2 / (2 - rho) */
static void weighted_omega(void **s)
{
    (void)s;
    double rho = 0.8;
    double omega = monitor_weighted_omega(1.0, pow(rho, WEIGHTED_PROBE - 2));
    assert_true(fabs(omega - 2.0 / (2.0 - rho)) < 1e-14);
    assert_true(monitor_weighted_omega(1.0, 2.0) == 1.0); /* growth: lambda 1, omega 1 */
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(geometric_converges),
          cmocka_unit_test(plateau_stalls_after_window), cmocka_unit_test(cap),
          cmocka_unit_test(non_finite), cmocka_unit_test(status_and_message),
          cmocka_unit_test(weighted_omega))
