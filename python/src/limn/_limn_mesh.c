/* SPDX-License-Identifier: MIT */
/* The Mesh type and the context's mesh calls: create, copy out, read, write,
   repair, measure, compare. */
#include "_limn.h"

static void mesh_dealloc(LimnMesh *self)
{
    limn_mesh *mesh = self->mesh;
    Py_BEGIN_ALLOW_THREADS
    limn_mesh_destroy(mesh);
    Py_END_ALLOW_THREADS
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* counts() -> (vertices, faces, indices, has colours) */
static PyObject *mesh_counts(LimnMesh *self, PyObject *unused)
{
    (void)unused;
    return Py_BuildValue("(nnnO)", (Py_ssize_t)limn_mesh_vertex_count(self->mesh),
                         (Py_ssize_t)limn_mesh_face_count(self->mesh),
                         (Py_ssize_t)limn_mesh_index_count(self->mesh),
                         limn_mesh_colors(self->mesh) ? Py_True : Py_False);
}

static PyMethodDef mesh_methods[] = {
    {"counts", (PyCFunction)mesh_counts, METH_NOARGS, "(vertices, faces, indices, has_colors)"},
    {NULL, NULL, 0, NULL}};

PyTypeObject LimnMesh_Type = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "limn._limn.Mesh",
    .tp_basicsize = sizeof(LimnMesh),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A limn_mesh (made by Context.mesh_create, read or an operation).",
    .tp_dealloc = (destructor)mesh_dealloc,
    .tp_methods = mesh_methods,
};

PyObject *limn_py_mesh_new(limn_mesh *m)
{
    LimnMesh *o = PyObject_New(LimnMesh, &LimnMesh_Type);
    if (!o) {
        limn_mesh_destroy(m);
        return NULL;
    }
    o->mesh = m;
    return (PyObject *)o;
}

/* Either a new Mesh for m, or NULL with the exception of st (m destroyed). */
static PyObject *mesh_result(LimnContext *c, limn_status st, limn_mesh *m)
{
    limn_py_leave(c);
    if (limn_py_check(c, st) < 0) {
        limn_mesh_destroy(m);
        return NULL;
    }
    return limn_py_mesh_new(m);
}

/* mesh_create(positions float64[n*3], n, offsets uint32[m+1], m, indices uint32[k], k) */
static PyObject *ctx_mesh_create(LimnContext *c, PyObject *args)
{
    PyObject *po, *oo, *io;
    Py_ssize_t n, m, k;
    if (!PyArg_ParseTuple(args, "OnOnOn", &po, &n, &oo, &m, &io, &k))
        return NULL;
    Py_buffer p = {0}, o = {0}, i = {0};
    int ok = limn_py_buffer(po, &p, 8, 3 * n, 0, "positions") == 0 &&
             limn_py_buffer(oo, &o, 4, m + 1, 0, "face offsets") == 0 &&
             limn_py_buffer(io, &i, 4, k, 0, "face indices") == 0 && limn_py_enter(c) == 0;
    if (!ok) {
        Py_buffer *views[] = {&p, &o, &i};
        for (int j = 0; j < 3; j++)
            if (views[j]->obj)
                PyBuffer_Release(views[j]);
        return NULL;
    }
    limn_mesh *mesh = NULL;
    limn_status st;
    CALL(c, st, limn_mesh_create(c->ctx, (size_t)n, p.buf, (size_t)m, o.buf, i.buf, &mesh));
    PyBuffer_Release(&i);
    PyBuffer_Release(&o);
    PyBuffer_Release(&p);
    return mesh_result(c, st, mesh);
}

int limn_py_mesh_arg(PyObject *o, void *out)
{
    if (!PyObject_TypeCheck(o, &LimnMesh_Type)) {
        PyErr_SetString(PyExc_TypeError, "a limn._limn.Mesh is expected");
        return 0;
    }
    *(limn_mesh **)out = ((LimnMesh *)o)->mesh;
    return 1;
}

/* copy_out(mesh, positions float64[n*3], offsets uint32[m+1], indices uint32[k],
   colours uint8[n*3] or None) */
