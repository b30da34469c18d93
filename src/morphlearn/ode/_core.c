/* The authors' robot and world in the Open Dynamics Engine, episodes run wholly in C.
 *
 * Every fact here is the paper authors' simulator and robot as recorded in docs/ode.md (world,
 * bodies, joints, contacts, step order, controller, outcome); nothing is fitted to a result.
 * The simulation runs in the authors' frame (robot faces +y, wheels at x = +-0.5); the caller's
 * points are in the project's frame (robot faces +x, +y left): x_a = -y, y_a = x (exact).
 *
 * One call, run_batch, runs n episodes one after another, each in its own world (no episode can
 * depend on another: tested alone, in a batch and in reverse order), with the GIL released.
 *
 * ODE reports through three handlers, all routed here (the guard below): a message (dMessage,
 * e.g. "LCP internal error") is counted and its first text kept, for the caller to say once; an
 * error or an internal assertion (dError, dDebug: "inertia must be positive definite", an AABB
 * beyond its integer range) would abort the interpreter after the handler returns, so the handler
 * jumps (longjmp) out of the episode instead, the world of that episode is left unfreed (ODE may be
 * mid-step: freeing it is not safe), the batch stops and the call raises one RuntimeError.
 * Built against Debian's libode-dev 0.16 (double precision) by setuptools (setup.py).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include <ode/ode.h>

#if !defined(dDOUBLE)
#error "morphlearn.ode needs ODE built in double precision (Debian's libode-dev is)"
#endif

/* Facts of the authors' robot that are not body parameters (docs/ode.md). */
#define SENSOR_RADIUS 0.05
#define SENSOR_MASS 1.0
#define SENSOR_LIFT 0.05 /* sensor centres at z = 2 WR + 0.05 */
#define LIGHT_MASS 1.0
#define LIGHT_Z 0.201
#define CASTOR_Y 0.5 /* castor centre (authors' frame), a sphere as large as a wheel */
#define WHEEL_X 0.5
#define MAX_CONTACTS 10
#define SLIP 0.01

enum { GROUP_NONE = 0, GROUP_ROBOT = 1, GROUP_ENV = 2, GROUP_GROUND = 3 };

/* -- ODE's messages and errors (see the top of this file) ------------------------------------- */

typedef struct {
    jmp_buf jump;
    int armed;           /* an episode is running: an error jumps back to it */
    int failed;          /* an error happened; its text in error */
    char error[240];
    long messages;       /* dMessage calls */
    int message_num;     /* the first one's number and text */
    char message[240];
} Guard;

/* The guard of the call running on this thread (the GIL is released while episodes run). */
static _Thread_local Guard *guard = NULL;

static void fail_with(const char *kind, int num, const char *msg, va_list ap) {
    Guard *g = guard;
    char text[200];
    vsnprintf(text, sizeof text, msg, ap);
    if (g == NULL || !g->armed) { /* not inside an episode: ODE aborts after this returns */
        fprintf(stderr, "%s %d: %s\n", kind, num, text);
        return;
    }
    snprintf(g->error, sizeof g->error, "%s %d: %s", kind, num, text);
    for (char *c = g->error; *c; c++)
        if (*c == '\n' || *c == '\r') *c = ' ';
    g->armed = 0;
    g->failed = 1;
    longjmp(g->jump, 1);
}

static void on_error(int num, const char *msg, va_list ap) { fail_with("ODE error", num, msg, ap); }

static void on_debug(int num, const char *msg, va_list ap) { fail_with("ODE internal error", num, msg, ap); }

static void on_message(int num, const char *msg, va_list ap) {
    Guard *g = guard;
    if (g == NULL) return; /* outside a call: nothing to report it to */
    if (g->messages++ == 0) {
        g->message_num = num;
        vsnprintf(g->message, sizeof g->message, msg, ap);
        for (char *c = g->message; *c; c++)
            if (*c == '\n' || *c == '\r') *c = ' ';
    }
}

/* Body parameters, in this order in the Python tuple (morphlearn.ode.core.params_tuple). */
typedef struct {
    double body_mass, wheel_mass, castor_mass, wheel_radius, max_speed, max_torque, wheel_setback,
        light_radius, gravity, dt, success_radius;
    long steps;
} Params;

