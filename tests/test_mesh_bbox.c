/* SPDX-License-Identifier: MIT */
/*
 * The bounding box (mesh_bbox_diagonal: four interleaved walks merged)
 * against one walk in vertex order with strict comparisons, bit for bit:
 * random coordinates of every vertex count 0..40 and 100003, with zeros of
 * both signs as the extremes (the merge's one difference, walked again),
 * NaNs after the first vertex (never an extreme) and first (the extreme
 * everywhere), infinities and repeated values.
 */
#include "support.h"
#include "mesh/mesh.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static void one_walk(const double *p, size_t n, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) {
        lo[c] = hi[c] = n ? p[c] : 0.0;
        for (size_t i = 0; i < n; i++) {
            double x = p[3 * i + c];
            lo[c] = x < lo[c] ? x : lo[c];
            hi[c] = x > hi[c] ? x : hi[c];
        }
    }
}

static uint64_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* A coordinate of kind k: 0 any, 1 from a few values with +-0 among them
   (extremes at zero, ties), 2 with a NaN or an infinity now and then. */
static double value(uint64_t *s, int k)
{
    uint64_t r = next(s);
    if (k == 1) {
        static const double few[] = {0.0, -0.0, 0.0, -0.0, 0.5, -0.0, 0.0};
        return few[r % 7] * ((r >> 8) % 3 == 0 ? -1.0 : 1.0);
    }
    if (k == 2 && r % 17 == 0)
        return (r >> 8) % 3 == 0 ? NAN : (r >> 8) % 3 == 1 ? INFINITY : -INFINITY;
    return ((double)(r >> 11) / 9007199254740992.0 - 0.5) * 1e3;
}

static void same_as_one_walk(const double *p, size_t n, const char *what)
{
    limn_mesh m;
    memset(&m, 0, sizeof m);
    m.vertex_count = n;
    m.positions = (double *)p;
    double lo[3], hi[3], wlo[3], whi[3];
    mesh_bbox_diagonal(&m, lo, hi);
    one_walk(p, n, wlo, whi);
    for (int c = 0; c < 3; c++)
        if (memcmp(&lo[c], &wlo[c], sizeof lo[c]) || memcmp(&hi[c], &whi[c], sizeof hi[c]))
            fail_msg("%s, %zu vertices, coordinate %d: [%g, %g] against one walk's [%g, %g]",
                     what, n, c, lo[c], hi[c], wlo[c], whi[c]);
}

static void against_one_walk(void **state)
{
    (void)state;
    uint64_t seed = 1;
    size_t big = 100003;
    double *p = malloc(3 * big * sizeof *p);
    assert_non_null(p);
    for (int k = 0; k < 3; k++)
        for (int round = 0; round < 20; round++) {
            for (size_t n = 0; n <= 40; n++) {
                for (size_t i = 0; i < 3 * n; i++)
                    p[i] = value(&seed, k);
                same_as_one_walk(p, n, k == 0 ? "random" : k == 1 ? "zeros" : "nan/inf");
            }
            for (size_t i = 0; i < 3 * big; i++)
                p[i] = value(&seed, k);
            same_as_one_walk(p, big, k == 0 ? "random" : k == 1 ? "zeros" : "nan/inf");
        }
    /* a NaN first: it stays the extreme, as in one walk */
    for (size_t i = 0; i < 3 * 64; i++)
        p[i] = value(&seed, 0);
    p[0] = NAN;
    same_as_one_walk(p, 64, "a NaN first");
    /* both zeros with the negative one first, in every walk's place */
    for (size_t at = 0; at < 8; at++) {
        for (size_t i = 0; i < 3 * 16; i++)
            p[i] = 1.0;
        p[3 * at] = -0.0;
        p[3 * (at + 5)] = 0.0;
        same_as_one_walk(p, 16, "-0 then +0");
        p[3 * at] = 0.0;
        p[3 * (at + 5)] = -0.0;
        same_as_one_walk(p, 16, "+0 then -0");
    }
    free(p);
}

TEST_MAIN(NULL, NULL, cmocka_unit_test(against_one_walk))
