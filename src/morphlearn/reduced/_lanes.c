/* The reduced model's SIMD kernel (reduced.backend: cpu-simd): kernel.py's episode, eight episodes a
 * core side by side in float64 lanes, outcomes identical to the scalar kernel's (_lanes_kernel.h says
 * how). Compiled twice: for AVX-512 (chosen at run time where the CPU has it) and for the x86-64
 * baseline, both with -ffp-contract=off (setup.py): the only fused operations are the explicit ones
 * that mirror libm's FMA build of expm1. The GIL is released while it runs. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <immintrin.h>
#include <math.h>
#include <string.h>

#define SWEEPS 100 /* kernel.py's _SWEEPS */
#ifndef GROUPS
#define GROUPS 2 /* groups of eight lanes a core steps together */
#endif
#define TANH_LIBM 0
#define TANH_PLAIN 1
#define TANH_FMA 2

#define CAT2(a, b) a##_##b
#define CAT(a, b) CAT2(a, b)

typedef struct {
    const double *g, *hm, *kk, *cen, *sen;
    double dt, vmax, tmax, radius, dz2;
    long long steps;
} Consts;

typedef double V8 __attribute__((vector_size(64)));
typedef long long VI8 __attribute__((vector_size(64)));
typedef struct {
    V8 x, y, c, s, q0, q1, q2, q3, q4, q5, best, lx, ly, w1, w2;
    VI8 hit, step, live;
    long long idx[8];
} Lanes;

#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq,fma")
#define NAME episodes_avx512
#define HAVE_FMA 1
#include "_lanes_kernel.h"
#undef NAME
#undef HAVE_FMA
#pragma GCC pop_options

#define NAME episodes_base
#define HAVE_FMA 0
#include "_lanes_kernel.h"
#undef NAME
#undef HAVE_FMA

static int isa_avx512(void) {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("fma");
}

/* the check set: both signs, magnitudes log-uniform over every branch of tanh and expm1 (2^-60 to
 * 2^6) and the thresholds between them */
static void check_set(double *v, int n) {
    unsigned long long st = 0x9E3779B97F4A7C15ULL;
    const double edges[] = {22.0, 1.0, 0x1p-55, 0x1p-54, 0.5 * 0.6931471805599453, 0.75 * 0.6931471805599453,
                            0.5, 0.25, 0.125, 19.4, 28.0, 38.8};
    int ne = (int)(sizeof edges / sizeof edges[0]);
    for (int i = 0; i < n; i++) {
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        double u = (double)(st >> 11) * 0x1p-53;
        st = st * 6364136223846793005ULL + 1442695040888963407ULL;
        double m = 1.0 + (double)(st >> 11) * 0x1p-53;
        double x;
        if (i % 16 == 0) { /* next to a threshold: a few ulps either side */
            double e = edges[(i / 16) % ne];
            int ulps = (int)((st >> 3) % 9) - 4;
            x = e;
            for (int k = 0; k < (ulps < 0 ? -ulps : ulps); k++) x = nextafter(x, ulps < 0 ? 0.0 : INFINITY);
        } else {
            x = ldexp(m, (int)(-60.0 + 66.0 * u));
        }
        v[i] = (st >> 63) ? -x : x;
    }
}

#define NCHECK (1 << 17)
static int chosen_mode = -1, chosen_isa = 0;

/* the tanh mode whose every result on the check set is libm's, bit for bit (libm itself if none) */
static int tanh_ok(int isa, int mode, const double *v) {
    for (int i = 0; i < NCHECK; i += 8) {
        double out[8];
        if (isa)
            tanh8_episodes_avx512(v + i, out, mode);
        else
            tanh8_episodes_base(v + i, out, mode);
        for (int j = 0; j < 8; j++) {
            double ref = tanh(v[i + j]);
            if (memcmp(&ref, &out[j], sizeof ref) != 0) return 0;
        }
    }
    return 1;
}

static void choose(void) {
    if (chosen_mode >= 0) return;
    static double v[NCHECK];
    check_set(v, NCHECK);
    chosen_isa = isa_avx512();
    const int order_avx[] = {TANH_FMA, TANH_PLAIN}, order_base[] = {TANH_PLAIN};
    const int *order = chosen_isa ? order_avx : order_base;
    int no = chosen_isa ? 2 : 1;
    chosen_mode = TANH_LIBM;
    for (int m = 0; m < no; m++)
        if (tanh_ok(chosen_isa, order[m], v)) {
            chosen_mode = order[m];
            break;
        }
}

static int get_buffer(PyObject *o, Py_buffer *b, const char *name, Py_ssize_t itemsize, Py_ssize_t n, int writable) {
    if (PyObject_GetBuffer(o, b, PyBUF_C_CONTIGUOUS | (writable ? PyBUF_WRITABLE : 0)) < 0) {
        PyErr_Format(PyExc_TypeError, "%s: a C-contiguous%s buffer is required", name, writable ? " writable" : "");
        return -1;
    }
    if (b->len != n * itemsize) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd bytes, got %zd", name, n * itemsize, b->len);
        PyBuffer_Release(b);
        return -1;
    }
    return 0;
}