typedef struct {
    dWorldID world;
    dJointGroupID contacts;
} CollideData;

/* Which geometry pairs collide (the authors' groups): anything with the ground, robot-env and
 * env-env; never two bodies joined by a joint. */
static int pair_collides(dGeomID o1, dGeomID o2) {
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact)) return 0;
    int g1 = (int)(intptr_t)dGeomGetData(o1), g2 = (int)(intptr_t)dGeomGetData(o2);
    return g1 == GROUP_GROUND || g2 == GROUP_GROUND || (g1 == GROUP_ENV && g2 == GROUP_ENV) ||
           (g1 == GROUP_ROBOT && g2 == GROUP_ENV) || (g1 == GROUP_ENV && g2 == GROUP_ROBOT);
}

static void near_callback(void *data, dGeomID o1, dGeomID o2) {
    CollideData *cd = (CollideData *)data;
    if (!pair_collides(o1, o2)) return;
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    dContact c[MAX_CONTACTS];
    memset(c, 0, sizeof c);
    int n = dCollide(o1, o2, MAX_CONTACTS, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; i++) {
        c[i].surface.mode = dContactSlip1 | dContactSlip2 | dContactApprox1;
        c[i].surface.mu = dInfinity;
        c[i].surface.slip1 = SLIP;
        c[i].surface.slip2 = SLIP;
        dJointID j = dJointCreateContact(cd->world, cd->contacts, &c[i]);
        dJointAttach(j, b1, b2);
    }
}

static dBodyID sphere_body(dWorldID w, dSpaceID s, double mass, double r, double x, double y, double z,
                           int group) {
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetSphereTotal(&m, mass, r);
    dBodySetMass(b, &m);
    dBodySetPosition(b, x, y, z);
    dGeomID g = dCreateSphere(s, r);
    dGeomSetBody(g, b);
    dGeomSetData(g, (void *)(intptr_t)group);
    return b;
}

/* A "fixed" joint of the authors' simulator: a hinge with both stops at 0, anchor at the world
 * origin, axis z, no motor. */
static dJointID fixed_hinge(dWorldID w, dBodyID a, dBodyID b) {
    dJointID j = dJointCreateHinge(w, 0);
    dJointAttach(j, a, b);
    dJointSetHingeAnchor(j, 0, 0, 0);
    dJointSetHingeAxis(j, 0, 0, 1);
    dJointSetHingeParam(j, dParamLoStop, 0);
    dJointSetHingeParam(j, dParamHiStop, 0);
    return j;
}

static dJointID axle(dWorldID w, dBodyID wheel, dBodyID chassis, const dReal *at, double ax) {
    dJointID j = dJointCreateHinge(w, 0);
    dJointAttach(j, wheel, chassis);
    dJointSetHingeAnchor(j, at[0], at[1], at[2]);
    dJointSetHingeAxis(j, ax, 0, 0);
    return j;
}

/* The world of one episode; bodies and joints in the authors' creation order (it fixes the order
 * of the constraint rows, so results depend on it). */
enum { B_LIGHT, B_CHASSIS, B_LEFT, B_RIGHT, B_SENSOR1, B_SENSOR2, B_CASTOR, N_BODIES };
enum { J_LIGHT, J_LEFT, J_RIGHT, J_SENSOR1, J_SENSOR2, J_CASTOR, N_JOINTS };
static const char *BODY_NAMES[N_BODIES] = {"light", "chassis", "left_wheel", "right_wheel", "sensor1", "sensor2", "castor"};

typedef struct {
    dWorldID world;
    dSpaceID space;
    dJointGroupID contacts;
    dGeomID ground;
    dBodyID body[N_BODIES];
    dJointID joint[N_JOINTS];
} World;

