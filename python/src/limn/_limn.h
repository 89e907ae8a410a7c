/* SPDX-License-Identifier: MIT */
/*
 * limn's Python extension (_limn): a thin layer over include/limn.h only.
 * Context wraps a limn_context (one thread at a time: `busy` refuses a
 * second), Mesh wraps a limn_mesh. Every limn call runs with the GIL
 * released (CALL below); progress callbacks take it back (PyGILState) and an
 * exception raised in one is kept and raised when the call returns.
 */
#ifndef LIMN_PY_H
#define LIMN_PY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <limn.h>

typedef struct {
    PyObject_HEAD
    limn_context *ctx;
    PyObject *progress;       /* callable or NULL */
    PyObject *exc_type, *exc_value, *exc_tb; /* raised by a callback */
    PyObject *warnings;       /* list of str: the warnings of the calls so far */
    long calls_without_gil;   /* callbacks entered by a thread not holding the GIL */
    int busy;                 /* a call is running on this context */
} LimnContext;

typedef struct {
    PyObject_HEAD
    limn_mesh *mesh;
} LimnMesh;

extern PyTypeObject LimnContext_Type;
extern PyTypeObject LimnMesh_Type;

/* Runs one limn call with the GIL released, then collects its warnings. */
#define CALL(c, st, expr)                                                                  \
    do {                                                                                   \
        Py_BEGIN_ALLOW_THREADS                                                             \
        (st) = (expr);                                                                     \
        Py_END_ALLOW_THREADS                                                               \
        limn_py_collect(c);                                                                \
    } while (0)

/* -1 with the Python exception set when st failed or a callback raised. */
int limn_py_check(LimnContext *c, limn_status st);
/* Raises limn.Error(message, status). */
void limn_py_raise(limn_status st, const char *message);
void limn_py_collect(LimnContext *c);
/* Marks c busy (RuntimeError when it already is); limn_py_leave clears it. */
int limn_py_enter(LimnContext *c);
void limn_py_leave(LimnContext *c);
PyObject *limn_py_str(const char *s);

/* PyArg "O&" converter: a Mesh object -> its limn_mesh * (TypeError otherwise). */
int limn_py_mesh_arg(PyObject *o, void *out);
/* A new Mesh object owning m (NULL and an exception when out of memory). */
PyObject *limn_py_mesh_new(limn_mesh *m);

/* dict helpers: 0, or -1 with an exception */
int limn_py_set(PyObject *d, const char *key, PyObject *value);
#define SET_NUM(d, k, x) limn_py_set(d, k, PyFloat_FromDouble(x))
#define SET_INT(d, k, x) limn_py_set(d, k, PyLong_FromLongLong((long long)(x)))
#define SET_STR(d, k, x) limn_py_set(d, k, limn_py_str(x))
#define SET_BOOL(d, k, x) limn_py_set(d, k, PyBool_FromLong(x))

/* Buffers: a C-contiguous buffer of `count` items of `itemsize` bytes. */
int limn_py_buffer(PyObject *obj, Py_buffer *view, Py_ssize_t itemsize, Py_ssize_t count,
                   int writable, const char *what);

/* Methods of Context: the mesh calls (_limn_mesh.c), the operations (_limn_ops.c). */
extern PyMethodDef limn_py_mesh_methods[];
extern PyMethodDef limn_py_ops_methods[];

#endif
