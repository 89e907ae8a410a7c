/* SPDX-License-Identifier: MIT */
/* The module _limn: the Context type, errors, progress callbacks, helpers. */
#include "_limn.h"

#include <string.h>

static PyObject *error_class; /* limn.Error, registered by limn/__init__.py */

PyObject *limn_py_str(const char *s)
{
    return PyUnicode_DecodeUTF8(s ? s : "", (Py_ssize_t)strlen(s ? s : ""), "replace");
}

int limn_py_set(PyObject *d, const char *key, PyObject *value)
{
    if (!value)
        return -1;
    int rc = PyDict_SetItemString(d, key, value);
    Py_DECREF(value);
    return rc;
}

void limn_py_raise(limn_status st, const char *message)
{
    PyObject *cls = error_class ? error_class : PyExc_RuntimeError;
    PyObject *msg = limn_py_str(message && *message ? message : limn_status_name(st));
    PyObject *e = msg ? PyObject_CallFunction(cls, "Oi", msg, (int)st) : NULL;
    Py_XDECREF(msg);
    if (e) {
        PyErr_SetObject(cls, e);
        Py_DECREF(e);
    }
}

void limn_py_collect(LimnContext *c)
{
    const char *w = limn_context_warnings(c->ctx);
    if (!w || !*w || !c->warnings)
        return;
    PyObject *s = limn_py_str(w);
    if (!s || PyList_Append(c->warnings, s) < 0)
        PyErr_Clear(); /* a warning lost to memory exhaustion is not an error */
    Py_XDECREF(s);
}

int limn_py_check(LimnContext *c, limn_status st)
{
    if (c->exc_type) { /* the callback's exception wins: it cancelled the work */
        PyErr_Restore(c->exc_type, c->exc_value, c->exc_tb);
        c->exc_type = c->exc_value = c->exc_tb = NULL;
        return -1;
    }
    if (st == LIMN_OK)
        return 0;
    limn_py_raise(st, limn_context_message(c->ctx));
    return -1;
}

int limn_py_enter(LimnContext *c)
{
    if (c->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "this limn context is in use by another call (one thread at a time)");
        return -1;
    }
    c->busy = 1;
    return 0;
}

void limn_py_leave(LimnContext *c) { c->busy = 0; }

