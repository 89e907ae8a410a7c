/* SPDX-License-Identifier: MIT */
/* limn bench: a whole job on a deterministic mesh of a requested size, every
   stage timed, the solve loop's bandwidth against a triad of the same run. */
#include "cli_bench.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *const help =
    "usage: limn bench [--vertices N] [--scheme loop|catmark] [--device SPEC]\n"
    "                  [--host-threads N] [--json FILE] [--repeat R] [-q]\n"
    "\n"
    "Builds a deterministic mesh of about N vertices (loop: an icosahedron, catmark:\n"
    "a cube, refined by limn's own subdivision to the level whose vertex count is\n"
    "nearest N, then gently bumped), writes it as scanners do (binary PLY, float32\n"
    "x y z, uchar/int face lists) in a private temporary directory, and times a\n"
    "real job on it: read, repair, topology, stencil, solve, write of the control\n"
    "mesh (the directory is removed after). Prints seconds and vertices/s per\n"
    "stage, the solve loop's GB/s (docs/performance.md's byte model) and its\n"
    "fraction of a STREAM triad measured on the same device in the same run, peak\n"
    "memory per vertex (before the triad), the device and the thread counts.\n"
    "\n"
    "  --vertices N           mesh size, suffix k, M or G (powers of 1000) [1M]\n"
    "  --scheme S             loop or catmark                          [loop]\n"
    "  --device SPEC          reference | opencl | opencl:P.D | opencl:NAME\n"
    CLI_HOST_THREADS_HELP
    "  --json FILE            also write every figure as JSON (docs/cli.md)\n"
    "  --repeat R             triad runs, the best counts, 1..1000        [5]\n"
    "  --triad-bytes SIZE     bytes of each triad array (K, M, G: powers of\n"
    "                         1024)                                     [128M]\n"
    "  -q, --quiet            no progress and no summary\n"
    "\n"
    "Exit status: 0 success, 1 failure (no JSON written), 2 bad usage.\n";

/* "20k", "8M", "1G" or a plain count (powers of 1000). */
static int parse_count(const char *text, size_t *out)
{
    char *end;
    errno = 0;
    if (text[0] < '0' || text[0] > '9')
        return cli_usage_error("bench", "--vertices '%s' is not a count such as 20k or 8M", text);
    unsigned long long v = strtoull(text, &end, 10);
    unsigned long long scale = *end == 'k' || *end == 'K' ? 1000ULL
                               : *end == 'M'              ? 1000000ULL
                               : *end == 'G'              ? 1000000000ULL
                                                          : 1ULL;
    if (scale > 1)
        end++;
    if (end == text || *end || errno == ERANGE)
        return cli_usage_error("bench", "--vertices '%s' is not a count such as 20k or 8M", text);
    if (v > 4000000000ULL / scale || v * scale < 100)
        return cli_usage_error("bench", "--vertices %s is outside 100..4G", text);
    *out = (size_t)(v * scale);
    return 0;
}

static int value_option(bench_args *b, const char *opt, const char *v)
{
    if (strcmp(opt, "--vertices") == 0)
        return parse_count(v, &b->vertices);
    if (strcmp(opt, "--scheme") == 0) {
        if (strcmp(v, "loop") && strcmp(v, "catmark"))
            return cli_usage_error("bench", "--scheme '%s' is not one of loop, catmark", v);
        b->scheme = v[0] == 'l' ? LIMN_SCHEME_LOOP : LIMN_SCHEME_CATMARK;
        return 0;
    }
    if (strcmp(opt, "--host-threads") == 0)
        return cli_parse_host_threads("bench", v, &b->host_threads);
    if (strcmp(opt, "--repeat") == 0) {
        if (!cli_parse_int(opt, v, &b->repeat))
            return EXIT_USAGE;
        return b->repeat >= 1 && b->repeat <= 1000
                   ? 0
                   : cli_usage_error("bench", "--repeat %s is outside 1..1000", v);
    }
    if (strcmp(opt, "--triad-bytes") == 0) {
        if (!cli_parse_size(opt, v, &b->triad_bytes))
            return EXIT_USAGE;
        return b->triad_bytes >= 32 ? 0
                                    : cli_usage_error("bench", "--triad-bytes %s: at least 32", v);
    }
    if (strcmp(opt, "--device") == 0)
        b->device = v;
    else
        b->json = v; /* --json */
    return 0;
}