/* run_batch(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights, sen, w, stop, first, dmin,
 * nsteps, finite, mode): cpu.run_batch's arguments (float64, int64, bool buffers) and the tanh mode
 * (-1: the one choose() picked) */
static PyObject *run_batch(PyObject *self, PyObject *args) {
    PyObject *o[11];
    Consts k;
    int stop, mode;
    if (!PyArg_ParseTuple(args, "OOOOdLdddd" "OOOp" "OOOOi", &o[0], &o[1], &o[2], &o[3], &k.dt, &k.steps, &k.vmax,
                          &k.tmax, &k.radius, &k.dz2, &o[4], &o[5], &o[6], &stop, &o[7], &o[8], &o[9], &o[10], &mode))
        return NULL;
    Py_buffer b[11];
    const char *names[] = {"g", "hm", "kk", "cen", "lights", "sen", "w", "first", "dmin", "nsteps", "finite"};
    Py_ssize_t n = 0;
    {
        Py_buffer tmp;
        if (PyObject_GetBuffer(o[9], &tmp, PyBUF_C_CONTIGUOUS) < 0) return NULL;
        n = tmp.len / 8;
        PyBuffer_Release(&tmp);
    }
    const Py_ssize_t sizes[] = {36, 12, 8, 6, 2 * n, 4, 2 * n, n, n, n, n};
    const Py_ssize_t items[] = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 1};
    int got = 0;
    for (; got < 11; got++)
        if (get_buffer(o[got], &b[got], names[got], items[got], sizes[got], got >= 7) < 0) break;
    if (got < 11) {
        for (int i = 0; i < got; i++) PyBuffer_Release(&b[i]);
        return NULL;
    }
    choose();
    if (mode < 0) mode = chosen_mode;
    if (mode != TANH_LIBM && mode != TANH_PLAIN && !(mode == TANH_FMA && chosen_isa)) {
        for (int i = 0; i < 11; i++) PyBuffer_Release(&b[i]);
        PyErr_Format(PyExc_ValueError, "mode = %d is invalid here", mode);
        return NULL;
    }
    k.g = b[0].buf, k.hm = b[1].buf, k.kk = b[2].buf, k.cen = b[3].buf, k.sen = b[5].buf;
    Py_BEGIN_ALLOW_THREADS;
    if (chosen_isa)
        episodes_avx512(&k, n, b[4].buf, b[6].buf, stop, mode, b[7].buf, b[8].buf, b[9].buf, b[10].buf);
    else
        episodes_base(&k, n, b[4].buf, b[6].buf, stop, mode, b[7].buf, b[8].buf, b[9].buf, b[10].buf);
    Py_END_ALLOW_THREADS;
    for (int i = 0; i < 11; i++) PyBuffer_Release(&b[i]);
    Py_RETURN_NONE;
}

/* tanh(x, out, mode): the kernel's tanh of float64 buffers (a multiple of 8 items), for the tests */
static PyObject *tanh_lanes(PyObject *self, PyObject *args) {
    PyObject *oi, *oo;
    int mode;
    if (!PyArg_ParseTuple(args, "OOi", &oi, &oo, &mode)) return NULL;
    choose();
    if (mode < 0) mode = chosen_mode;
    if (mode != TANH_LIBM && mode != TANH_PLAIN && !(mode == TANH_FMA && chosen_isa)) {
        PyErr_Format(PyExc_ValueError, "mode = %d is invalid here", mode);
        return NULL;
    }
    Py_buffer bi, bo;
    if (PyObject_GetBuffer(oi, &bi, PyBUF_C_CONTIGUOUS) < 0) return NULL;
    if (get_buffer(oo, &bo, "out", 1, bi.len, 1) < 0 || bi.len % 64) {
        if (bi.len % 64 == 0) PyBuffer_Release(&bi);
        else PyErr_SetString(PyExc_ValueError, "x: a multiple of 8 float64 is required");
        return NULL;
    }
    for (Py_ssize_t i = 0; i < bi.len / 8; i += 8) {
        if (chosen_isa)
            tanh8_episodes_avx512((const double *)bi.buf + i, (double *)bo.buf + i, mode);
        else
            tanh8_episodes_base((const double *)bi.buf + i, (double *)bo.buf + i, mode);
    }
    PyBuffer_Release(&bi);
    PyBuffer_Release(&bo);
    Py_RETURN_NONE;
}

/* (instruction set, tanh mode) the kernel runs with */
static PyObject *mode(PyObject *self, PyObject *args) {
    choose();
    return Py_BuildValue("(si)", chosen_isa ? "avx512" : "x86-64", chosen_mode);
}

static PyMethodDef methods[] = {
    {"run_batch", run_batch, METH_VARARGS, "Episodes across lanes (cpu.run_batch's arguments, then the tanh mode)."},
    {"tanh", tanh_lanes, METH_VARARGS, "The kernel's tanh (x, out, mode), for the tests."},
    {"mode", mode, METH_NOARGS, "(instruction set, tanh mode: 0 libm, 1 fdlibm baseline, 2 fdlibm FMA)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_lanes", NULL, -1, methods};

PyMODINIT_FUNC PyInit__lanes(void) { return PyModule_Create(&module); }