int limn_py_buffer(PyObject *obj, Py_buffer *view, Py_ssize_t itemsize, Py_ssize_t count,
                   int writable, const char *what)
{
    int flags = PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) {
        view->obj = NULL;
        return -1;
    }
    if (view->len != itemsize * count) {
        PyErr_Format(PyExc_ValueError, "%s: %zd bytes given, %zd expected", what, view->len,
                     itemsize * count);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------ progress */

static void keep_exception(LimnContext *c)
{
    if (c->exc_type) { /* one is kept already: the first wins */
        PyErr_Clear();
        return;
    }
    PyErr_Fetch(&c->exc_type, &c->exc_value, &c->exc_tb);
    PyErr_NormalizeException(&c->exc_type, &c->exc_value, &c->exc_tb);
}

/* limn_progress_fn: called by limn without the GIL (the caller released it). */
static void progress_trampoline(void *user, const char *stage, double fraction)
{
    LimnContext *c = user;
    int held = PyGILState_Check();
    PyGILState_STATE g = PyGILState_Ensure();
    if (!held)
        c->calls_without_gil++;
    if (c->progress && !c->exc_type) {
        PyObject *r = PyObject_CallFunction(c->progress, "sd", stage, fraction);
        if (!r)
            keep_exception(c);
        Py_XDECREF(r);
    }
    PyGILState_Release(g);
}

/* ------------------------------------------------------------ Context */

static int context_init(LimnContext *self, PyObject *args, PyObject *kw)
{
    (void)args;
    (void)kw;
    if (self->ctx)
        return 0;
    limn_context *ctx;
    Py_BEGIN_ALLOW_THREADS
    ctx = limn_context_create();
    Py_END_ALLOW_THREADS
    self->ctx = ctx;
    self->warnings = PyList_New(0);
    if (!self->ctx || !self->warnings) {
        PyErr_NoMemory();
        return -1;
    }
    limn_context_set_progress(self->ctx, progress_trampoline, self);
    return 0;
}

static void context_dealloc(LimnContext *self)
{
    limn_context *ctx = self->ctx;
    Py_BEGIN_ALLOW_THREADS
    limn_context_destroy(ctx); /* may close an OpenCL context: not under the GIL */
    Py_END_ALLOW_THREADS
    Py_XDECREF(self->progress);
    Py_XDECREF(self->exc_type);
    Py_XDECREF(self->exc_value);
    Py_XDECREF(self->exc_tb);
    Py_XDECREF(self->warnings);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* set_device(spec or None) */
static PyObject *context_set_device(LimnContext *self, PyObject *args)
{
    const char *spec = NULL;
    if (!PyArg_ParseTuple(args, "z", &spec) || limn_py_enter(self) < 0)
        return NULL;
    limn_status st;
    CALL(self, st, limn_context_set_device(self->ctx, spec));
    limn_py_leave(self);
    return limn_py_check(self, st) < 0 ? NULL : Py_NewRef(Py_None);
}

/* set_fallback("reference", "none" or None) */
static PyObject *context_set_fallback(LimnContext *self, PyObject *args)
{
    const char *backend = NULL;
    if (!PyArg_ParseTuple(args, "z", &backend) || limn_py_enter(self) < 0)
        return NULL;
    limn_status st;
    CALL(self, st, limn_context_set_fallback(self->ctx, backend));
    limn_py_leave(self);
    return limn_py_check(self, st) < 0 ? NULL : Py_NewRef(Py_None);
}

/* fall_back(status) -> True when the context switched to the reference backend */
static PyObject *context_fall_back(LimnContext *self, PyObject *args)
{
    int status;
    if (!PyArg_ParseTuple(args, "i", &status) || limn_py_enter(self) < 0)
        return NULL;
    limn_status st;
    CALL(self, st, limn_context_fall_back(self->ctx, (limn_status)status));
    limn_py_leave(self);
    return PyBool_FromLong(st == LIMN_OK);
}

static PyObject *context_set_progress(LimnContext *self, PyObject *fn)
{
    if (fn != Py_None && !PyCallable_Check(fn)) {
        PyErr_SetString(PyExc_ValueError, "progress must be a callable(stage, fraction) or None");
        return NULL;
    }
    Py_XSETREF(self->progress, fn == Py_None ? NULL : Py_NewRef(fn));
    return Py_NewRef(Py_None);
}

static PyObject *context_list_devices(LimnContext *self, PyObject *unused)
{
    (void)unused;
    size_t size = 1 << 16;
    char *buf = PyMem_Malloc(size);
    if (!buf)
        return PyErr_NoMemory();
    if (limn_py_enter(self) < 0) {
        PyMem_Free(buf);
        return NULL;
    }
    limn_status st;
    CALL(self, st, limn_list_devices(self->ctx, buf, size));
    limn_py_leave(self);
    PyObject *r = limn_py_check(self, st) < 0 ? NULL : limn_py_str(buf);
    PyMem_Free(buf);
    return r;
}

static PyObject *context_device_name(LimnContext *self, PyObject *unused)
{
    (void)unused;
    return limn_py_str(limn_context_device_name(self->ctx));
}

/* threads() -> (OpenCL runtime threads, source, host threads, source) */
static PyObject *context_threads(LimnContext *self, PyObject *unused)
{
    (void)unused;
    int t = 0, h = 0;
    const char *ts = "", *hs = "";
    limn_context_threads(self->ctx, &t, &ts);
    if (limn_context_host_threads(self->ctx, &h, &hs) != LIMN_OK)
        hs = "";
    return Py_BuildValue("(isis)", t, ts, h, hs);
}

/* pop_warnings() -> list of str (and clears them) */
static PyObject *context_pop_warnings(LimnContext *self, PyObject *unused)
{
    (void)unused;
    PyObject *list = self->warnings, *fresh = PyList_New(0);
    if (!fresh)
        return NULL;
    self->warnings = fresh;
    return list;
}

static PyObject *context_calls_without_gil(LimnContext *self, PyObject *unused)
{
    (void)unused;
    return PyLong_FromLong(self->calls_without_gil);
}

static PyMethodDef context_methods[] = {
    {"set_device", (PyCFunction)context_set_device, METH_VARARGS, "set_device(spec or None)"},
    {"set_fallback", (PyCFunction)context_set_fallback, METH_VARARGS,
     "set_fallback('reference' | 'none' | None)"},
    {"fall_back", (PyCFunction)context_fall_back, METH_VARARGS,
     "fall_back(status) -> bool: switched to the reference backend"},
    {"set_progress", (PyCFunction)context_set_progress, METH_O, "set_progress(callable or None)"},
    {"list_devices", (PyCFunction)context_list_devices, METH_NOARGS, "the OpenCL devices"},
    {"device_name", (PyCFunction)context_device_name, METH_NOARGS, "the last device used"},
    {"threads", (PyCFunction)context_threads, METH_NOARGS, "(threads, source, host, source)"},
    {"pop_warnings", (PyCFunction)context_pop_warnings, METH_NOARGS, "warnings so far"},
    {"calls_without_gil", (PyCFunction)context_calls_without_gil, METH_NOARGS,
     "progress callbacks entered from a thread that did not hold the GIL"},
    {NULL, NULL, 0, NULL}};

static PyMethodDef *all_methods(void)
{
    static PyMethodDef table[64];
    if (table[0].ml_name)
        return table;
    size_t n = 0;
    PyMethodDef *parts[] = {context_methods, limn_py_mesh_methods, limn_py_ops_methods};
    for (size_t p = 0; p < 3; p++)
        for (PyMethodDef *m = parts[p]; m->ml_name && n + 1 < 64; m++)
            table[n++] = *m;
    return table;
}

PyTypeObject LimnContext_Type = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "limn._limn.Context",
    .tp_basicsize = sizeof(LimnContext),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A limn_context: device choice, messages, warnings, progress.",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)context_init,
    .tp_dealloc = (destructor)context_dealloc,
};

/* ------------------------------------------------------------ module */

static PyObject *mod_register_error(PyObject *m, PyObject *cls)
{
    (void)m;
    Py_XSETREF(error_class, Py_NewRef(cls));
    return Py_NewRef(Py_None);
}

static PyObject *mod_version(PyObject *m, PyObject *unused)
{
    (void)m;
    (void)unused;
    return limn_py_str(limn_version());
}

static PyObject *mod_status_name(PyObject *m, PyObject *args)
{
    (void)m;
    int st;
    if (!PyArg_ParseTuple(args, "i", &st))
        return NULL;
    return limn_py_str(limn_status_name((limn_status)st));
}

/* format_from_name(name) -> int, or -1 when unknown */
static PyObject *mod_format_from_name(PyObject *m, PyObject *args)
{
    (void)m;
    const char *name;
    limn_format f;
    if (!PyArg_ParseTuple(args, "s", &name))
        return NULL;
    return PyLong_FromLong(limn_format_from_name(name, &f) ? (long)f : -1L);
}

static PyMethodDef module_methods[] = {
    {"register_error", mod_register_error, METH_O, "the class raised for limn's failures"},
    {"version", mod_version, METH_NOARGS, "limn_version()"},
    {"status_name", mod_status_name, METH_VARARGS, "limn_status_name(status)"},
    {"format_from_name", mod_format_from_name, METH_VARARGS, "limn_format_from_name"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "_limn",
                                        "limn's C API, wrapped (use the package limn).", -1,
                                        module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__limn(void)
{
    LimnContext_Type.tp_methods = all_methods();
    if (PyType_Ready(&LimnContext_Type) < 0 || PyType_Ready(&LimnMesh_Type) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m)
        return NULL;
    if (PyModule_AddObjectRef(m, "Context", (PyObject *)&LimnContext_Type) < 0 ||
        PyModule_AddObjectRef(m, "Mesh", (PyObject *)&LimnMesh_Type) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