static PyObject *ctx_copy_out(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    PyObject *po, *oo, *io, *co;
    if (!PyArg_ParseTuple(args, "O&OOOO", limn_py_mesh_arg, &mesh, &po, &oo, &io, &co))
        return NULL;
    size_t n = limn_mesh_vertex_count(mesh), m = limn_mesh_face_count(mesh);
    size_t k = limn_mesh_index_count(mesh);
    Py_buffer b[4] = {{0}};
    int ok = limn_py_buffer(po, &b[0], 8, 3 * (Py_ssize_t)n, 1, "positions") == 0 &&
             limn_py_buffer(oo, &b[1], 4, (Py_ssize_t)m + 1, 1, "face offsets") == 0 &&
             limn_py_buffer(io, &b[2], 4, (Py_ssize_t)k, 1, "face indices") == 0 &&
             (co == Py_None || limn_py_buffer(co, &b[3], 1, 3 * (Py_ssize_t)n, 1, "colours") == 0) &&
             limn_py_enter(c) == 0;
    limn_status st = LIMN_OK;
    if (ok) {
        CALL(c, st, limn_mesh_copy_positions(c->ctx, mesh, b[0].buf, n));
        if (!st)
            CALL(c, st, limn_mesh_copy_faces(c->ctx, mesh, b[1].buf, m + 1, b[2].buf, k));
        if (!st && co != Py_None)
            CALL(c, st, limn_mesh_copy_colors(c->ctx, mesh, b[3].buf, n));
        limn_py_leave(c);
    }
    for (int j = 0; j < 4; j++)
        if (b[j].obj)
            PyBuffer_Release(&b[j]);
    if (!ok)
        return NULL;
    return limn_py_check(c, st) < 0 ? NULL : Py_NewRef(Py_None);
}

/* set_colors(mesh, colours uint8[n*3] or None) */
static PyObject *ctx_set_colors(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    PyObject *co;
    if (!PyArg_ParseTuple(args, "O&O", limn_py_mesh_arg, &mesh, &co))
        return NULL;
    Py_buffer b = {0};
    Py_ssize_t n = (Py_ssize_t)limn_mesh_vertex_count(mesh);
    if (co != Py_None && limn_py_buffer(co, &b, 1, 3 * n, 0, "colours") < 0)
        return NULL;
    if (limn_py_enter(c) < 0) {
        if (b.obj)
            PyBuffer_Release(&b);
        return NULL;
    }
    limn_status st;
    CALL(c, st, limn_mesh_set_colors(c->ctx, mesh, b.obj ? b.buf : NULL));
    limn_py_leave(c);
    if (b.obj)
        PyBuffer_Release(&b);
    return limn_py_check(c, st) < 0 ? NULL : Py_NewRef(Py_None);
}

/* read(path bytes, format int, max_memory) -> Mesh */
static PyObject *ctx_read(LimnContext *c, PyObject *args)
{
    const char *path;
    int format;
    unsigned long long max_memory;
    if (!PyArg_ParseTuple(args, "yiK", &path, &format, &max_memory) || limn_py_enter(c) < 0)
        return NULL;
    limn_context_set_max_memory(c->ctx, (size_t)max_memory);
    limn_mesh *mesh = NULL;
    limn_status st;
    CALL(c, st, limn_mesh_read(c->ctx, path, (limn_format)format, &mesh));
    return mesh_result(c, st, mesh);
}

/* write(mesh, path bytes, format int, float32 bool) -> {max_error, mean_error, bbox_diagonal} */
static PyObject *ctx_write(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    const char *path;
    int format, single;
    if (!PyArg_ParseTuple(args, "O&yip", limn_py_mesh_arg, &mesh, &path, &format, &single) ||
        limn_py_enter(c) < 0)
        return NULL;
    limn_write_options o;
    limn_write_options_default(&o);
    o.precision = single ? LIMN_OUTPUT_FLOAT : LIMN_OUTPUT_DOUBLE;
    limn_write_report r = {.size = sizeof r};
    limn_status st;
    CALL(c, st, limn_mesh_write_with(c->ctx, mesh, path, (limn_format)format, &o, &r));
    limn_py_leave(c);
    if (limn_py_check(c, st) < 0)
        return NULL;
    return Py_BuildValue("{s:d,s:d,s:d}", "max_error", r.max_error, "mean_error", r.mean_error,
                         "bbox_diagonal", r.bbox_diagonal);
}

