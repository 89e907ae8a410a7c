/* SPDX-License-Identifier: MIT */
/* The file of a parallel write (mpi_write_io.h): rank 0 makes the temporary
   file beside the target as atomic_file does for one process, every rank
   writes its bytes into it at its offset (MPI_File_write_at_all), rank 0
   renames it once every rank has succeeded (or hands it to an output set).
   A target that cannot be replaced by a rename (standard output, a FIFO, a
   character device) gets the bytes through rank 0, rank by rank, into
   atomic_file's buffer, written at the commit as the single process does. */
#include "mpi/mpi_write_io.h"
#include "base/large_alloc.h"
#include "mesh/io/output_set.h"

#include "base/context.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* MPI counts are int: bytes per call */
#define WRITE_CHUNK ((uint64_t)1 << 30)
/* a straight-through target's bytes travel to rank 0 in messages of this size */
#define STREAM_CHUNK (1 << 16)

static limn_status mpi_failed(mpi_writer *w, const char *what, int rc)
{
    char text[MPI_MAX_ERROR_STRING];
    int n = 0;
    if (MPI_Error_string(rc, text, &n) != MPI_SUCCESS)
        snprintf(text, sizeof text, "MPI error %d", rc);
    return ctx_fail(w->ctx, LIMN_ERR_IO, "cannot write %s: %s: %s (rank %d)", w->path, what, text,
                    w->rank);
}

/* Rank 0: atomic_file_open; a regular target's temporary file is closed
   empty, to be opened by every rank through MPI-IO. */
static limn_status open_target(mpi_writer *w)
{
    limn_status st = LIMN_OK;
    if (w->rank == 0) {
        st = atomic_file_open(w->ctx, w->path, &w->af);
        if (!st) {
            w->streamed = w->af.out.kind != OUTPUT_FILE;
            if (!w->streamed)
                st = atomic_file_finish(w->ctx, &w->af); /* removes it on failure */
        }
    }
    st = mpi_writer_agree(w, st);
    if (st)
        return st;
    MPI_Bcast(&w->streamed, 1, MPI_INT, 0, w->comm);
    if (w->streamed)
        return LIMN_OK;
    int len = w->rank == 0 ? (int)strlen(w->af.tmp_path) + 1 : 0;
    MPI_Bcast(&len, 1, MPI_INT, 0, w->comm);
    char *tmp = w->rank == 0 ? w->af.tmp_path : large_malloc((size_t)len);
    int oom = !tmp;
    MPI_Allreduce(MPI_IN_PLACE, &oom, 1, MPI_INT, MPI_MAX, w->comm);
    if (oom) {
        if (w->rank != 0)
            free(tmp);
        st = ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory");
        return mpi_writer_agree(w, st);
    }
    MPI_Bcast(tmp, len, MPI_CHAR, 0, w->comm);
    /* a communicator of the file's own: the MPI-IO library's messages never
       pair with this layer's agreements, even when one rank's write gives
       up halfway (Open MPI's vulcan does) */
    MPI_Comm_dup(w->comm, &w->file_comm);
    int rc = MPI_File_open(w->file_comm, tmp, MPI_MODE_WRONLY, MPI_INFO_NULL, &w->fh);
    if (w->rank != 0)
        free(tmp);
    if (rc != MPI_SUCCESS) {
        w->fh = MPI_FILE_NULL;
        st = mpi_failed(w, "MPI_File_open of the temporary file", rc);
    }
    return mpi_writer_agree(w, st);
}

/* n bytes at off, in collective calls of at most WRITE_CHUNK; every rank
   makes the same number of calls, writing nothing once it has failed. */
static limn_status write_at_all(mpi_writer *w, uint64_t off, const unsigned char *p, uint64_t n)
{
    uint64_t calls = (n + WRITE_CHUNK - 1) / WRITE_CHUNK, most;
    MPI_Allreduce(&calls, &most, 1, MPI_UINT64_T, MPI_MAX, w->comm);
    limn_status st = LIMN_OK;
    for (uint64_t c = 0; c < most; c++) {
        uint64_t at = c * WRITE_CHUNK;
        int len = !st && at < n ? (int)(n - at < WRITE_CHUNK ? n - at : WRITE_CHUNK) : 0;
        MPI_Status status;
        int rc = MPI_File_write_at_all(w->fh, (MPI_Offset)(off + at), p + (len ? at : 0), len,
                                       MPI_BYTE, &status);
        int done = 0; /* ROMIO leaves the count of an empty write undefined */
        if (rc == MPI_SUCCESS && len)
            rc = MPI_Get_count(&status, MPI_BYTE, &done);
        if (!st && rc != MPI_SUCCESS)
            st = mpi_failed(w, "MPI_File_write_at_all", rc);
        else if (!st && done != len)
            st = ctx_fail(w->ctx, LIMN_ERR_IO,
                          "cannot write %s: MPI_File_write_at_all wrote %d of %d bytes at offset "
                          "%llu (rank %d)", w->path, done, len,
                          (unsigned long long)(off + at), w->rank);
    }
    return st;
}

/* Rank 0: the temporary file that the ranks wrote and closed has all the
   bytes (an MPI-IO library may lose a failed write without an error: Open
   MPI 4.1's vulcan does when an aggregator's pwritev fails), then fsync. */
