/* SPDX-License-Identifier: MIT */
/*
 * The loops of smooth, denoise, sharpen and morph (filter.h), the same for
 * one process and for MPI: only the engine's term and transfers differ.
 */
#include "series/filter.h"

#include "base/context.h"
#include "mesh/mesh.h"
#include "series/series.h"

#include <stddef.h>

limn_status series_terms(const series_engine *e, device_buffer *x, device_buffer *acc,
                         device_buffer *ra, device_buffer *rb, int m)
{
    limn_status st = LIMN_OK;
    device_buffer *cur = x;
    for (int i = 0; i <= m; i++) {
        device_buffer *next = cur == ra ? rb : ra;
        st = e->ops->term(e, cur, next, acc, i < m ? SERIES_STORE_NEXT : 0,
                     i == 0 ? SERIES_ACC_SET_AX : SERIES_ACC_ADD_AX, st);
        if (st && !e->carry)
            return st;
        ++*e->products;
        cur = next;
    }
    return e->ops->agree(e, st);
}

limn_status series_smooth_run(const series_engine *e, const limn_mesh *mesh, int terms,
                              limn_mesh **out)
{
    device_buffer **b = e->buf;
    limn_status st = e->ops->upload(e, e->root ? mesh->positions : NULL, b[0]);
    if (!st)
        st = series_terms(e, b[0], b[1], b[2], b[3], terms - 1);
    if (!st)
        st = e->ops->result(e, b[1], mesh, "smoothing", out);
    return st;
}

limn_status series_denoise_run(const series_engine *e, const limn_mesh *mesh, int m, int steps,
                               int keep_volume, limn_mesh **out)
{
    device_buffer *t = e->buf[0], *acc = e->buf[1];
    limn_status st = e->ops->upload(e, e->root ? mesh->positions : NULL, t);
    for (int k = 0; !st && k < steps; k++) {
        st = series_terms(e, t, acc, e->buf[2], e->buf[3], m);
        device_buffer *tmp = t;
        t = acc;
        acc = tmp;
        ctx_progress(e->ctx, "denoise", (double)(k + 1) / steps);
    }
    if (!st)
        st = e->ops->result(e, t, mesh, "denoising", out);
    if (!st && keep_volume) {
        st = e->ops->agree(e, e->root ? series_keep_volume(e->ctx, mesh, *out) : LIMN_OK);
        if (st && out) {
            limn_mesh_destroy(*out);
            *out = NULL;
        }
    }
    return st;
}

/* One sharpening step's terms: acc += r_i for from <= i < to, r_0 = t,
   r_{i+1} = (E - A) r_i (r_1 .. r_to in ra, rb); *last gets r_to. */
static limn_status sharpen_terms(const series_engine *e, device_buffer *t, device_buffer *acc,
                                 int from, int to, device_buffer **last)
{
    limn_status st = LIMN_OK;
    device_buffer *cur = t, *ra = e->buf[2], *rb = e->buf[3];
    for (int i = 0; i < to; i++) {
        device_buffer *next = cur == ra ? rb : ra;
        st = e->ops->term(e, cur, next, acc, SERIES_STORE_NEXT,
                          i >= from ? SERIES_ACC_ADD_X : SERIES_ACC_NONE, st);
        if (st && !e->carry)
            return st;
        ++*e->products;
        cur = next;
    }
    *last = cur;
    return e->ops->agree(e, st);
}

limn_status series_sharpen_run(const series_engine *e, const limn_mesh *mesh, int from, int to,
                               int steps, limn_mesh **out)
{
    device_buffer *t = e->buf[0], *acc = e->buf[1], *cur = t;
    limn_status st = e->ops->upload(e, e->root ? mesh->positions : NULL, t);
    for (int k = 0; !st && k < steps; k++) {
        /* acc = T + sum_{i=from..to-1} r_i + r_to */
        st = e->ops->axpby(e, 1.0, t, 0.0, t, acc);
        if (!st)
            st = sharpen_terms(e, t, acc, from, to, &cur);
        if (!st)
            st = e->ops->axpby(e, 1.0, acc, 1.0, cur, acc);
        device_buffer *tmp = t;
        t = acc;
        acc = tmp;
        ctx_progress(e->ctx, "sharpen", (double)(k + 1) / steps);
    }
    if (!st)
        st = e->ops->result(e, t, mesh, "sharpening", out);
    return st;
}

/* Frame k on the root: Q_k = TO + D_k (D_k in q on entry). */
static limn_status morph_frame(const series_engine *e, const limn_mesh *from, const limn_mesh *to,
                               int closed, double diag, int k, double *q, limn_morph_frame_fn fn,
                               void *user)
{
    size_t n = from->vertex_count;
    for (size_t i = 0; i < 3 * n; i++)
        q[i] = to->positions[i] + q[i];
    limn_status st = series_check_finite(e->ctx, q, n, "the morph");
    return st ? st : series_emit_frame(from, to, closed, diag, k, q, fn, user);
}

limn_status series_morph_run(const series_engine *e, const limn_mesh *from, const limn_mesh *to,
                             const limn_morph_options *o, int closed, double diag, double *q,
                             limn_morph_frame_fn fn, void *user)
{
    device_buffer **b = e->buf;
    limn_status st = e->ops->upload(e, q, b[0]);
    if (!st && e->root)
        st = series_emit_frame(from, to, closed, diag, 0, from->positions, fn, user);
    st = e->ops->agree(e, st);
    for (int k = 1; !st && k < o->frames; k++) {
        /* D_k = p sum_{i=0..m} (E - A)^i A D_{k-1}; Q_k = TO + D_k */
        st = series_terms(e, b[0], b[1], b[2], b[3], o->m);
        if (!st)
            st = e->ops->axpby(e, o->p, b[1], 0.0, b[1], b[0]);
        if (!st)
            st = e->ops->download(e, b[0], q);
        if (!st)
            st = e->ops->agree(
                e, e->root ? morph_frame(e, from, to, closed, diag, k, q, fn, user) : LIMN_OK);
        ctx_progress(e->ctx, "morph", (double)k / (double)(o->frames - 1));
    }
    return st;
}