/* 0, -1 (help printed) or an exit status. */
static int parse(int argc, char **argv, bench_args *b)
{
    *b = (bench_args){.vertices = 1000000, .scheme = LIMN_SCHEME_LOOP, .repeat = 5,
                      .triad_bytes = (size_t)128 << 20};
    static const struct option longopts[] = {
        CLI_FLAG("help"),        CLI_FLAG("quiet"),        CLI_VALUE("vertices"),
        CLI_VALUE("scheme"),     CLI_VALUE("device"),      CLI_VALUE("host-threads"),
        CLI_VALUE("json"),       CLI_VALUE("repeat"),      CLI_VALUE("triad-bytes"),
        CLI_OPTIONS_END};
    int rc = cli_options("bench", longopts, "hq", &argc, &argv);
    for (int i = 1; !rc && i < argc; i++) {
        const char *s = argv[i];
        if (strcmp(s, "-h") == 0 || strcmp(s, "--help") == 0) {
            fputs(help, stdout);
            return -1;
        }
        if (strcmp(s, "-q") == 0 || strcmp(s, "--quiet") == 0) {
            b->quiet = 1;
            continue;
        }
        if (s[0] != '-' || !s[1])
            return cli_usage_error("bench", "unexpected argument '%s' (bench reads no file)", s);
        const char *v = cli_value(argc, argv, &i);
        rc = v ? value_option(b, s, v) : cli_usage_error("bench", "%s needs a value", s);
    }
    if (!rc && b->json) {
        const char *outputs[] = {b->json};
        rc = cli_check_outputs("bench", outputs, 1);
    }
    return rc;
}

/* Bytes the solve loop must move (docs/performance.md, perf/run_suite.py's
   solve_bytes): a product's CSR table (4-byte column and 8-byte weight a
   nonzero, 4 + 4 in float, a 4-byte row offset a row) and its vector
   streams once (3: m, p read and p_next written; chebyshev 4; sgs 18), 32
   bytes a vertex each in double, 16 in float; a mixed solve's double
   products are residuals (m, p read, a float r written). */
double bench_loop_bytes(const limn_report *r)
{
    double nnz = (double)r->stencil_nonzeros, n = (double)r->vertices;
    double streams = strcmp(r->method, "chebyshev") == 0 ? 4 : strcmp(r->method, "sgs") == 0 ? 18 : 3;
    double nf = r->products_float;
    if (nf > 0) {
        double residual = 12 * nnz + (4 + 32 + 32 + 16) * n;
        return residual * (r->products - nf) + (8 * nnz + (4 + streams * 16) * n) * nf;
    }
    return (12 * nnz + (4 + streams * 32) * n) * r->products;
}

static void progress(const bench_args *b, const char *what)
{
    if (!b->quiet && isatty(2))
        fprintf(stderr, "limn bench: %s\n", what);
}

/* The job on the written file, every stage timed (bench_figures). */
static limn_status run_job(const bench_args *b, limn_context *ctx, const char *in,
                           const char *out, bench_figures *f)
{
    limn_mesh *mesh = NULL, *control = NULL;
    limn_repair_report rr = {.size = sizeof rr};
    double t0 = cli_now();
    progress(b, "reading");
    limn_status st = limn_mesh_read(ctx, in, LIMN_FORMAT_PLY, &mesh);
    f->read = cli_now() - t0;
    if (!st) {
        progress(b, "repairing");
        st = limn_mesh_repair(ctx, mesh, NULL, &rr);
    }
    f->repair = cli_now() - t0 - f->read;
    if (!st) {
        cli_progress_enable(ctx, b->quiet);
        limn_interpolate_options o;
        limn_interpolate_options_default(&o);
        o.scheme = b->scheme;
        st = limn_interpolate(ctx, mesh, &o, &control, &f->r);
        cli_progress_done();
    }
    double t1 = cli_now();
    if (!st) {
        progress(b, "writing the control mesh");
        st = limn_mesh_write(ctx, control, out, LIMN_FORMAT_PLY);
    }
    f->write = cli_now() - t1;
    f->total = cli_now() - t0;
    f->peak_rss = cli_peak_rss(); /* the job's peak: before the triad */
    limn_mesh_destroy(control);
    limn_mesh_destroy(mesh);
    return st;
}

/* The input file, made in a child process (a context of its own on the
   reference backend): the job's peak memory is then the job's alone, and its
   context opens the device and pays its set-up as a real run does. The
   child's figures come back through a pipe. */
typedef struct made {
    int levels, ok;
    size_t faces, file_bytes;
    double generate, write_input;
} made;

