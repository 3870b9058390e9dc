/* A callable that runs a compiled model's one-state right-hand side with CPython's
 * vectorcall protocol, for `CompiledSystem.rhs_c`.
 *
 * Why: through ctypes, one call of `lg_eval_rhs` costs about 0.7 µs and each
 * `ndarray.ctypes.data` about 0.9 µs, so a single state took ~4 µs while the C itself
 * takes 0.08 µs (the top) to 2 µs (a 20-link chain).  Here the arrays are read through
 * NumPy's C API and the call costs about 0.1 µs more than the C evaluation.
 *
 *     caller = RhsCaller(address_of_lg_eval_rhs, n_state, n_params, library)
 *     status = caller(t, y, p, out)      # out <- (q', q''), status 0 = fine
 *
 * It is compiled once per Python version (see `_fastcall.py`), not once per model: the
 * model's function arrives as an address, with the object that keeps its library loaded.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

typedef int (*rhs_fn)(int, const double *, const double *, const double *, double *);

typedef struct {
    PyObject_HEAD
    rhs_fn fn;
    Py_ssize_t n_state;   /* 2n: length of y and out */
    Py_ssize_t n_params;  /* least length of p */
    vectorcallfunc vectorcall;
    PyObject *owner;      /* what keeps the code at `fn` loaded (the ctypes library) */
} RhsCaller;

/* The array's data, checked: a C-contiguous, aligned float64 ndarray (writable for `out`)
 * of at least `least` numbers.  NumPy's own accessors: the buffer protocol would cost
 * ~0.1 µs per array, which is more than the top's whole evaluation. */
static double *get_doubles(PyObject *obj, int writable, npy_intp least, const char *name) {
    if (!PyArray_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "rhs_c: `%s` must be a NumPy array", name);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)obj;
    int need = NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED | (writable ? NPY_ARRAY_WRITEABLE : 0);
    if (PyArray_TYPE(a) != NPY_DOUBLE || !PyArray_CHKFLAGS(a, need)) {
        PyErr_Format(PyExc_TypeError, "rhs_c: `%s` must be a contiguous%s float64 array", name,
                     writable ? ", writable" : "");
        return NULL;
    }
    if (PyArray_SIZE(a) < least) {
        PyErr_Format(PyExc_ValueError, "rhs_c: `%s` holds %zd numbers, %zd are needed", name,
                     (Py_ssize_t)PyArray_SIZE(a), (Py_ssize_t)least);
        return NULL;
    }
    return (double *)PyArray_DATA(a);
}

static PyObject *caller_vectorcall(PyObject *self_obj, PyObject *const *args, size_t nargsf, PyObject *kwnames) {
    RhsCaller *self = (RhsCaller *)self_obj;
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    if (nargs != 4 || (kwnames && PyTuple_GET_SIZE(kwnames))) {
        PyErr_SetString(PyExc_TypeError, "rhs_c(t, y, p, out) takes exactly 4 positional arguments");
        return NULL;
    }
    double t = PyFloat_AsDouble(args[0]);
    if (t == -1.0 && PyErr_Occurred()) {
        return NULL;
    }
    const double *y = get_doubles(args[1], 0, self->n_state, "y");
    const double *p = y ? get_doubles(args[2], 0, self->n_params, "p") : NULL;
    double *out = p ? get_doubles(args[3], 1, self->n_state, "out") : NULL;
    if (!out) {
        return NULL;
    }
    int status = self->fn(1, &t, y, p, out);
    return PyLong_FromLong(status);
}

static PyObject *caller_new(PyTypeObject *type, PyObject *args, PyObject *kwargs) {
    unsigned long long address;
    Py_ssize_t n_state, n_params;
    PyObject *owner;
    if (!PyArg_ParseTuple(args, "KnnO", &address, &n_state, &n_params, &owner)) {
        return NULL;
    }
    if (!address || n_state < 0 || n_params < 0) {
        PyErr_SetString(PyExc_ValueError, "RhsCaller(address, n_state, n_params, owner): bad arguments");
        return NULL;
    }
    RhsCaller *self = (RhsCaller *)type->tp_alloc(type, 0);
    if (!self) {
        return NULL;
    }
    self->fn = (rhs_fn)(uintptr_t)address;
    self->n_state = n_state;
    self->n_params = n_params;
    self->vectorcall = caller_vectorcall;
    Py_INCREF(owner);
    self->owner = owner;
    return (PyObject *)self;
}

static void caller_dealloc(PyObject *self) {
    Py_XDECREF(((RhsCaller *)self)->owner);
    Py_TYPE(self)->tp_free(self);
}

static PyTypeObject RhsCallerType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lagrangian_fastcall.RhsCaller",
    .tp_doc = "rhs_c(t, y, p, out) -> status: one state of a compiled model's right-hand side",
    .tp_basicsize = sizeof(RhsCaller),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_VECTORCALL,
    .tp_new = caller_new,
    .tp_dealloc = caller_dealloc,
    .tp_call = PyVectorcall_Call,
    .tp_vectorcall_offset = offsetof(RhsCaller, vectorcall),
};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "lagrangian_fastcall",
    "Vectorcall wrapper of a compiled model's right-hand side.", -1, NULL,
};

PyMODINIT_FUNC PyInit_lagrangian_fastcall(void) {
    import_array();
    if (PyType_Ready(&RhsCallerType) < 0) {
        return NULL;
    }
    PyObject *module = PyModule_Create(&module_def);
    if (!module) {
        return NULL;
    }
    Py_INCREF(&RhsCallerType);
    if (PyModule_AddObject(module, "RhsCaller", (PyObject *)&RhsCallerType) < 0) {
        Py_DECREF(&RhsCallerType);
        Py_DECREF(module);
        return NULL;
    }
    return module;
}
