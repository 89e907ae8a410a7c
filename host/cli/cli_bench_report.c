/* SPDX-License-Identifier: MIT */
/* limn bench's figures: the summary it prints and its JSON (keys listed in
   docs/cli.md "limn bench"). */
#include "cli_bench.h"

#include <string.h>

/* The job's stages in order, their seconds from f. */
typedef struct bench_stage {
    const char *name;
    double seconds;
} bench_stage;

static double opencl_setup(const limn_report *r)
{
    return r->seconds_opencl_platform + r->seconds_opencl_context + r->seconds_opencl_build +
           r->seconds_opencl_kernels;
}

static int stages(const bench_figures *f, bench_stage s[9])
{
    const bench_stage all[] = {
        {"read", f->read},         {"repair", f->repair},
        {"opencl_setup", opencl_setup(&f->r)},
        {"topology", f->r.seconds_topology},   {"stencil", f->r.seconds_stencil},
        {"solve", f->r.seconds_solve},         {"iterations", f->r.seconds_iterations},
        {"write", f->write},       {"total", f->total}};
    memcpy(s, all, sizeof all);
    return (int)(sizeof all / sizeof *all);
}

static double per_second(double count, double seconds) { return seconds > 0 ? count / seconds : 0; }

/* Below this a stage did not run here: the topology is the repair's, reused
   by the operator (one topology per run), so its rate would be noise. */
#define STAGE_RAN 1e-3

static double loop_gb_per_s(const bench_figures *f)
{
    return per_second(bench_loop_bytes(&f->r) * 1e-9, f->r.seconds_iterations);
}

void bench_print(const bench_args *b, const bench_figures *f)
{
    cli_locale loc;
    int entered = cli_locale_enter(&loc);
    const limn_report *r = &f->r;
    printf("limn bench: %s, %zu vertices (%s refined %d times, asked %zu), %zu faces\n",
           limn_scheme_name(r->scheme), r->vertices,
           b->scheme == LIMN_SCHEME_LOOP ? "icosahedron" : "cube", f->levels, b->vertices,
           f->faces);
    printf("  input: float32 binary PLY, %.1f MB (made in %.3f s, written in %.3f s)\n",
           (double)f->file_bytes * 1e-6, f->generate, f->write_input);
    printf("  solve: %s, %s, %d iterations, %.3g products, max error %.3g\n", r->method,
           r->precision ? r->precision : "double", r->iterations, r->products, r->max_rel_error);
    printf("  %-13s %10s %14s\n", "stage", "seconds", "vertices/s");
    bench_stage s[9];
    int n = stages(f, s);
    for (int k = 0; k < n; k++)
        if (s[k].seconds < STAGE_RAN)
            printf("  %-13s %10.3f %14s\n", s[k].name, s[k].seconds,
                   strcmp(s[k].name, "topology") == 0 ? "(in repair)" : "-");
        else
            printf("  %-13s %10.3f %14.4g\n", s[k].name, s[k].seconds,
                   per_second((double)r->vertices, s[k].seconds));
    double gb = loop_gb_per_s(f);
    printf("  solve loop: %.3g GB moved, %.3g GB/s = %.0f%% of the triad (%.3g GB/s, "
           "%.0f MiB arrays, best of %d)\n",
           bench_loop_bytes(r) * 1e-9, gb, 100 * per_second(gb, f->triad.gb_per_s),
           f->triad.gb_per_s, (double)f->triad.array_bytes / (1 << 20), f->triad.repeats);
    printf("  peak memory: %.0f MB, %.0f bytes a vertex\n", (double)f->peak_rss * 1e-6,
           per_second((double)f->peak_rss, (double)r->vertices));
    printf("  device: %s; OpenCL threads %d (%s), host threads %d (%s)\n", r->device,
           f->threads, f->threads_source, f->host_threads, f->host_threads_source);
    if (entered)
        cli_locale_leave(&loc);
}

static void json_mesh(json_out *j, const bench_args *b, const bench_figures *f)
{
    const limn_report *r = &f->r;
    json_string(j, "command", "bench");
    json_string(j, "scheme", limn_scheme_name(r->scheme));
    json_string(j, "base_mesh", b->scheme == LIMN_SCHEME_LOOP ? "icosahedron" : "cube");
    json_integer(j, "levels", f->levels);
    json_integer(j, "vertices_requested", (long long)b->vertices);
    json_integer(j, "vertices", (long long)r->vertices);
    json_integer(j, "faces", (long long)f->faces);
    json_integer(j, "input_bytes", (long long)f->file_bytes);
    json_integer(j, "stencil_nonzeros", (long long)r->stencil_nonzeros);
    json_string(j, "method", r->method);
    json_string(j, "precision", r->precision ? r->precision : "double");
    json_integer(j, "iterations", r->iterations);
    json_number(j, "products", r->products);
    json_number(j, "products_float", r->products_float);
    json_number(j, "max_rel_error", r->max_rel_error);
    json_string(j, "device", r->device);
    json_integer(j, "threads", f->threads);
    json_string(j, "threads_source", f->threads_source);
    json_integer(j, "host_threads", f->host_threads);
    json_string(j, "host_threads_source", f->host_threads_source);
    json_integer(j, "peak_rss_bytes", (long long)f->peak_rss);
    json_number(j, "peak_bytes_per_vertex", per_second((double)f->peak_rss, (double)r->vertices));
}

limn_status bench_json(limn_context *ctx, const bench_args *b, const bench_figures *f)
{
    json_out *j = json_begin();
    if (!j)
        return cli_error(LIMN_ERR_MEMORY, "out of memory writing %s", b->json);
    json_mesh(j, b, f);
    bench_stage s[9];
    int n = stages(f, s);
    json_object_begin(j, "seconds");
    json_number(j, "generate", f->generate);
    json_number(j, "write_input", f->write_input);
    for (int k = 0; k < n; k++)
        json_number(j, s[k].name, s[k].seconds);
    json_object_end(j);
    json_object_begin(j, "vertices_per_second");
    for (int k = 0; k < n; k++)
        json_number(j, s[k].name,
                    s[k].seconds < STAGE_RAN ? 0 : per_second((double)f->r.vertices, s[k].seconds));
    json_object_end(j);
    json_object_begin(j, "solve_loop");
    json_number(j, "bytes", bench_loop_bytes(&f->r));
    json_number(j, "gb_per_s", loop_gb_per_s(f));
    json_number(j, "triad_fraction", per_second(loop_gb_per_s(f), f->triad.gb_per_s));
    json_object_end(j);
    json_object_begin(j, "triad");
    json_integer(j, "array_bytes", (long long)f->triad.array_bytes);
    json_integer(j, "repeats", f->triad.repeats);
    json_number(j, "seconds_best", f->triad.seconds_best);
    json_number(j, "seconds_mean", f->triad.seconds_mean);
    json_number(j, "gb_per_s", f->triad.gb_per_s);
    json_integer(j, "mismatches", (long long)f->triad.mismatches);
    json_string(j, "device", f->triad.device);
    json_object_end(j);
    return json_commit(ctx, j, b->json);
}