static void world_build(World *W, const Params *p, const double *s1, const double *s2, double lx, double ly) {
    const double wr = p->wheel_radius;
    W->world = dWorldCreate();
    dWorldSetGravity(W->world, 0, 0, -p->gravity);
    W->space = dHashSpaceCreate(0);
    W->contacts = dJointGroupCreate(0);
    W->ground = dCreatePlane(W->space, 0, 0, 1, 0);
    dGeomSetData(W->ground, (void *)(intptr_t)GROUP_GROUND);
    dWorldID w = W->world;
    dSpaceID s = W->space;
    W->body[B_LIGHT] = sphere_body(w, s, LIGHT_MASS, p->light_radius, lx, ly, LIGHT_Z, GROUP_ENV);
    dBodyID chassis = W->body[B_CHASSIS] = dBodyCreate(w);
    {
        dMass m;
        dMassSetBoxTotal(&m, p->body_mass, 1.0, 1.0, wr / 2);
        dBodySetMass(chassis, &m);
        dBodySetPosition(chassis, 0, 0, wr);
        dGeomID g = dCreateBox(s, 1.0, 1.0, wr / 2);
        dGeomSetBody(g, chassis);
        dGeomSetData(g, (void *)(intptr_t)GROUP_ROBOT);
    }
    W->body[B_LEFT] = sphere_body(w, s, p->wheel_mass, wr, -WHEEL_X, -p->wheel_setback, wr, GROUP_ROBOT);
    W->body[B_RIGHT] = sphere_body(w, s, p->wheel_mass, wr, WHEEL_X, -p->wheel_setback, wr, GROUP_ROBOT);
    const double sz = 2 * wr + SENSOR_LIFT;
    W->body[B_SENSOR1] = sphere_body(w, s, SENSOR_MASS, SENSOR_RADIUS, s1[0], s1[1], sz, GROUP_NONE);
    W->body[B_SENSOR2] = sphere_body(w, s, SENSOR_MASS, SENSOR_RADIUS, s2[0], s2[1], sz, GROUP_NONE);
    W->body[B_CASTOR] = sphere_body(w, s, p->castor_mass, wr, 0, CASTOR_Y, wr, GROUP_ROBOT);
    W->joint[J_LIGHT] = fixed_hinge(w, W->body[B_LIGHT], 0);
    W->joint[J_LEFT] = axle(w, W->body[B_LEFT], chassis, dBodyGetPosition(W->body[B_LEFT]), -1.0);
    W->joint[J_RIGHT] = axle(w, W->body[B_RIGHT], chassis, dBodyGetPosition(W->body[B_RIGHT]), -1.0);
    W->joint[J_SENSOR1] = fixed_hinge(w, chassis, W->body[B_SENSOR1]);
    W->joint[J_SENSOR2] = fixed_hinge(w, chassis, W->body[B_SENSOR2]);
    /* the castor rolls freely: no motor (FMax stays 0); it moves sideways only by contact slip */
    W->joint[J_CASTOR] = axle(w, W->body[B_CASTOR], chassis, dBodyGetPosition(W->body[B_CASTOR]), 1.0);
}

static void world_destroy(World *W) {
    dJointGroupDestroy(W->contacts);
    dSpaceDestroy(W->space);
    dWorldDestroy(W->world);
}

/* The controller: sensor readings 1 / |p_sensor - p_light|^2 (3D, body centres); sensor 1 drives
 * the right wheel, sensor 2 the left; velocity max_speed * tanh(w s), force limit max_torque. */
static void control(const World *W, const Params *p, double w1, double w2, double *r1, double *r2) {
    const dReal *q1 = dBodyGetPosition(W->body[B_SENSOR1]), *q2 = dBodyGetPosition(W->body[B_SENSOR2]);
    const dReal *ql = dBodyGetPosition(W->body[B_LIGHT]);
    const double e1x = q1[0] - ql[0], e1y = q1[1] - ql[1], e1z = q1[2] - ql[2];
    const double e2x = q2[0] - ql[0], e2y = q2[1] - ql[1], e2z = q2[2] - ql[2];
    *r1 = 1.0 / (e1x * e1x + e1y * e1y + e1z * e1z);
    *r2 = 1.0 / (e2x * e2x + e2y * e2y + e2z * e2z);
    const double m_right = tanh(w1 * *r1), m_left = tanh(w2 * *r2);
    dJointSetHingeParam(W->joint[J_RIGHT], dParamVel, p->max_speed * m_right);
    dJointSetHingeParam(W->joint[J_RIGHT], dParamFMax, p->max_torque);
    dJointSetHingeParam(W->joint[J_LEFT], dParamVel, p->max_speed * m_left);
    dJointSetHingeParam(W->joint[J_LEFT], dParamFMax, p->max_torque);
}

