/* SPDX-License-Identifier: MIT */
/*
 * The fuzz harness shared by the libFuzzer targets (fuzz_target.c, built with
 * -DLIMN_FUZZ=ON and clang) and by the replay test (replay.c, part of the
 * normal suite), so that every committed corpus file and every crash found
 * runs through exactly the same code in CTest.
 *
 * One input is written to an in-memory file (memfd, a regular file for
 * fstat, so the size checks are those of a real file), read with
 * limn_mesh_read in the target's format, then repaired and classified
 * (limn_mesh_repair, limn_mesh_info_compute). Beyond the sanitizers, it
 * aborts when a call breaks its contract: a success with an invalid mesh
 * (index out of range, face of < 3 corners, non-finite coordinate), a
 * failure without a message naming the file, a repair that leaves a face
 * using a vertex twice, a topology that fails on a repaired mesh, or a
 * repaired mesh that does not come back bit for bit from binary PLY, or a
 * slice reader (mesh_slice.h, 3 parts) that accepts a file limn_mesh_read
 * refuses or reads another mesh.
 */
#ifndef LIMN_FUZZ_COMMON_H
#define LIMN_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

/* Target names: obj, off, stl, ply (whole files), ply_le and ply_be (the
   input follows a fixed "ply\nformat binary_... 1.0\n" prefix). Returns 0;
   -1 for an unknown target name. */
int limn_fuzz_run(const char *target, const uint8_t *data, size_t size);

#endif