static void make_input(const bench_args *b, const char *in, made *m)
{
    limn_mesh *mesh = NULL;
    double t0 = cli_now();
    progress(b, "building the mesh");
    limn_context *gen = limn_context_create();
    limn_status st = gen ? limn_context_set_device(gen, "reference")
                         : cli_error(LIMN_ERR_MEMORY, "out of memory");
    if (!st)
        st = limn_context_set_host_threads(gen, b->host_threads);
    if (!st)
        st = bench_mesh(gen, b, &mesh, &m->levels);
    m->generate = cli_now() - t0;
    if (!st) {
        m->faces = limn_mesh_face_count(mesh);
        progress(b, "writing it as float32 binary PLY");
        st = bench_write_scanner_ply(mesh, in, &m->file_bytes);
    }
    m->write_input = cli_now() - t0 - m->generate;
    m->ok = !st;
    if (st)
        cli_fail("bench", gen, st);
    limn_mesh_destroy(mesh);
    limn_context_destroy(gen);
}

static limn_status make_input_apart(const bench_args *b, const char *in, bench_figures *f)
{
    int fd[2];
    made m = {0};
    if (pipe(fd) != 0)
        return cli_error(LIMN_ERR_IO, "pipe: %s", strerror(errno));
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        make_input(b, in, &m);
        _exit(write(fd[1], &m, sizeof m) == (ssize_t)sizeof m && m.ok ? 0 : 1);
    }
    close(fd[1]);
    ssize_t got = pid > 0 ? read(fd[0], &m, sizeof m) : -1;
    close(fd[0]);
    int status = 0;
    if (pid > 0)
        waitpid(pid, &status, 0);
    if (pid < 0)
        return cli_error(LIMN_ERR_MEMORY, "fork: %s", strerror(errno));
    if (got != (ssize_t)sizeof m || !m.ok || !WIFEXITED(status) || WEXITSTATUS(status))
        return cli_error(LIMN_ERR_IO, "the input mesh could not be made (see above)");
    f->levels = m.levels;
    f->faces = m.faces;
    f->file_bytes = m.file_bytes;
    f->generate = m.generate;
    f->write_input = m.write_input;
    return LIMN_OK;
}

/* The input, the job and the triad; the temporary directory removed in any
   case. */
static limn_status bench_run(const bench_args *b, limn_context *ctx, bench_figures *f)
{
    char dir[4096], in[4200], out[4200];
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/limn_bench_XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(dir))
        return cli_error(LIMN_ERR_IO, "cannot make a temporary directory %s: %s", dir,
                         strerror(errno));
    snprintf(in, sizeof in, "%s/mesh_f32.ply", dir);
    snprintf(out, sizeof out, "%s/control.ply", dir);
    limn_status st = make_input_apart(b, in, f);
    if (!st)
        st = run_job(b, ctx, in, out, f);
    remove(in);
    remove(out);
    rmdir(dir);
    if (!st) {
        progress(b, "measuring the triad");
        f->triad.size = sizeof f->triad;
        st = limn_device_triad(ctx, b->triad_bytes, b->repeat, &f->triad);
    }
    return st;
}

int cli_bench(int argc, char **argv)
{
    bench_args b;
    int rc = parse(argc, argv, &b);
    if (rc)
        return rc < 0 ? 0 : rc;
    limn_context *ctx = limn_context_create();
    if (!ctx) {
        fprintf(stderr, "limn bench: error: out of memory\n");
        return EXIT_FAILURE_RUN;
    }
    bench_figures f = {.r = {.size = sizeof f.r}};
    limn_status st = limn_context_set_host_threads(ctx, b.host_threads);
    if (!st)
        st = limn_context_set_device(ctx, b.device);
    if (!st)
        st = bench_run(&b, ctx, &f);
    if (!st) {
        limn_context_threads(ctx, &f.threads, &f.threads_source);
        limn_context_host_threads(ctx, &f.host_threads, &f.host_threads_source);
        if (f.triad.mismatches)
            st = cli_error(LIMN_ERR_DEVICE, "the triad's result on %s is wrong in %zu of %zu "
                                            "elements",
                           f.triad.device, f.triad.mismatches, f.triad.elements);
    }
    if (!st && b.json)
        st = bench_json(ctx, &b, &f);
    if (st)
        rc = cli_fail("bench", ctx, st);
    else if (!b.quiet)
        bench_print(&b, &f);
    limn_context_destroy(ctx);
    return rc;
}
