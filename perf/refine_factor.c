/* SPDX-License-Identifier: MIT */
/*
 * Measures the design choice of host/refine/refine.c: refinement level by level (one
 * small CSR table per step, applied in turn) against one table composed from
 * the base mesh to the finest level ("factorised"). Prints entries, bytes and
 * seconds for both, as one JSON line.
 *   refine_factor MESH LEVELS loop|catmark
 */
#include "limn.h"
#include "refine/refine.h"
#include "stencil/stencil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* C = S * B (rows of S combine rows of B); dense accumulator over B's columns. */
static int compose(const stencil_csr *s, const stencil_csr *b, stencil_csr *c)
{
    double *acc = calloc(b->cols, sizeof *acc);
    uint32_t *touched = malloc(b->cols * sizeof *touched);
    unsigned char *seen = calloc(b->cols, 1);
    size_t cap = s->row_offsets[s->rows] * 4 + 16, k = 0;
    c->rows = s->rows;
    c->cols = b->cols;
    c->row_offsets = malloc((s->rows + 1) * sizeof *c->row_offsets);
    c->columns = malloc(cap * sizeof *c->columns);
    c->weights = malloc(cap * sizeof *c->weights);
    c->row_offsets[0] = 0;
    for (size_t i = 0; i < s->rows; i++) {
        size_t nt = 0;
        for (uint32_t p = s->row_offsets[i]; p < s->row_offsets[i + 1]; p++) {
            uint32_t r = s->columns[p];
            for (uint32_t q = b->row_offsets[r]; q < b->row_offsets[r + 1]; q++) {
                uint32_t col = b->columns[q];
                if (!seen[col]) {
                    seen[col] = 1;
                    touched[nt++] = col;
                }
                acc[col] += s->weights[p] * b->weights[q];
            }
        }
        if (k + nt > cap) {
            while (k + nt > cap)
                cap *= 2;
            c->columns = realloc(c->columns, cap * sizeof *c->columns);
            c->weights = realloc(c->weights, cap * sizeof *c->weights);
            if (!c->columns || !c->weights)
                return -1;
        }
        for (size_t t = 0; t < nt; t++) {
            c->columns[k] = touched[t];
            c->weights[k++] = acc[touched[t]];
            acc[touched[t]] = 0;
            seen[touched[t]] = 0;
        }
        if (k > UINT32_MAX)
            return -1;
        c->row_offsets[i + 1] = (uint32_t)k;
    }
    free(acc);
    free(touched);
    free(seen);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: refine_factor MESH LEVELS loop|catmark\n");
        return 2;
    }
    limn_context *ctx = limn_context_create();
    limn_mesh *m = NULL;
    if (limn_mesh_read(ctx, argv[1], LIMN_FORMAT_AUTO, &m) != LIMN_OK) {
        fprintf(stderr, "%s\n", limn_context_message(ctx));
        return 1;
    }
    int levels = atoi(argv[2]);
    limn_scheme scheme = strcmp(argv[3], "loop") == 0 ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
    limn_context_set_device(ctx, "reference");
    refine_plan plan;
    double t0 = now();
    if (refine_plan_build(ctx, m, scheme, 0.0, levels, &plan) != LIMN_OK) {
        fprintf(stderr, "%s\n", limn_context_message(ctx));
        return 1;
    }
    double t1 = now();
    size_t n0 = limn_mesh_vertex_count(m), nl = limn_mesh_vertex_count(plan.meshes[levels]);
    size_t steps_nnz = 0;
    for (int k = 0; k < levels; k++)
        steps_nnz += plan.steps[k].row_offsets[plan.steps[k].rows];
    double *out = malloc(nl * 3 * sizeof *out);
    double t2 = now();
    refine_plan_apply(ctx, &plan, 0, 3, limn_mesh_positions(m), out);
    double t3 = now();
    /* compose */
    stencil_csr composed = plan.steps[0], next;
    int owned = 0, failed = 0;
    double t4 = now();
    for (int k = 1; k < levels && !failed; k++) {
        failed = compose(&plan.steps[k], &composed, &next) != 0;
        if (owned)
            stencil_free(&composed);
        composed = next;
        owned = 1;
    }
    double t5 = now();
    size_t comp_nnz = failed ? 0 : composed.row_offsets[composed.rows];
    double *out2 = malloc(nl * 3 * sizeof *out2);
    double t6 = now();
    if (!failed)
        stencil_apply3(&composed, limn_mesh_positions(m), out2);
    double t7 = now();
    double diff = 0;
    for (size_t i = 0; !failed && i < 3 * nl; i++) {
        double d = out[i] - out2[i];
        diff = d * d > diff ? d * d : diff;
    }
    printf("{\"vertices\": %zu, \"levels\": %d, \"output_vertices\": %zu, "
           "\"level_by_level\": {\"entries\": %zu, \"bytes\": %zu, \"seconds_build\": %.4f, "
           "\"seconds_apply\": %.4f}, "
           "\"factorised\": {\"entries\": %zu, \"bytes\": %zu, \"seconds_compose\": %.4f, "
           "\"seconds_apply_host\": %.4f, \"max_abs_difference\": %.3g}}\n",
           n0, levels, nl, steps_nnz, steps_nnz * 12, t1 - t0, t3 - t2, comp_nnz, comp_nnz * 12,
           t5 - t4, t7 - t6, diff > 0 ? __builtin_sqrt(diff) : 0.0);
    if (owned)
        stencil_free(&composed);
    free(out);
    free(out2);
    refine_plan_free(&plan);
    limn_mesh_destroy(m);
    limn_context_destroy(ctx);
    return 0;
}