static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CPU seconds spent in dSpaceCollide and dWorldStep (benchmarks: how close an episode is to the
 * cost of dWorldStep alone); NULL when not measured. */
typedef struct {
    double collide, step;
} Timing;

/* One episode. Sensor points and light in the authors' frame. Each step t = 0 .. steps-1:
 * collide -> read the chassis (state before the step) -> controller -> motors -> dWorldStep ->
 * empty the contact group. Writes the first step at which the chassis centre is within
 * success_radius of the light as placed (-1: none), the closest 2D distance up to that step (or
 * over the whole episode if !stop_at_success), the steps simulated, and whether the state stayed
 * finite. With path != NULL, writes the chassis (x, y) read at each step, in the project's frame
 * (2 * steps doubles; the caller fills NaN). Returns 0, or -1 after an ODE error (the guard holds
 * its text; the outputs are not written). */
static int episode(const Params *p, const double *s1, const double *s2, double w1, double w2, double lx,
                   double ly, int stop_at_success, int64_t *first, double *dmin, int64_t *steps,
                   uint8_t *finite, double *path, Timing *timing) {
    World W;
    Guard *g = guard;
    if (setjmp(g->jump)) return -1; /* an ODE error (fail_with): W is left unfreed */
    g->armed = 1;
    world_build(&W, p, s1, s2, lx, ly);
    CollideData cd = {W.world, W.contacts};
    const dBodyID chassis = W.body[B_CHASSIS];
    double best = INFINITY, r1, r2;
    int64_t hit = -1, k = 0;
    uint8_t ok = 1;
    for (k = 0; k < p->steps; k++) {
        double t0 = timing ? cpu_now() : 0;
        dSpaceCollide(W.space, &cd, near_callback);
        if (timing) timing->collide += cpu_now() - t0;
        const dReal *c = dBodyGetPosition(chassis);
        if (!(isfinite(c[0]) && isfinite(c[1]) && isfinite(c[2]))) {
            ok = 0;
            break;
        }
        if (path) {
            path[2 * k] = c[1]; /* project frame: x = y_a, y = -x_a */
            path[2 * k + 1] = -c[0];
        }
        const double dx = c[0] - lx, dy = c[1] - ly;
        const double d = sqrt(dx * dx + dy * dy);
        if (d < best) best = d;
        if (hit < 0 && d <= p->success_radius) {
            hit = k;
            if (stop_at_success) break;
        }
        control(&W, p, w1, w2, &r1, &r2);
        if (timing) t0 = cpu_now();
        dWorldStep(W.world, p->dt);
        if (timing) timing->step += cpu_now() - t0;
        dJointGroupEmpty(W.contacts);
    }
    *first = hit;
    *dmin = best;
    *steps = k;
    *finite = ok;
    world_destroy(&W);
    g->armed = 0;
    return 0;
}

/* -- Python ----------------------------------------------------------------------------------- */

/* "O&" converter: the params tuple of morphlearn.ode.core.params_tuple into Params. */
static int parse_params(PyObject *o, void *out) {
    Params *p = (Params *)out;
    if (!PyArg_ParseTuple(o, "ddddddddddld;params: a tuple of 12 body values (core.params_tuple)", &p->body_mass,
                          &p->wheel_mass, &p->castor_mass, &p->wheel_radius, &p->max_speed, &p->max_torque,
                          &p->wheel_setback, &p->light_radius, &p->gravity, &p->dt, &p->steps, &p->success_radius))
        return 0;
    /* the ranges are the caller's (morphlearn.physics.params); here only what C itself relies on */
    const double v[] = {p->body_mass, p->wheel_mass, p->castor_mass, p->wheel_radius, p->max_speed, p->max_torque,
                        p->wheel_setback, p->light_radius, p->gravity, p->dt, p->success_radius};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        if (!isfinite(v[i])) {
            PyErr_SetString(PyExc_ValueError, "params: every body value must be finite");
            return 0;
        }
    if (p->steps < 1) {
        PyErr_SetString(PyExc_ValueError, "params: steps must be >= 1");
        return 0;
    }
    return 1;
}

