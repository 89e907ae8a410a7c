/* SPDX-License-Identifier: MIT */
/*
 * Times the variants of perf/kernel_variants.cl on an operator written by
 * perf/export_operator (add `rcm` there for the renumbered order): the
 * design measurements behind README "Performance". Plain OpenCL on the first
 * device, one variant at a time from the same starting vectors; prints the
 * best and median of `repeats` steps, GB/s by the base layout's byte model
 * (so that a variant moving fewer bytes shows as a higher rate only if it
 * is faster) and a check value (the last step's sum of |r|^2: equal across
 * variants that compute the same thing).
 *   kernel_variants OPERATOR.bin [VARIANT,... (default: all)] [repeats, default 15]
 * Threads: POCL_MAX_PTHREAD_COUNT. Prefetch distance: -D PD=96 (KERNEL_OPTIONS).
 */
#include <CL/cl.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef KERNEL_SOURCE
#define KERNEL_SOURCE "perf/kernel_variants.cl"
#endif
#define WORKGROUP 8
#define ROWS 256

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static char *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *b = malloc((size_t)n + 1);
    if (b && fread(b, 1, (size_t)n, f) != (size_t)n) {
        free(b);
        b = NULL;
    }
    fclose(f);
    if (b)
        b[n] = '\0';
    *size = (size_t)n;
    return b;
}

#define CK(x)                                                                                  \
    do {                                                                                       \
        cl_int e_ = (x);                                                                       \
        if (e_ != CL_SUCCESS) {                                                                \
            fprintf(stderr, "kernel_variants: %s failed (%d)\n", #x, e_);                     \
            exit(1);                                                                           \
        }                                                                                      \
    } while (0)

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: kernel_variants OPERATOR.bin [VARIANT,...] [repeats]\n");
        return 2;
    }
    const char *all = "d_base,d_pref,d_ro,d_two,d_d16,d_v3,d_local,"
                      "f_base,f_pref,f_two,f_cw,f_d16,f_v3,f_local";
    int repeats = argc > 3 ? atoi(argv[3]) : 15;
    if (repeats < 1 || repeats > 1000)
        repeats = 15;
    size_t size;
    char *op = slurp(argv[1], &size);
    if (!op || size < 16) {
        fprintf(stderr, "kernel_variants: cannot read %s\n", argv[1]);
        return 1;
    }
    uint64_t n64, nnz64;
    memcpy(&n64, op, 8);
    memcpy(&nnz64, op + 8, 8);
    size_t n = (size_t)n64, nnz = (size_t)nnz64;
    uint32_t *ro = (uint32_t *)(op + 16), *col = ro + n + 1;
    double *w = (double *)(col + nnz), *pos = w + nnz;
    /* the layouts the variants read */
    float *wf = malloc(nnz * sizeof *wf);
    uint32_t *cw = malloc(2 * nnz * sizeof *cw);
    int16_t *d16 = malloc(nnz * sizeof *d16);
    double *m4 = calloc(4 * n, sizeof *m4), *m3 = malloc(3 * n * sizeof *m3);
    float *f4 = calloc(4 * n, sizeof *f4), *f3 = malloc(3 * n * sizeof *f3);
    for (size_t k = 0; k < nnz; k++) {
        wf[k] = (float)w[k];
        cw[2 * k] = col[k];
        memcpy(&cw[2 * k + 1], &wf[k], sizeof(float));
    }
    for (size_t i = 0; i < n; i++)
        for (uint32_t k = ro[i]; k < ro[i + 1]; k++)
            d16[k] = (int16_t)((long)col[k] - (long)i); /* only meaningful in RCM order */
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            m4[4 * i + c] = m3[3 * i + c] = pos[3 * i + c];
            f4[4 * i + c] = f3[3 * i + c] = (float)pos[3 * i + c];
        }

    cl_platform_id platform;
    cl_device_id device;
    cl_int err;
    CK(clGetPlatformIDs(1, &platform, NULL));
    CK(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 1, &device, NULL));
    cl_context ctx = clCreateContext(NULL, 1, &device, NULL, NULL, &err);
    CK(err);
    cl_command_queue q = clCreateCommandQueue(ctx, device, 0, &err);
    CK(err);
    size_t len;
    char *src = slurp(KERNEL_SOURCE, &len);
    if (!src) {
        fprintf(stderr, "kernel_variants: cannot read %s\n", KERNEL_SOURCE);
        return 1;
    }
    const char *srcs = src;
    cl_program prog = clCreateProgramWithSource(ctx, 1, &srcs, &len, &err);
    CK(err);
    const char *opts = getenv("KERNEL_OPTIONS") ? getenv("KERNEL_OPTIONS")
                                                : "-D ROWS_PER_ITEM=256 -D PD=96";
    if (clBuildProgram(prog, 1, &device, opts, NULL, NULL) != CL_SUCCESS) {
        static char log[20000];
        clGetProgramBuildInfo(prog, device, CL_PROGRAM_BUILD_LOG, sizeof log, log, NULL);
        fprintf(stderr, "kernel_variants: build failed:\n%s\n", log);
        return 1;
    }
