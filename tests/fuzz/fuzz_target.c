/* SPDX-License-Identifier: MIT */
/* A libFuzzer entry point; FUZZ_TARGET names the reader (fuzz_common.h). */
#include "fuzz_common.h"

#ifndef FUZZ_TARGET
#error "compile with -DFUZZ_TARGET=\"obj\" (or off, stl, ply, ply_le, ply_be)"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    limn_fuzz_run(FUZZ_TARGET, data, size);
    return 0;
}
