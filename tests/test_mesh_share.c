/* SPDX-License-Identifier: MIT */
/*
 * Copies share their faces (host/mesh/mesh.c): limn_mesh_copy and the
 * results of the operations hold the original's face arrays, counted, and
 * the last holder frees them. What must hold: a copy's faces are the same
 * memory; a repair that changes a copy's faces (repeated corners, duplicate
 * faces removed) changes that copy alone; the holders outlive each other in
 * any order (AddressSanitizer's stage runs this test too); copies taken on
 * several threads at once from one const mesh count right.
 */
#include "support.h"
#include "mesh/mesh.h"

#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Two triangles over a square, the first repeated as a rotated copy (a
   duplicate face), and a quad with a repeated corner (0 1 1 3). */
static limn_mesh *square(limn_context *ctx)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const uint32_t off[] = {0, 3, 6, 9, 13};
    static const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 1, 2, 0, 0, 1, 1, 3};
    limn_mesh *m = NULL;
    assert_int_equal(limn_mesh_create(ctx, 4, pos, 4, off, idx, &m), LIMN_OK);
    return m;
}

static void copies_share_and_repair_unshares(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *m = square(ctx), *a = NULL, *b = NULL;
    assert_int_equal(limn_mesh_copy(ctx, m, &a), LIMN_OK);
    assert_int_equal(limn_mesh_copy(ctx, a, &b), LIMN_OK);
    const uint32_t *faces = limn_mesh_face_indices(m);
    assert_ptr_equal(limn_mesh_face_indices(a), faces);
    assert_ptr_equal(limn_mesh_face_indices(b), faces);
    assert_ptr_equal(limn_mesh_face_offsets(b), limn_mesh_face_offsets(m));
    assert_ptr_not_equal(limn_mesh_positions(b), limn_mesh_positions(m));

    /* b loses its repeated corner and its duplicate face; m and a keep theirs */
    limn_repair_options o;
    limn_repair_options_default(&o);
    o.duplicate_faces = 1;
    limn_repair_report r = {.size = sizeof r};
    assert_int_equal(limn_mesh_repair(ctx, b, &o, &r), LIMN_OK);
    assert_int_equal(r.duplicates_removed, 1);
    assert_int_equal(r.repeats_removed, 1);
    assert_int_equal(limn_mesh_face_count(b), 3);
    assert_ptr_not_equal(limn_mesh_face_indices(b), faces);
    static const uint32_t before[] = {0, 1, 2, 0, 2, 3, 1, 2, 0, 0, 1, 1, 3};
    for (limn_mesh *held = m; held; held = held == m ? a : NULL) {
        assert_int_equal(limn_mesh_face_count(held), 4);
        assert_int_equal(limn_mesh_index_count(held), 13);
        assert_memory_equal(limn_mesh_face_indices(held), before, sizeof before);
    }
    /* the original first, then its copy: the copy's faces stay readable */
    limn_mesh_destroy(m);
    assert_memory_equal(limn_mesh_face_indices(a), before, sizeof before);
    uint32_t back_offsets[5], back[13];
    assert_int_equal(limn_mesh_copy_faces(ctx, a, back_offsets, 5, back, 13), LIMN_OK);
    assert_memory_equal(back, before, sizeof before);
    assert_int_equal(back_offsets[4], 13);
    limn_mesh_destroy(b);
    limn_mesh_destroy(a);
}

/* The repair of the only holder left changes the faces in place of nothing
   else: the shared count is dropped with the other holders. */
static void last_holder_repairs(void **state)
{
    limn_context *ctx = *state;
    limn_mesh *m = square(ctx), *a = NULL;
    assert_int_equal(limn_mesh_copy(ctx, m, &a), LIMN_OK);
    limn_mesh_destroy(m);
    limn_repair_report r = {.size = sizeof r};
    assert_int_equal(limn_mesh_repair(ctx, a, NULL, &r), LIMN_OK);
    assert_int_equal(r.repeats_removed, 1);
    assert_int_equal(r.duplicate_faces, 1); /* found and kept: not asked to remove */
    assert_int_equal(limn_mesh_face_count(a), 4);
    /* a copy of the repaired mesh shares its new faces, and a repair of that
       copy (removing the duplicate) leaves the original's faces alone */
    limn_mesh *b = NULL;
    assert_int_equal(limn_mesh_copy(ctx, a, &b), LIMN_OK);
    assert_ptr_equal(limn_mesh_face_indices(b), limn_mesh_face_indices(a));
    limn_repair_options o;
    limn_repair_options_default(&o);
    o.duplicate_faces = 1;
    assert_int_equal(limn_mesh_repair(ctx, b, &o, &r), LIMN_OK);
    assert_int_equal(limn_mesh_face_count(b), 3);
    assert_int_equal(limn_mesh_face_count(a), 4);
    limn_mesh_destroy(a);
    limn_mesh_destroy(b);
}

#define THREADS 4
#define COPIES 200

typedef struct copier {
    const limn_mesh *from;
    limn_mesh *copies[COPIES];
    int failed;
} copier;

static void *copy_many(void *arg)
{
    copier *c = arg;
    limn_context *ctx = limn_context_create();
    if (!ctx) {
        c->failed = 1;
        return NULL;
    }
    for (int i = 0; i < COPIES; i++)
        c->failed |= limn_mesh_copy(ctx, c->from, &c->copies[i]) != LIMN_OK;
    limn_context_destroy(ctx);
    return NULL;
}

static void copies_on_threads(void **state)
{
    (void)state;
    limn_context *ctx = limn_context_create();
    assert_non_null(ctx);
    limn_mesh *m = square(ctx);
    limn_context_destroy(ctx);
    copier c[THREADS];
    pthread_t t[THREADS];
    for (int k = 0; k < THREADS; k++) {
        memset(&c[k], 0, sizeof c[k]);
        c[k].from = m;
        assert_int_equal(pthread_create(&t[k], NULL, copy_many, &c[k]), 0);
    }
    for (int k = 0; k < THREADS; k++)
        assert_int_equal(pthread_join(t[k], NULL), 0);
    const uint32_t *faces = limn_mesh_face_indices(m);
    limn_mesh_destroy(m); /* every copy still holds the faces */
    for (int k = 0; k < THREADS; k++) {
        assert_false(c[k].failed);
        for (int i = 0; i < COPIES; i++) {
            assert_ptr_equal(limn_mesh_face_indices(c[k].copies[i]), faces);
            assert_int_equal(limn_mesh_face_indices(c[k].copies[i])[12], 3);
            limn_mesh_destroy(c[k].copies[i]);
        }
    }
}

TEST_MAIN(NULL, NULL, CONTEXT_TEST(copies_share_and_repair_unshares),
          CONTEXT_TEST(last_holder_repairs), cmocka_unit_test(copies_on_threads))
