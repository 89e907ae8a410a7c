/* SPDX-License-Identifier: MIT */
/*
 * A headless picture of a mesh: orthographic view from an azimuth and an
 * elevation, z-buffer, Lambert shading (two-sided, one directional light
 * plus ambient) with per-pixel interpolated vertex normals ("smooth") or face
 * normals ("flat"), vertex colours when the mesh has them, and supersampling
 * for anti-aliasing. Polygons are fan-triangulated. Plain C, deterministic.
 */
#include "base/abi.h"
#include "mesh/check.h"
#include "base/context.h"
#include "base/vec3.h"
#include "topology/measure.h"
#include "mesh/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void limn_render_options_default(limn_render_options *o)
{
    abi_default(&abi_render_options, o);
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
static void normalize3(double *v)
{
    double l = sqrt(vec3_dot(v, v));
    if (l > 0)
        for (int c = 0; c < 3; c++)
            v[c] /= l;
}

typedef struct raster {
    int w, h;
    float *depth;            /* larger is nearer */
    float *color;            /* 3 per sample */
    double eye[3], light[3];
} raster;

typedef struct vert {
    double x, y, z;          /* pixel coordinates and depth */
    double n[3];             /* normal (world) */
    double c[3];             /* base colour in [0, 1] */
} vert;

static double shade(const raster *r, const double *normal)
{
    double n[3] = {normal[0], normal[1], normal[2]};
    normalize3(n);
    if (vec3_dot(n, r->eye) < 0) /* two-sided */
        for (int c = 0; c < 3; c++)
            n[c] = -n[c];
    double d = vec3_dot(n, r->light);
    return 0.22 + 0.78 * (d > 0 ? d : 0.0);
}

static void triangle(raster *r, const vert *a, const vert *b, const vert *c, int flat,
                     const double *face_normal)
{
    double area = (b->x - a->x) * (c->y - a->y) - (b->y - a->y) * (c->x - a->x);
    if (area == 0.0)
        return;
    int x0 = (int)floor(fmin(a->x, fmin(b->x, c->x))), x1 = (int)ceil(fmax(a->x, fmax(b->x, c->x)));
    int y0 = (int)floor(fmin(a->y, fmin(b->y, c->y))), y1 = (int)ceil(fmax(a->y, fmax(b->y, c->y)));
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > r->w - 1 ? r->w - 1 : x1;
    y1 = y1 > r->h - 1 ? r->h - 1 : y1;
    double flat_shade = flat ? shade(r, face_normal) : 0.0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            double px = x + 0.5, py = y + 0.5;
            double w0 = ((b->x - px) * (c->y - py) - (b->y - py) * (c->x - px)) / area;
            double w1 = ((c->x - px) * (a->y - py) - (c->y - py) * (a->x - px)) / area;
            double w2 = 1.0 - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0)
                continue;
            double z = w0 * a->z + w1 * b->z + w2 * c->z;
            size_t k = (size_t)y * (size_t)r->w + (size_t)x;
            if (z <= r->depth[k])
                continue;
            r->depth[k] = (float)z;
            double s = flat_shade;
            if (!flat) {
                double n[3];
                for (int j = 0; j < 3; j++)
                    n[j] = w0 * a->n[j] + w1 * b->n[j] + w2 * c->n[j];
                s = shade(r, n);
            }
            for (int j = 0; j < 3; j++)
                r->color[3 * k + j] = (float)(s * (w0 * a->c[j] + w1 * b->c[j] + w2 * c->c[j]));
        }
}

/* The options limn_render can draw with. */
static limn_status check_view(limn_context *ctx, const limn_render_options *o)
{
    if (o->width < 1 || o->height < 1 || o->width > 16384 || o->height > 16384)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "picture size %dx%d is outside 1..16384", o->width,
                         o->height);
    if (o->supersample < 1 || o->supersample > 4)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "supersampling %d is outside 1..4",
                         o->supersample);
    if (o->up_axis < 0 || o->up_axis > 2)
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "up axis %d is not 0, 1 or 2", o->up_axis);
    if (!isfinite(o->azimuth) || !isfinite(o->elevation))
        return ctx_fail(ctx, LIMN_ERR_ARGUMENT, "the view angles must be finite");
    return LIMN_OK;
}

/* The camera: U up, F front, R = U x F to the right at azimuth 0; r->eye
   and r->light, and the picture's right and up directions. */
static void place_camera(raster *r, const limn_render_options *o, double right[3], double up[3])
{
    double U[3] = {0, 0, 0}, F[3] = {0, 0, 0}, R[3];
    U[o->up_axis] = 1.0;
    F[(o->up_axis + 1) % 3] = 1.0;
    cross3(U, F, R);
    const double deg = 3.14159265358979323846 / 180.0;
    double az = o->azimuth * deg, el = o->elevation * deg;
    for (int j = 0; j < 3; j++) {
        r->eye[j] = cos(el) * (sin(az) * R[j] + cos(az) * F[j]) + sin(el) * U[j];
        right[j] = cos(az) * R[j] - sin(az) * F[j];
    }
    cross3(r->eye, right, up);
    for (int j = 0; j < 3; j++)
        r->light[j] = 0.75 * r->eye[j] + 0.55 * up[j] - 0.35 * right[j];
    normalize3(r->light);
}

/* Vertex normals (area-weighted Newell normals) into v, and the vertices
   faces use. */
