/* SPDX-License-Identifier: MIT */
/*
 * Vertex partition for the MPI ranks: METIS k-way on the graph whose edges
 * are the mesh's edges (the stencil of a row reaches one ring of faces, so
 * cutting few edges means few ghost values). Isolated vertices are vertices
 * without edges and several components are just a disconnected graph: METIS
 * takes both. One part, or no more vertices than parts, needs no METIS.
 */
#include "mpi/mpi_part.h"
#include "base/large_alloc.h"

#include "base/context.h"
#include "mesh/mesh.h"

#include <limits.h>
#include <metis.h>
#include <stdlib.h>
#include <string.h>

static int cmp_idx(const void *a, const void *b)
{
    idx_t x = *(const idx_t *)a, y = *(const idx_t *)b;
    return x < y ? -1 : x > y;
}

/* Symmetric adjacency without repeats or self loops, METIS's CSR. */
static limn_status edge_graph(limn_context *ctx, const limn_mesh *mesh, idx_t **xadj_out,
                              idx_t **adj_out)
{
    size_t n = mesh->vertex_count, corners = mesh->face_offsets[mesh->face_count];
    if (2 * corners > (size_t)INT32_MAX)
        return ctx_fail(ctx, LIMN_ERR_MEMORY,
                         "the mesh has %zu face corners: too many for METIS's 32-bit indices",
                         corners);
    idx_t *xadj = calloc(n + 1, sizeof *xadj), *adj = large_malloc((2 * corners + 1) * sizeof *adj);
    idx_t *fill = large_malloc((n + 1) * sizeof *fill);
    if (!xadj || !adj || !fill) {
        free(xadj);
        free(adj);
        free(fill);
        return ctx_fail(ctx, LIMN_ERR_MEMORY, "out of memory for the graph of %zu vertices", n);
    }
    /* each face edge in both directions (an interior edge twice: merged below) */
    for (size_t f = 0; f < mesh->face_count; f++)
        for (uint32_t c = mesh->face_offsets[f]; c < mesh->face_offsets[f + 1]; c++)
            xadj[mesh->face_indices[c] + 1] += 2;
    for (size_t v = 0; v < n; v++)
        xadj[v + 1] += xadj[v];
    memcpy(fill, xadj, (n + 1) * sizeof *fill);
    for (size_t f = 0; f < mesh->face_count; f++) {
        uint32_t b = mesh->face_offsets[f], e = mesh->face_offsets[f + 1];
        for (uint32_t c = b; c < e; c++) {
            uint32_t v = mesh->face_indices[c];
            adj[fill[v]++] = (idx_t)mesh->face_indices[c + 1 < e ? c + 1 : b];
            adj[fill[v]++] = (idx_t)mesh->face_indices[c > b ? c - 1 : e - 1];
        }
    }
    /* sort and merge each list in place, compacting as we go */
    idx_t out = 0;
    for (size_t v = 0; v < n; v++) {
        idx_t b = xadj[v], e = xadj[v + 1];
        qsort(adj + b, (size_t)(e - b), sizeof *adj, cmp_idx);
        xadj[v] = out;
        for (idx_t k = b; k < e; k++)
            if (adj[k] != (idx_t)v && (k == b || adj[k] != adj[k - 1]))
                adj[out++] = adj[k];
    }
    xadj[n] = out;
    free(fill);
    *xadj_out = xadj;
    *adj_out = adj;
    return LIMN_OK;
}

limn_status mpi_partition(limn_context *ctx, const limn_mesh *mesh, int parts,
                          uint32_t *part_of, size_t *edge_cut)
{
    size_t n = mesh->vertex_count;
    *edge_cut = 0;
    if (parts <= 1 || n == 0) {
        memset(part_of, 0, n * sizeof *part_of);
        return LIMN_OK;
    }
    idx_t *xadj = NULL, *adj = NULL;
    limn_status st = edge_graph(ctx, mesh, &xadj, &adj);
    if (st)
        return st;
    if (n <= (size_t)parts || xadj[n] == 0) {
        /* tiny meshes: a vertex per rank (the last ranks get none); no edges at
           all: contiguous blocks */
        for (size_t v = 0; v < n; v++)
            part_of[v] = (uint32_t)(n <= (size_t)parts ? v : v * (size_t)parts / n);
    } else {
        idx_t nv = (idx_t)n, ncon = 1, np = parts, objval = 0;
        idx_t *part = large_malloc(n * sizeof *part);
        idx_t options[METIS_NOPTIONS];
        METIS_SetDefaultOptions(options);
        options[METIS_OPTION_SEED] = 4321; /* the same partition on every run */
        options[METIS_OPTION_NUMBERING] = 0;
        int rc = part ? METIS_PartGraphKway(&nv, &ncon, xadj, adj, NULL, NULL, NULL, &np, NULL,
                                            NULL, options, &objval, part)
                      : METIS_ERROR_MEMORY;
        if (rc == METIS_OK) {
            for (size_t v = 0; v < n; v++)
                part_of[v] = (uint32_t)part[v];
        } else {
            st = ctx_fail(ctx, rc == METIS_ERROR_MEMORY ? LIMN_ERR_MEMORY : LIMN_ERR_ARGUMENT,
                           "METIS could not partition the %zu vertices into %d parts (%s)", n,
                           parts,
                           rc == METIS_ERROR_MEMORY  ? "out of memory"
                           : rc == METIS_ERROR_INPUT ? "input error"
                                                     : "error");
        }
        free(part);
    }
    for (size_t v = 0; !st && v < n; v++)
        for (idx_t k = xadj[v]; k < xadj[v + 1]; k++)
            *edge_cut += (size_t)adj[k] > v && part_of[adj[k]] != part_of[v];
    free(xadj);
    free(adj);
    return st;
}

limn_status mpi_edge_cut(limn_context *ctx, const limn_mesh *mesh, int parts,
                         const uint32_t *part_of, size_t *edge_cut)
{
    size_t n = mesh->vertex_count;
    *edge_cut = 0;
    for (size_t v = 0; v < n; v++)
        if (part_of[v] >= (uint32_t)(parts > 0 ? parts : 1))
            return ctx_fail(ctx, LIMN_ERR_ARGUMENT,
                             "vertex %zu is given to part %u but there are %d parts", v,
                             part_of[v], parts);
    if (n == 0)
        return LIMN_OK;
    idx_t *xadj = NULL, *adj = NULL;
    limn_status st = edge_graph(ctx, mesh, &xadj, &adj);
    for (size_t v = 0; !st && v < n; v++)
        for (idx_t k = xadj[v]; k < xadj[v + 1]; k++)
            *edge_cut += (size_t)adj[k] > v && part_of[adj[k]] != part_of[v];
    free(xadj);
    free(adj);
    return st;
}
