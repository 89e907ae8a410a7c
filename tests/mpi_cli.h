/* SPDX-License-Identifier: MIT */
/* What the tests of `mpirun -np N limn ...` share (test_mpi_cli*.c): the
   launcher, the generated inputs, what the output and the report say. They
   run in the group's scratch (shell.h: test_dir, test_text). */
#ifndef LIMN_TEST_MPI_CLI_H
#define LIMN_TEST_MPI_CLI_H

#include <stddef.h>

/* Runs `limn ARGS` ($LIMN_BIN; ranks > 0: under $LIMN_MPIEXEC with that
   many ranks, killed after 300 s so that a hang fails instead of
   blocking), its output in test_text; the exit status. */
int mpi_cli_run(int ranks, const char *args);
/* How many times needle occurs in hay (overlapping too). */
size_t mpi_cli_count(const char *hay, const char *needle);
/* The report at path says the run was on slices (no rank held the mesh). */
int mpi_cli_report_sliced(const char *path);
/* test_dir/tri.obj and test_dir/quad.obj: several components (a grid, then
   an icosahedron or a cube), boundaries and an isolated vertex. */
void mpi_cli_write_inputs(void);

#endif
