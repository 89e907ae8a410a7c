/* SPDX-License-Identifier: MIT */
/* limn devices: the OpenCL devices and how to pick one. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

int cli_devices(int argc, char **argv)
{
    static const struct option longopts[] = {CLI_FLAG("help"), CLI_OPTIONS_END};
    int orc = cli_options("devices", longopts, "h", &argc, &argv);
    if (orc)
        return orc;
    if (argc > 1 && (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0)) {
        puts("usage: limn devices\n\nLists OpenCL devices as P.D (platform.device); pick one "
             "with --device opencl:P.D,\n--device opencl:NAME, or LIMN_PLATFORM / LIMN_DEVICE / "
             "LIMN_DEVICE_TYPE.\nEach line ends with whether limn can use the device "
             "('limn: usable', or 'limn: NO,'\nand why: it needs double precision, OpenCL 1.2 "
             "and work-groups of 8); without\na choice limn takes the first usable device.\n"
             "The last line gives the OpenCL runtime's thread count and its source: the cores\n"
             "inside the CPU binding (hwloc), unless POCL_MAX_PTHREAD_COUNT or\n"
             "POCL_CPU_MAX_CU_COUNT is set.");
        return 0;
    }
    if (argc > 1)
        return cli_usage_error("devices", "unexpected argument '%s'", argv[1]);
    limn_context *ctx = cli_context("devices");
    if (!ctx)
        return EXIT_FAILURE_RUN;
    size_t size = 1 << 16;
    char *buf = malloc(size);
    limn_status st = buf ? limn_list_devices(ctx, buf, size)
                         : cli_error(LIMN_ERR_MEMORY, "out of memory");
    int rc = 0;
    if (st) {
        rc = cli_fail("devices", ctx, st);
    } else {
        cli_print_warnings("devices", ctx);
        fputs(buf, stdout);
        puts("reference  plain C backend (--device reference)");
        int threads;
        const char *source;
        limn_context_threads(ctx, &threads, &source);
        printf("threads: %d (%s)\n", threads, source);
    }
    free(buf);
    limn_context_destroy(ctx);
    return rc;
}