#define BUF(ptr, bytes) clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes, ptr, &err)
    cl_mem b_ro = BUF(ro, (n + 1) * 4), b_col = BUF(col, nnz * 4), b_w = BUF(w, nnz * 8);
    cl_mem b_wf = BUF(wf, nnz * 4), b_cw = BUF(cw, nnz * 8), b_d16 = BUF(d16, nnz * 2);
    cl_mem m_4 = BUF(m4, n * 32), p_4[2] = {BUF(m4, n * 32), BUF(m4, n * 32)};
    cl_mem b_f4 = BUF(f4, n * 16), d_4[2] = {BUF(f4, n * 16), BUF(f4, n * 16)};
    cl_mem m_3 = BUF(m3, n * 24), p_3[2] = {BUF(m3, n * 24), BUF(m3, n * 24)};
    cl_mem b_f3 = BUF(f3, n * 12), d_3[2] = {BUF(f3, n * 12), BUF(f3, n * 12)};
    size_t chunks = (n + ROWS - 1) / ROWS, items = (chunks + WORKGROUP - 1) / WORKGROUP * WORKGROUP;
    cl_mem parts = clCreateBuffer(ctx, CL_MEM_READ_WRITE, items * 24, NULL, &err);
    CK(err);
    double *partials = malloc(items * 24), *times = malloc((size_t)repeats * sizeof *times);

    char *names = strdup(argc > 2 ? argv[2] : all);
    printf("%zu rows, %zu nonzeros, %s\n", n, nnz, opts);
    for (char *name = strtok(names, ","); name; name = strtok(NULL, ",")) {
        cl_kernel k = clCreateKernel(prog, name, &err);
        if (err != CL_SUCCESS) {
            fprintf(stderr, "kernel_variants: no variant %s\n", name);
            return 1;
        }
        int fl = name[0] == 'f', v3 = strstr(name, "v3") != NULL, pairs = strstr(name, "cw") != NULL;
        /* the same starting vectors for every variant */
        for (int i = 0; i < 2; i++) {
            CK(clEnqueueWriteBuffer(q, p_4[i], CL_TRUE, 0, n * 32, m4, 0, NULL, NULL));
            CK(clEnqueueWriteBuffer(q, d_4[i], CL_TRUE, 0, n * 16, f4, 0, NULL, NULL));
            CK(clEnqueueWriteBuffer(q, p_3[i], CL_TRUE, 0, n * 24, m3, 0, NULL, NULL));
            CK(clEnqueueWriteBuffer(q, d_3[i], CL_TRUE, 0, n * 12, f3, 0, NULL, NULL));
        }
        cl_uint rows = (cl_uint)n;
        double omega = 1.0, check = 0.0;
        float omega_f = 1.0f;
        for (int r = 0; r < repeats + 2; r++) {
            cl_uint a = 0;
            int c = r & 1;
            cl_mem *rhs = fl ? (v3 ? &b_f3 : &b_f4) : (v3 ? &m_3 : &m_4);
            cl_mem *x = fl ? (v3 ? d_3 : d_4) : (v3 ? p_3 : p_4);
            CK(clSetKernelArg(k, a++, sizeof rows, &rows));
            CK(clSetKernelArg(k, a++, sizeof(cl_mem), &b_ro));
            if (pairs) {
                CK(clSetKernelArg(k, a++, sizeof(cl_mem), &b_cw));
            } else {
                CK(clSetKernelArg(k, a++, sizeof(cl_mem), strstr(name, "d16") ? &b_d16 : &b_col));
                CK(clSetKernelArg(k, a++, sizeof(cl_mem), fl ? &b_wf : &b_w));
            }
            CK(clSetKernelArg(k, a++, sizeof(cl_mem), rhs));
            CK(clSetKernelArg(k, a++, sizeof(cl_mem), &x[c]));
            CK(clSetKernelArg(k, a++, sizeof(cl_mem), &x[1 - c]));
            CK(clSetKernelArg(k, a++, sizeof(cl_mem), &parts));
            if (fl)
                CK(clSetKernelArg(k, a++, sizeof omega_f, &omega_f));
            else
                CK(clSetKernelArg(k, a++, sizeof omega, &omega));
            size_t global = items, local = WORKGROUP;
            double t = now();
            CK(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, NULL));
            CK(clEnqueueReadBuffer(q, parts, CL_TRUE, 0, chunks * 24, partials, 0, NULL, NULL));
            t = now() - t;
            if (r >= 2) /* two untimed: compile and first touch */
                times[r - 2] = t;
            check = 0.0;
            for (size_t i = 0; i < chunks; i++)
                check += partials[3 * i + 2];
        }
        qsort(times, (size_t)repeats, sizeof *times, cmp_double);
        double bytes = fl ? 8.0 * (double)nnz + 52.0 * (double)n
                          : 12.0 * (double)nnz + 100.0 * (double)n;
        printf("%-8s best %7.2f ms  median %7.2f ms  %6.2f GB/s  check %.9e\n", name,
               times[0] * 1e3, times[repeats / 2] * 1e3, bytes / times[0] / 1e9, check);
        clReleaseKernel(k);
    }
    free(names);
    return 0;
}