static void vertex_normals(const limn_mesh *mesh, vert *v, unsigned char *used)
{
    for (size_t f = 0; f < mesh->face_count; f++) {
        double fn[3];
        measure_face_normal(mesh->positions, mesh->face_offsets, mesh->face_indices, f, fn);
        for (uint32_t k = mesh->face_offsets[f]; k < mesh->face_offsets[f + 1]; k++) {
            vert *p = v + mesh->face_indices[k];
            for (int j = 0; j < 3; j++)
                p->n[j] += fn[j];
            used[mesh->face_indices[k]] = 1;
        }
    }
}

/* The vertices in picture coordinates (the used ones fill 90% of it) and
   their colours. */
static void project(const limn_mesh *mesh, const limn_render_options *o, const raster *r,
                    const double right[3], const double up[3], const unsigned char *used,
                    vert *v)
{
    size_t n = mesh->vertex_count;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++) {
        const double *p = mesh->positions + 3 * i;
        v[i].x = vec3_dot(p, right);
        v[i].y = vec3_dot(p, up);
        v[i].z = vec3_dot(p, r->eye);
        for (int j = 0; j < 3; j++)
            v[i].c[j] = (mesh->colors ? mesh->colors[3 * i + j] : o->color[j]) / 255.0;
        if (used[i]) {
            lo[0] = fmin(lo[0], v[i].x), hi[0] = fmax(hi[0], v[i].x);
            lo[1] = fmin(lo[1], v[i].y), hi[1] = fmax(hi[1], v[i].y);
        }
    }
    double dx = hi[0] - lo[0], dy = hi[1] - lo[1];
    double scale = 0.9 * fmin(r->w / (dx > 0 ? dx : 1.0), r->h / (dy > 0 ? dy : 1.0));
    if (!(dx > 0) && !(dy > 0))
        scale = 1.0;
    double mx = 0.5 * (lo[0] + hi[0]), my = 0.5 * (lo[1] + hi[1]);
    for (size_t i = 0; i < n; i++) {
        v[i].x = 0.5 * r->w + scale * (v[i].x - mx);
        v[i].y = 0.5 * r->h - scale * (v[i].y - my);
    }
}

/* Each face as a fan of triangles. */
static void draw_faces(raster *r, const limn_mesh *mesh, const vert *v, int flat)
{
    for (size_t f = 0; f < mesh->face_count; f++) {
        double fn[3];
        measure_face_normal(mesh->positions, mesh->face_offsets, mesh->face_indices, f, fn);
        uint32_t b = mesh->face_offsets[f], e = mesh->face_offsets[f + 1];
        for (uint32_t k = b + 1; k + 1 < e; k++)
            triangle(r, &v[mesh->face_indices[b]], &v[mesh->face_indices[k]],
                     &v[mesh->face_indices[k + 1]], flat, fn);
    }
}

/* Box filter of the ss x ss samples down to the picture. */
static void downsample(const raster *r, int ss, int width, int height, uint8_t *rgb)
{
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++)
            for (int j = 0; j < 3; j++) {
                double s = 0.0;
                for (int sy = 0; sy < ss; sy++)
                    for (int sx = 0; sx < ss; sx++)
                        s += r->color[3 * ((size_t)(y * ss + sy) * (size_t)r->w +
                                           (size_t)(x * ss + sx)) +
                                      j];
                s /= ss * ss;
                s = s < 0 ? 0 : s > 1 ? 1 : s;
                rgb[3 * ((size_t)y * (size_t)width + (size_t)x) + j] =
                    (uint8_t)lround(s * 255.0);
            }
}

limn_status limn_render(limn_context *ctx, const limn_mesh *mesh,
                        const limn_render_options *options, uint8_t *rgb)
{
    limn_status checked = abi_begin(ctx, "limn_render", "rgb", rgb);
    if (!checked)
        checked = check_mesh_magnitude(ctx, "limn_render", NULL, mesh);
    if (checked)
        return checked;
    limn_render_options o;
    limn_render_options_default(&o);
    checked = abi_options_in(ctx, "limn_render", "options", &abi_render_options, options, &o);
    if (!checked)
        checked = check_view(ctx, &o);
    if (checked)
        return checked;

    int ss = o.supersample;
    raster r = {.w = o.width * ss, .h = o.height * ss};
    size_t samples = (size_t)r.w * (size_t)r.h, n = mesh->vertex_count;
    r.depth = malloc(samples * sizeof *r.depth);
    r.color = malloc(3 * samples * sizeof *r.color);
    vert *v = calloc(n ? n : 1, sizeof *v);
    if (!r.depth || !r.color || !v) {
        free(r.depth);
        free(r.color);
        free(v);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for a %dx%d picture", o.width,
                         o.height);
    }
    for (size_t k = 0; k < samples; k++) {
        r.depth[k] = -INFINITY;
        for (int j = 0; j < 3; j++)
            r.color[3 * k + j] = (float)(o.background[j] / 255.0);
    }
    double right[3], up[3];
    place_camera(&r, &o, right, up);
    unsigned char *used = calloc(n ? n : 1, 1);
    if (!used) {
        free(r.depth);
        free(r.color);
        free(v);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for %zu vertices", n);
    }
    vertex_normals(mesh, v, used);
    project(mesh, &o, &r, right, up, used, v);
    draw_faces(&r, mesh, v, o.flat);
    downsample(&r, ss, o.width, o.height, rgb);
    free(used);
    free(r.depth);
    free(r.color);
    free(v);
    return LIMN_OK;
}