/* project frame (x forward, y left) -> the authors' frame (x right, y forward): exact */
static void to_authors(const double *xy, double *out) {
    out[0] = -xy[1];
    out[1] = xy[0];
}

static int get_buffer(PyObject *o, Py_buffer *b, const char *name, const char *fmt, Py_ssize_t n, int writable) {
    if (PyObject_GetBuffer(o, b, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0)) < 0) {
        PyErr_Format(PyExc_TypeError, "%s: a C-contiguous%s buffer is required", name, writable ? " writable" : "");
        return -1;
    }
    const char *f = b->format ? b->format : "B";
    if (f[0] == '<' || f[0] == '=' || f[0] == '@') f++;
    /* int64: numpy says 'l' on LP64 platforms, 'q' elsewhere */
    int same = strcmp(f, fmt) == 0 || (fmt[0] == 'q' && (f[0] == 'l' || f[0] == 'q') && f[1] == 0 && b->itemsize == 8);
    if (!same || b->len != n * b->itemsize) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd items of format '%s', got %zd bytes of '%s'", name, n, fmt,
                     b->len, b->format ? b->format : "B");
        PyBuffer_Release(b);
        return -1;
    }
    return 0;
}

static PyObject *run_batch(PyObject *self, PyObject *args) {
    Params p;
    PyObject *o[8];
    int stop_at_success, timed = 0;
    Py_ssize_t n;
    if (!PyArg_ParseTuple(args, "O&nOOOOOOOpO|p", parse_params, &p, &n, &o[0], &o[1], &o[2], &o[3], &o[4], &o[5],
                          &o[6], &stop_at_success, &o[7], &timed))
        return NULL;
    if (n < 0) {
        PyErr_SetString(PyExc_ValueError, "n must be >= 0");
        return NULL;
    }
    /* the sizes below are products: refuse any that Py_ssize_t cannot hold (4 n; 2 n steps) */
    if (n > PY_SSIZE_T_MAX / 4 || (n > 0 && p.steps > PY_SSIZE_T_MAX / 2 / n)) {
        PyErr_Format(PyExc_ValueError, "n = %zd episodes of %ld steps: the buffers' sizes overflow", n, p.steps);
        return NULL;
    }
    static const char *names[] = {"sensors", "weights", "lights", "first_step", "d_min", "steps", "finite"};
    static const char *fmts[] = {"d", "d", "d", "q", "d", "q", "B"};
    const Py_ssize_t counts[] = {4 * n, 2 * n, 2 * n, n, n, n, n};
    Py_buffer b[8];
    int got = 0;
    for (; got < 7; got++)
        if (get_buffer(o[got], &b[got], names[got], fmts[got], counts[got], got >= 3) < 0) goto fail;
    int with_path = o[7] != Py_None;
    if (with_path && get_buffer(o[7], &b[7], "path", "d", 2 * n * (Py_ssize_t)p.steps, 1) < 0) goto fail;
    if (with_path) got = 8;
    const double *sen = b[0].buf, *w = b[1].buf, *li = b[2].buf;
    for (Py_ssize_t i = 0; i < 4 * n; i++)
        if (!isfinite(sen[i])) {
            PyErr_SetString(PyExc_ValueError, "sensors: not finite");
            goto fail;
        }
    for (Py_ssize_t i = 0; i < 2 * n; i++)
        if (!isfinite(w[i]) || !isfinite(li[i])) {
            PyErr_SetString(PyExc_ValueError, "weights or lights: not finite");
            goto fail;
        }
    Timing timing = {0, 0};
    Guard g;
    memset(&g, 0, sizeof g);
    Py_ssize_t failed_at = -1;
    Py_BEGIN_ALLOW_THREADS;
    guard = &g;
    for (Py_ssize_t i = 0; i < n; i++) {
        double s1[2], s2[2], l[2];
        to_authors(sen + 4 * i, s1);
        to_authors(sen + 4 * i + 2, s2);
        to_authors(li + 2 * i, l);
        if (episode(&p, s1, s2, w[2 * i], w[2 * i + 1], l[0], l[1], stop_at_success, (int64_t *)b[3].buf + i,
                    (double *)b[4].buf + i, (int64_t *)b[5].buf + i, (uint8_t *)b[6].buf + i,
                    with_path ? (double *)b[7].buf + 2 * i * p.steps : NULL, timed ? &timing : NULL) < 0) {
            failed_at = i;
            break;
        }
    }
    guard = NULL;
    Py_END_ALLOW_THREADS;
    for (int i = 0; i < got; i++) PyBuffer_Release(&b[i]);
    if (failed_at >= 0) {
        PyErr_Format(PyExc_RuntimeError, "%s (episode %zd of %zd; the batch stopped there)", g.error, failed_at + 1, n);
        return NULL;
    }
    PyObject *out = Py_BuildValue("{s:l,s:i,s:s}", "messages", g.messages, "message_num", g.message_num, "message",
                                  g.message);
    if (out && timed) {
        PyObject *c = PyFloat_FromDouble(timing.collide), *s = PyFloat_FromDouble(timing.step);
        if (!c || !s || PyDict_SetItemString(out, "collide", c) < 0 || PyDict_SetItemString(out, "world_step", s) < 0)
            Py_CLEAR(out);
        Py_XDECREF(c);
        Py_XDECREF(s);
    }
    return out;
fail:
    for (int i = 0; i < got; i++) PyBuffer_Release(&b[i]);
    return NULL;
}

