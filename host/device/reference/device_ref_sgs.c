/* SPDX-License-Identifier: MIT */
/*
 * The reference backend's sweeps of the SGS-preconditioned conjugate
 * gradients: kernels/sgs.cl in plain C, the same operations in the same
 * order (built with -ffp-contract=off), the same chunks of rows for the
 * reductions, colour by colour, so both backends agree bit for bit.
 */
#include "device/reference/device_ref.h"
#include "base/vec3.h"

#include <math.h>

typedef struct sgs_view {
    const uint32_t *ro, *col, *split;
    const double *w, *info;
} sgs_view;

static sgs_view view_of(const device_sgs *a)
{
    sgs_view v = {a->row_offsets->data, a->columns->data, a->split->data, a->weights->data,
                  a->info->data};
    return v;
}

/* acc = sum over entries [from, to) of w_k x_col(k), component by component */
static void part(const sgs_view *s, uint32_t from, uint32_t to, const double *x, double acc[3])
{
    acc[0] = acc[1] = acc[2] = 0.0;
    for (uint32_t k = from; k < to; k++) {
        const double *xj = x + 4 * (size_t)s->col[k];
        for (int c = 0; c < 3; c++)
            acc[c] += s->w[k] * xj[c];
    }
}

static limn_status ref_sgs_upper(struct device *dev, const device_sgs *a, double beta,
                                 const sgs_vectors *v)
{
    sgs_view s = view_of(a);
    const double *rhat = v->rhat->data;
    double *phat = v->phat->data, *t = v->t->data;
    for (size_t c = a->colours; c-- > 0;)
        for (size_t i = a->colour_begin[c]; i < a->colour_begin[c + 1]; i++) {
            const double *in = s.info + 4 * i;
            double *p = phat + 4 * i, acc[3];
            for (int k = 0; k < 3; k++)
                p[k] = rhat[4 * i + k] + beta * p[k];
            p[3] = 0.0;
            part(&s, s.split[i], s.ro[i + 1], t, acc);
            for (int k = 0; k < 3; k++)
                t[4 * i + k] = (in[1] * p[k] - acc[k]) / in[0];
            t[4 * i + 3] = 0.0;
        }
    (void)dev;
    return LIMN_OK;
}

/* acc_x and acc_u over entries [from, to): two sums side by side */
static void part2(const sgs_view *s, uint32_t from, uint32_t to, const double *x,
                  const double *u, double ax[3], double au[3])
{
    ax[0] = ax[1] = ax[2] = au[0] = au[1] = au[2] = 0.0;
    for (uint32_t k = from; k < to; k++) {
        const double *xj = x + 4 * (size_t)s->col[k], *uj = u + 4 * (size_t)s->col[k];
        for (int c = 0; c < 3; c++) {
            ax[c] += s->w[k] * xj[c];
            au[c] += s->w[k] * uj[c];
        }
    }
}

/* Row i of the start sweep: r_i, u_i, rhat_i; its length scale |r_i| in *len. */
static double start_row(const sgs_view *s, size_t i, const sgs_vectors *v, double *len)
{
    const double *in = s->info + 4 * i, *b = v->b->data, *x = v->x->data;
    double *r = v->r->data, *u = v->u->data, *rhat = v->rhat->data;
    double lx[3], lu[3], hx[3];
    part2(s, s->ro[i], s->split[i], x, u, lx, lu);
    part(s, s->split[i], s->ro[i + 1], x, hx);
    for (int k = 0; k < 3; k++)
        r[4 * i + k] = b[4 * i + k] - ((in[0] * x[4 * i + k] + lx[k]) + hx[k]);
    r[4 * i + 3] = 0.0;
    *len = in[2] * sqrt(vec3_dot(r + 4 * i, r + 4 * i));
    for (int k = 0; k < 3; k++) {
        u[4 * i + k] = (r[4 * i + k] - lu[k]) / in[0];
        rhat[4 * i + k] = in[1] * u[4 * i + k];
    }
    u[4 * i + 3] = rhat[4 * i + 3] = 0.0;
    return vec3_dot(rhat + 4 * i, rhat + 4 * i);
}

