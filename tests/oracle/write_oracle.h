/* SPDX-License-Identifier: MIT */
/* Test-only: the mesh writers as they were before the block writers (one
 * fprintf / byte loop per number, through the public accessors): the bytes
 * limn_mesh_write must still give. single: PLY positions as float32. */
#ifndef LIMN_TEST_WRITE_ORACLE_H
#define LIMN_TEST_WRITE_ORACLE_H

#include "limn.h"

#include <stdio.h>

/* format: OBJ, OFF, PLY, PLY_ASCII or PLY_BINARY_BE. Returns 0 on success. */
int write_oracle(const limn_mesh *m, limn_format format, int single, FILE *f);

#endif