static const char *name_of(const World *W, dBodyID b) {
    for (int i = 0; i < N_BODIES; i++)
        if (W->body[i] == b) return BODY_NAMES[i];
    return NULL; /* the static world */
}

static PyObject *vec3(const dReal *v) { return Py_BuildValue("(ddd)", v[0], v[1], v[2]); }

/* facts(params, sensors, light, w1, w2): the world an episode builds, read back from ODE (authors'
 * frame), and its first controller step: for the tests that check it against the authors' facts. */
static PyObject *facts(PyObject *self, PyObject *args) {
    Params p;
    double sen[4], li[2], w1, w2;
    if (!PyArg_ParseTuple(args, "O&(dddd)(dd)dd", parse_params, &p, &sen[0], &sen[1], &sen[2], &sen[3], &li[0],
                          &li[1], &w1, &w2))
        return NULL;
    double s1[2], s2[2], l[2];
    to_authors(sen, s1);
    to_authors(sen + 2, s2);
    to_authors(li, l);
    World W;
    Guard gd;
    memset(&gd, 0, sizeof gd);
    guard = &gd;
    if (setjmp(gd.jump)) {
        guard = NULL;
        PyErr_Format(PyExc_RuntimeError, "%s (building the world)", gd.error);
        return NULL;
    }
    gd.armed = 1;
    world_build(&W, &p, s1, s2, l[0], l[1]);
    gd.armed = 0;
    guard = NULL;
    PyObject *out = PyDict_New(), *bodies = PyList_New(0), *joints = PyList_New(0), *pairs = PyList_New(0);
    dVector3 g;
    dWorldGetGravity(W.world, g);
    PyDict_SetItemString(out, "gravity", vec3(g));
    PyDict_SetItemString(out, "erp", PyFloat_FromDouble(dWorldGetERP(W.world)));
    PyDict_SetItemString(out, "cfm", PyFloat_FromDouble(dWorldGetCFM(W.world)));
    PyDict_SetItemString(out, "space", PyUnicode_FromString(dSpaceGetClass(W.space) == dHashSpaceClass ? "hash" : "other"));
    dGeomID geoms[N_BODIES + 1];
    const char *gnames[N_BODIES + 1];
    geoms[0] = W.ground;
    gnames[0] = "ground";
    for (int i = 0; i < N_BODIES; i++) {
        dBodyID b = W.body[i];
        dMass m;
        dBodyGetMass(b, &m);
        dGeomID geom = dBodyGetFirstGeom(b);
        geoms[i + 1] = geom;
        gnames[i + 1] = BODY_NAMES[i];
        PyObject *size;
        const char *shape;
        if (dGeomGetClass(geom) == dSphereClass) {
            shape = "sphere";
            size = PyFloat_FromDouble(dGeomSphereGetRadius(geom));
        } else {
            dVector3 l;
            dGeomBoxGetLengths(geom, l);
            shape = "box";
            size = vec3(l);
        }
        static const char *groups[] = {"none", "robot", "env", "ground"};
        PyObject *d = Py_BuildValue("{s:s,s:d,s:(ddd),s:N,s:s,s:N,s:s}", "name", BODY_NAMES[i], "mass", m.mass,
                                    "inertia", m.I[0], m.I[5], m.I[10], "position", vec3(dBodyGetPosition(b)),
                                    "shape", shape, "size", size, "group",
                                    groups[(int)(intptr_t)dGeomGetData(geom)]);
        PyList_Append(bodies, d);
        Py_DECREF(d);
    }
    for (int i = 0; i < N_JOINTS; i++) {
        dJointID j = W.joint[i];
        dVector3 a, x;
        dJointGetHingeAnchor(j, a);
        dJointGetHingeAxis(j, x);
        const char *n0 = name_of(&W, dJointGetBody(j, 0)), *n1 = name_of(&W, dJointGetBody(j, 1));
        PyObject *d = Py_BuildValue(
            "{s:s,s:(zz),s:N,s:N,s:d,s:d,s:d}", "type", dJointGetType(j) == dJointTypeHinge ? "hinge" : "other",
            "bodies", n0, n1, "anchor", vec3(a), "axis", vec3(x), "lo_stop", dJointGetHingeParam(j, dParamLoStop),
            "hi_stop", dJointGetHingeParam(j, dParamHiStop), "fmax", dJointGetHingeParam(j, dParamFMax));
        PyList_Append(joints, d);
        Py_DECREF(d);
    }
    for (int i = 0; i <= N_BODIES; i++)
        for (int k = i + 1; k <= N_BODIES; k++)
            if (pair_collides(geoms[i], geoms[k])) {
                PyObject *t = Py_BuildValue("(ss)", gnames[i], gnames[k]);
                PyList_Append(pairs, t);
                Py_DECREF(t);
            }
    double r1, r2;
    control(&W, &p, w1, w2, &r1, &r2);
    PyObject *step0 = Py_BuildValue(
        "{s:d,s:d,s:d,s:d,s:d,s:d}", "s1", r1, "s2", r2, "vel_right", dJointGetHingeParam(W.joint[J_RIGHT], dParamVel),
        "vel_left", dJointGetHingeParam(W.joint[J_LEFT], dParamVel), "fmax_right",
        dJointGetHingeParam(W.joint[J_RIGHT], dParamFMax), "fmax_left", dJointGetHingeParam(W.joint[J_LEFT], dParamFMax));
    PyDict_SetItemString(out, "bodies", bodies);
    PyDict_SetItemString(out, "joints", joints);
    PyDict_SetItemString(out, "collides", pairs);
    PyDict_SetItemString(out, "step0", step0);
    Py_DECREF(bodies);
    Py_DECREF(joints);
    Py_DECREF(pairs);
    Py_DECREF(step0);
    world_destroy(&W);
    return out;
}

