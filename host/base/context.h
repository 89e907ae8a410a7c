/* SPDX-License-Identifier: MIT */
/* The per-caller context: error message, warnings, device choice. */
#ifndef LIMN_CONTEXT_H
#define LIMN_CONTEXT_H

#include "limn.h"
#include <stdarg.h>

struct device;

struct limn_context {
    char message[2048];
    char *long_message;       /* heap: the whole message when it outgrew message[] (a
                                 build log); shown while message[0] is set */
    char *warnings;           /* heap, grows; NULL when empty */
    size_t warnings_len;
    limn_progress_fn progress;
    void *progress_user;
    char device_spec[256];    /* "" = from the environment */
    struct device *device; /* opened lazily */
    char device_name[256];
    int fallback;             /* 0: from LIMN_FALLBACK; 1: none; 2: the reference backend */
    int device_failed;        /* the last LIMN_ERR_MEMORY came from the OpenCL device */
    int device_slot;          /* of the OpenCL devices matching the choice, take number
                                 slot % count (MPI: the rank on its node); 0 = the first */
    int threads_request;      /* limn_context_set_threads; 0 = from the CPU binding */
    int host_threads_request; /* limn_context_set_host_threads; 0 = as threads_request */
    int host_threads_counted; /* cores in the binding (< 0: CPUs of the mask); 0 = not yet */
    size_t max_memory;        /* limn_context_set_max_memory; 0 = 3/4 of physical memory */
};

/* Records a failure message and returns status (for `return ctx_fail(...)`). */
limn_status ctx_fail(limn_context *ctx, limn_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Appends one warning line. */
void ctx_warn(limn_context *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Clears message and warnings at the start of a public call. */
void ctx_clear(limn_context *ctx);
void ctx_progress(limn_context *ctx, const char *stage, double fraction);
/* The readers' memory limit in bytes: the context's setting, else three
   quarters of physical memory (SIZE_MAX when that is unknown). */
size_t context_max_memory(const limn_context *ctx);

#endif