static PyObject *repair_dict(const limn_repair_report *r)
{
    return Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n}", "faces_before",
                         (Py_ssize_t)r->faces_before, "faces_after", (Py_ssize_t)r->faces_after,
                         "repeat_faces", (Py_ssize_t)r->repeat_faces, "faces_split",
                         (Py_ssize_t)r->faces_split, "degenerate_removed",
                         (Py_ssize_t)r->degenerate_removed, "duplicate_faces",
                         (Py_ssize_t)r->duplicate_faces, "duplicates_removed",
                         (Py_ssize_t)r->duplicates_removed, "nonmanifold_edges",
                         (Py_ssize_t)r->nonmanifold_edges, "components",
                         (Py_ssize_t)r->components, "boundary_loops",
                         (Py_ssize_t)r->boundary_loops);
}

/* repair(mesh, repeated_vertices bool, duplicate_faces bool) -> dict */
static PyObject *ctx_repair(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    int repeated, duplicates;
    if (!PyArg_ParseTuple(args, "O&pp", limn_py_mesh_arg, &mesh, &repeated, &duplicates) ||
        limn_py_enter(c) < 0)
        return NULL;
    limn_repair_options o;
    limn_repair_options_default(&o);
    o.repeated_vertices = repeated;
    o.duplicate_faces = duplicates;
    limn_repair_report r = {.size = sizeof r};
    limn_status st;
    CALL(c, st, limn_mesh_repair(c->ctx, mesh, &o, &r));
    limn_py_leave(c);
    return limn_py_check(c, st) < 0 ? NULL : repair_dict(&r);
}

/* measure(mesh) -> {closed, volume, area} */
static PyObject *ctx_measure(LimnContext *c, PyObject *args)
{
    limn_mesh *mesh;
    if (!PyArg_ParseTuple(args, "O&", limn_py_mesh_arg, &mesh) || limn_py_enter(c) < 0)
        return NULL;
    limn_mesh_measures r = {.size = sizeof r};
    limn_status st;
    CALL(c, st, limn_mesh_measure(c->ctx, mesh, &r));
    limn_py_leave(c);
    if (limn_py_check(c, st) < 0)
        return NULL;
    return Py_BuildValue("{s:O,s:d,s:d}", "closed", r.closed ? Py_True : Py_False, "volume",
                         r.volume, "area", r.area);
}

/* compare(a, b) -> {mean_distance, max_distance, ...} */
static PyObject *ctx_compare(LimnContext *c, PyObject *args)
{
    limn_mesh *a, *b;
    if (!PyArg_ParseTuple(args, "O&O&", limn_py_mesh_arg, &a, limn_py_mesh_arg, &b) || limn_py_enter(c) < 0)
        return NULL;
    limn_mesh_comparison r = {.size = sizeof r};
    limn_status st;
    CALL(c, st, limn_mesh_compare(c->ctx, a, b, &r));
    limn_py_leave(c);
    if (limn_py_check(c, st) < 0)
        return NULL;
    return Py_BuildValue("{s:d,s:d,s:d,s:n}", "mean_distance", r.mean_distance, "max_distance",
                         r.max_distance, "mean_normal_angle", r.mean_normal_angle,
                         "flipped_faces", (Py_ssize_t)r.flipped_faces);
}

PyMethodDef limn_py_mesh_methods[] = {
    {"mesh_create", (PyCFunction)ctx_mesh_create, METH_VARARGS, "limn_mesh_create"},
    {"copy_out", (PyCFunction)ctx_copy_out, METH_VARARGS, "limn_mesh_copy_*"},
    {"set_colors", (PyCFunction)ctx_set_colors, METH_VARARGS, "limn_mesh_set_colors"},
    {"read", (PyCFunction)ctx_read, METH_VARARGS, "limn_mesh_read"},
    {"write", (PyCFunction)ctx_write, METH_VARARGS, "limn_mesh_write_with"},
    {"repair", (PyCFunction)ctx_repair, METH_VARARGS, "limn_mesh_repair"},
    {"measure", (PyCFunction)ctx_measure, METH_VARARGS, "limn_mesh_measure"},
    {"compare", (PyCFunction)ctx_compare, METH_VARARGS, "limn_mesh_compare"},
    {NULL, NULL, 0, NULL}};