static limn_status check_closed(mpi_writer *w, uint64_t expected)
{
    int fd = open(w->af.tmp_path, O_WRONLY | O_CLOEXEC);
    struct stat sb;
    int e = fd < 0 || fstat(fd, &sb) != 0 ? errno : 0;
    limn_status st = LIMN_OK;
    if (!e && (uint64_t)sb.st_size != expected)
        st = ctx_fail(w->ctx, LIMN_ERR_IO,
                      "cannot write %s: the ranks wrote %llu bytes of %llu (a write failed in "
                      "the MPI-IO library)", w->path, (unsigned long long)sb.st_size,
                      (unsigned long long)expected);
    if (!e && !st && fsync(fd) != 0)
        e = errno;
    if (fd >= 0 && close(fd) != 0 && !e)
        e = errno;
    if (e && !st)
        st = ctx_fail(w->ctx, LIMN_ERR_IO, "cannot write %s: %s", w->path, strerror(e));
    return st;
}

/* Every rank's vertex bytes, then every rank's face bytes, in rank order. */
static limn_status write_parallel(mpi_writer *w)
{
    uint64_t len[2] = {w->vbytes.len, w->fbytes.len}, before[2] = {0, 0}, total[2];
    MPI_Exscan(len, before, 2, MPI_UINT64_T, MPI_SUM, w->comm);
    MPI_Allreduce(len, total, 2, MPI_UINT64_T, MPI_SUM, w->comm);
    if (w->rank == 0)
        before[0] = before[1] = 0; /* MPI_Exscan leaves rank 0's undefined */
    limn_status st = write_at_all(w, before[0], w->vbytes.data, len[0]);
    limn_status sf = write_at_all(w, total[0] + before[1], w->fbytes.data, len[1]);
    /* No MPI_File_sync: MPI_File_close synchronises the file by the
       standard, and Open MPI's ompio returns from a sync that failed on one
       rank before its barrier, which then pairs with another rank's close.
       Rank 0 checks and syncs the closed file itself before the rename. */
    st = st ? st : sf;
    int rc = MPI_File_close(&w->fh);
    if (!st && rc != MPI_SUCCESS)
        st = mpi_failed(w, "MPI_File_close", rc);
    st = mpi_writer_agree(w, st);
    if (!st && w->rank == 0)
        st = check_closed(w, total[0] + total[1]);
    return mpi_writer_agree(w, st);
}

/* Rank 0 takes rank from's n bytes (n known to both) in messages of
   STREAM_CHUNK; rank from sends them. After a failure rank 0 still takes
   them (no sender is left waiting), writing nothing. */
static limn_status relay(mpi_writer *w, int from, const unsigned char *mine, uint64_t n,
                         limn_status st)
{
    static const int tag = 0x11e;
    if (w->rank != 0) {
        for (uint64_t at = 0; at < n; at += STREAM_CHUNK)
            MPI_Send(mine + at, (int)(n - at < STREAM_CHUNK ? n - at : STREAM_CHUNK), MPI_BYTE,
                     0, tag, w->comm);
        return st;
    }
    unsigned char buf[STREAM_CHUNK];
    for (uint64_t at = 0; at < n; at += STREAM_CHUNK) {
        size_t len = (size_t)(n - at < STREAM_CHUNK ? n - at : STREAM_CHUNK);
        const unsigned char *p = mine + at;
        if (from != 0) {
            MPI_Recv(buf, (int)len, MPI_BYTE, from, tag, w->comm, MPI_STATUS_IGNORE);
            p = buf;
        }
        if (!st && fwrite(p, 1, len, w->af.f) != len)
            st = ctx_fail(w->ctx, LIMN_ERR_IO, "cannot write %s: write error", w->path);
    }
    return st;
}

/* A straight-through target: every rank's bytes to rank 0's buffer, in order. */
static limn_status write_streamed(mpi_writer *w)
{
    uint64_t mine[2] = {w->vbytes.len, w->fbytes.len};
    uint64_t *all = w->rank == 0 ? large_malloc(2 * (size_t)w->size * sizeof *all) : NULL;
    int oom = w->rank == 0 && !all;
    MPI_Bcast(&oom, 1, MPI_INT, 0, w->comm);
    if (oom)
        return mpi_writer_agree(w, ctx_fail(w->ctx, LIMN_ERR_MEMORY, "out of memory"));
    MPI_Gather(mine, 2, MPI_UINT64_T, all, 2, MPI_UINT64_T, 0, w->comm);
    limn_status st = LIMN_OK;
    for (int part = 0; part < 2; part++) {
        const growbuf *g = part ? &w->fbytes : &w->vbytes;
        for (int r = 0; r < w->size; r++) {
            if (w->rank == 0)
                st = relay(w, r, g->data, all[2 * r + part], st);
            else if (r == w->rank)
                st = relay(w, r, g->data, g->len, st);
        }
    }
    free(all);
    return mpi_writer_agree(w, st);
}

limn_status mpi_writer_output(mpi_writer *w)
{
    limn_status st = open_target(w);
    if (!st)
        st = w->streamed ? write_streamed(w) : write_parallel(w);
    if (w->fh != MPI_FILE_NULL)
        MPI_File_close(&w->fh);
    if (w->file_comm != MPI_COMM_NULL)
        MPI_Comm_free(&w->file_comm);
    if (!st && w->rank == 0 && w->stage)
        output_set_adopt(w->stage, &w->af); /* to appear with the set's other outputs */
    else if (!st && w->rank == 0)
        st = atomic_file_commit(w->ctx, &w->af); /* the rename, or the bytes written through */
    st = mpi_writer_agree(w, st);
    if (w->rank == 0)
        atomic_file_abort(&w->af); /* after a failure: the temporary file removed */
    return st;
}