static PyObject *config(PyObject *self, PyObject *noargs) {
    const char *c = dGetConfiguration();
    return PyUnicode_FromString(c ? c : "");
}

static PyObject *version(PyObject *self, PyObject *noargs) { return PyUnicode_FromString(dODE_VERSION); }

static PyMethodDef methods[] = {
    {"run_batch", run_batch, METH_VARARGS,
     "run_batch(params, n, sensors, weights, lights, first_step, d_min, steps, finite, stop_at_success, path[, timed]) "
     "-> {messages, message_num, message[, collide, world_step]}; an ODE error raises RuntimeError"},
    {"facts", facts, METH_VARARGS, "facts(params, sensors, light, w1, w2): the world as built, read back."},
    {"version", version, METH_NOARGS, "The ODE version the core was built against (ode/version.h)."},
    {"config", config, METH_NOARGS, "ODE's build configuration string (dGetConfiguration)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_core", "The authors' robot in ODE (C).", -1, methods};

PyMODINIT_FUNC PyInit__core(void) {
    if (!dInitODE2(0)) {
        PyErr_SetString(PyExc_ImportError, "dInitODE2 failed");
        return NULL;
    }
    dSetErrorHandler(on_error);
    dSetDebugHandler(on_debug);
    dSetMessageHandler(on_message);
    return PyModule_Create(&module);
}
