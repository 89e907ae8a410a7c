/* SPDX-License-Identifier: MIT */
/* What the two halves of `limn` under mpirun share (LIMN_MPI builds only):
   cli_mpi.c (the launch, the gathered calls, the report's figures) keeps
   every rank's figures; cli_mpi_sliced.c (the jobs on slices of a file)
   hands them over. */
#ifndef LIMN_CLI_MPI_H
#define LIMN_CLI_MPI_H

#include "cli.h"

#include <limn_mpi.h>

/* Collective: every rank's statistics of res to the root, for cli_mpi_json
   (the report's "mpi" object) and cli_mpi_print. */
void cli_mpi_collect(const limn_mpi_result *res);
/* The figures collected are of a run on slices (no rank held the mesh). */
void cli_mpi_mark_sliced(void);
/* Collective: every rank's seconds reading and repairing its slice to the
   root (the report's seconds_load per rank). */
void cli_mpi_gather_load(double seconds);

#endif