/* Row i of a step's sweep: u_i, st_i; returns phat_i . q_i. */
static double step_row(const sgs_view *s, size_t i, const sgs_vectors *v)
{
    const double *in = s->info + 4 * i, *p = (const double *)v->phat->data + 4 * i;
    const double *t = v->t->data, *ti = t + 4 * i;
    double *u = v->u->data, *st = v->st->data, *ui = u + 4 * i;
    double lt[3], lu[3], vv[3], q[3];
    part2(s, s->ro[i], s->split[i], t, u, lt, lu);
    for (int k = 0; k < 3; k++) {
        vv[k] = in[1] * p[k];
        ui[k] = ((vv[k] - in[0] * ti[k]) - lu[k]) / in[0];
    }
    ui[3] = 0.0;
    for (int k = 0; k < 3; k++) {
        st[4 * i + k] = vv[k] + lt[k];
        q[k] = in[1] * (ti[k] + ui[k]);
    }
    st[4 * i + 3] = 0.0;
    return vec3_dot(p, q);
}

/* The forward sweep over one chunk of one colour: n[0] = max scale_i |r_i|
   (start), n[1] = the sum of the rows' dot products. */
typedef struct sgs_sweep {
    const sgs_view *s;
    const sgs_vectors *v;
    int start;
    double alpha; /* sgs_update */
} sgs_sweep;

static void lower_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const sgs_sweep *w = user;
    for (size_t i = begin; i < end; i++) {
        if (w->start) {
            double len;
            n[1] += start_row(w->s, i, w->v, &len);
            n[0] = len > n[0] ? len : n[0];
        } else {
            n[1] += step_row(w->s, i, w->v);
        }
    }
}

static limn_status ref_sgs_lower(struct device *dev, const device_sgs *a, int start,
                                 const sgs_vectors *v, device_norms *out)
{
    sgs_view s = view_of(a);
    sgs_sweep w = {&s, v, start, 0.0};
    out->max = out->sum = out->sum_sq = 0.0;
    for (size_t c = 0; c < a->colours; c++) {
        device_norms n;
        ref_chunks(a->colour_begin[c], a->colour_begin[c + 1] - a->colour_begin[c], lower_chunk,
                   &w, &n);
        out->max = n.max > out->max ? n.max : out->max;
        out->sum += n.sum;
    }
    (void)dev;
    return LIMN_OK;
}

static void update_chunk(void *user, size_t begin, size_t end, double n[3])
{
    const sgs_sweep *w = user;
    const sgs_vectors *v = w->v;
    const double *t = v->t->data, *u = v->u->data, *st = v->st->data, alpha = w->alpha;
    double *x = v->x->data, *r = v->r->data, *rhat = v->rhat->data;
    for (size_t i = begin; i < end; i++) {
        const double *in = w->s->info + 4 * i, *ti = t + 4 * i;
        for (int k = 0; k < 3; k++) {
            x[4 * i + k] = x[4 * i + k] + alpha * ti[k];
            r[4 * i + k] = r[4 * i + k] - alpha * st[4 * i + k];
            rhat[4 * i + k] = rhat[4 * i + k] - alpha * (in[1] * (ti[k] + u[4 * i + k]));
        }
        x[4 * i + 3] = r[4 * i + 3] = rhat[4 * i + 3] = 0.0;
        double len = in[2] * sqrt(vec3_dot(r + 4 * i, r + 4 * i));
        n[0] = len > n[0] ? len : n[0];
        n[1] += vec3_dot(rhat + 4 * i, rhat + 4 * i);
    }
}

static limn_status ref_sgs_update(struct device *dev, const device_sgs *a, double alpha,
                                  const sgs_vectors *v, device_norms *norms)
{
    sgs_view s = view_of(a);
    sgs_sweep w = {&s, v, 0, alpha};
    ref_chunks(0, a->rows, update_chunk, &w, norms);
    (void)dev;
    return LIMN_OK;
}

const device_sgs_ops ref_sgs_ops = {ref_sgs_upper, ref_sgs_lower, ref_sgs_update};
