/* The reduced model's episodes, eight at a time: one lane an episode, compiled once per instruction
 * set by _lanes.c (which defines NAME, HAVE_FMA and includes this file inside a target region).
 * GROUPS vectors of eight lanes are stepped in turn so their dependency chains overlap on the core.
 * Where the time goes (perf, AVX-512): the six divisions a step (the sensors' 1 / (d1 d2), the two
 * tanh's two each, the heading turn's 1 / (1 + t^2)) and the 512-bit ports' throughput; where every
 * lane's tanh argument is below 1 (far from the light, most steps) tanh takes fdlibm's k = 0 branch
 * alone, with no argument reduction.
 *
 * Every lane does exactly the scalar kernel's arithmetic (kernel.py as numba compiles it: no
 * contraction, the same expression order, the same branches as selects), so a lane's state is the
 * scalar episode's to the last bit. tanh is libm's algorithm (fdlibm's tanh over its expm1) evaluated
 * across lanes with the operations of the libm this process runs (TANH_FMA: glibc's FMA build of
 * expm1, whose fused operations are mirrored one by one; TANH_PLAIN: its baseline build), or libm's
 * own tanh called lane by lane (TANH_LIBM); _lanes.c picks the mode that matches libm on its check
 * set, libm itself when none does. Inputs outside the ranges the vector path covers (zero, below
 * 2^-55, NaN, infinity) go to libm lane by lane in every mode. */

typedef V8 V;
typedef VI8 VI;

#define LANES 8

static inline __attribute__((always_inline)) V CAT(sel, NAME)(VI m, V a, V b) {
    return (V)(((VI)a & m) | ((VI)b & ~m));
}
#define SEL CAT(sel, NAME)

static inline __attribute__((always_inline)) int CAT(any, NAME)(VI m) {
#if HAVE_FMA
    return _mm512_test_epi64_mask((__m512i)m, (__m512i)m) != 0;
#else
    long long r = 0;
    for (int j = 0; j < LANES; j++) r |= m[j];
    return r != 0;
#endif
}
#define ANY CAT(any, NAME)

static inline __attribute__((always_inline)) V CAT(splat, NAME)(double v) {
    V r = {v, v, v, v, v, v, v, v};
    return r;
}
#define S CAT(splat, NAME)

#if HAVE_FMA /* a * b + c, -(a * b) + c, a * b - c, each rounded once */
#define FMA(a, b, c) ((V)_mm512_fmadd_pd((__m512d)(a), (__m512d)(b), (__m512d)(c)))
#define FNMA(a, b, c) ((V)_mm512_fnmadd_pd((__m512d)(a), (__m512d)(b), (__m512d)(c)))
#define FMS(a, b, c) ((V)_mm512_fmsub_pd((__m512d)(a), (__m512d)(b), (__m512d)(c)))
#endif

/* expm1 at lanes whose argument lies in (-2, -2^-54] or [2, 44) (what tanh passes on), fdlibm's
 * algorithm; fused is 1 for the FMA build's operations, 0 for the baseline's. Its reduction k is
 * then 0, -1, -2, -3 (negative arguments) or 3..64 (positive): fdlibm's k == 1 branch never runs
 * and is left out */
static inline __attribute__((always_inline)) V CAT(expm1v, NAME)(V y, int fused) {
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10,
                 invln2 = 1.44269504088896338700e+00, q1 = -3.33333333333331316428e-02,
                 q2 = 1.58730158725481460165e-03, q3 = -7.93650757867487942473e-05,
                 q4 = 4.00821782732936239552e-06, q5 = -2.01099218183624371326e-07;
    VI bits = (VI)y;
    VI neg = bits < 0;
    VI hy = (bits >> 32) & 0x7fffffff;
    VI path0 = hy <= 0x3fd62e42;
    if (!ANY(~path0)) { /* every lane at k = 0 (far from the light, most steps): no reduction */
        V hfx = 0.5 * y;
        V hxs = y * hfx;
        V h2 = hxs * hxs;
        V h4 = h2 * h2;
#if HAVE_FMA
        if (fused) {
            V r1 = FMA(h4, FMA(hxs, S(q5), S(q4)), FMA(h2, FMA(hxs, S(q3), S(q2)), FMA(hxs, S(q1), S(1.0))));
            V t = FNMA(r1, hfx, S(3.0));
            V e = ((r1 - t) / FNMA(t, y, S(6.0))) * hxs;
            return y - FMS(e, y, hxs);
        }
#endif
        V r1 = ((1.0 + hxs * q1) + h2 * (q2 + hxs * q3)) + h4 * (q4 + hxs * q5);
        V t = 3.0 - r1 * hfx;
        V e = hxs * ((r1 - t) / (6.0 - y * t));
        return y - (y * e - hxs);
    }
    VI path1 = ~path0 & (hy < 0x3FF0A2B2);
    V half = SEL(neg, S(-0.5), S(0.5));
    VI kg = __builtin_convertvector(invln2 * y + half, VI); /* not fused in either build */
    VI one_i = {1, 1, 1, 1, 1, 1, 1, 1};
    VI kpm = (one_i & ~neg) | (-one_i & neg);
    VI k = (kg & ~path0 & ~path1) | (kpm & path1);
    V tk = __builtin_convertvector(k, V);
    V hi;
#if HAVE_FMA
    if (fused)
        hi = FNMA(tk, S(ln2_hi), y);
    else
#endif
        hi = y - tk * ln2_hi;
    V lo = tk * ln2_lo;
    V xr = hi - lo;
    V c = (hi - xr) - lo;
    xr = SEL(path0, y, xr);
    V hfx = 0.5 * xr;
    V hxs = xr * hfx;
    V h2 = hxs * hxs;
    V h4 = h2 * h2;
    V r1, t, e, r0, e2, rm1;
#if HAVE_FMA
    if (fused) {
        V R1 = FMA(hxs, S(q1), S(1.0));
        V R2 = FMA(hxs, S(q3), S(q2));
        V R3 = FMA(hxs, S(q5), S(q4));
        r1 = FMA(h4, R3, FMA(h2, R2, R1));
        t = FNMA(r1, hfx, S(3.0));
        e = ((r1 - t) / FNMA(t, xr, S(6.0))) * hxs;
        r0 = xr - FMS(e, xr, hxs);
        e2 = FMS(e - c, xr, c) - hxs;
        rm1 = FMA(S(0.5), xr - e2, S(-0.5));
    } else
#endif
    {
        V R1 = 1.0 + hxs * q1;
        V R2 = q2 + hxs * q3;
        V R3 = q4 + hxs * q5;
        r1 = (R1 + h2 * R2) + h4 * R3;
        t = 3.0 - r1 * hfx;
        e = hxs * ((r1 - t) / (6.0 - xr * t));
        r0 = xr - (xr * e - hxs);
        e2 = (xr * (e - c) - c) - hxs;
        rm1 = 0.5 * (xr - e2) - 0.5;
    }
    VI kexp = k << 52; /* k added to the exponent (the high word's k << 20) */
    /* k <= -2 or k > 56 */
    V yw = (V)((VI)(1.0 - (e2 - xr)) + kexp) - 1.0;
    /* 2 <= k < 20: t = 1 - 2^-k */
    VI ks = k & 31;
    VI tsmall = (0x3ff00000LL - (0x200000LL >> ks)) << 32;
    V ys = (V)((VI)((V)tsmall - (e2 - xr)) + kexp);
    /* 20 <= k <= 56: t = 2^-k */
    VI tbig = (0x3ffLL - k) << 52;
    V yb = (V)((VI)((xr - (e2 + (V)tbig)) + 1.0) + kexp);
    V r = SEL((k <= -2) | (k > 56), yw, SEL(k < 20, ys, yb));
    r = SEL(k == -1, rm1, r);
    r = SEL(k == 0, r0, r);
    return r;
}
#define EXPM1V CAT(expm1v, NAME)

/* tanh across lanes, libm's to the last bit (see the file's comment) */
static inline __attribute__((always_inline)) V CAT(tanhv, NAME)(V x, int mode) {
    if (mode == TANH_LIBM) {
        V r = x;
        for (int j = 0; j < LANES; j++) r[j] = tanh(x[j]);
        return r;
    }
    VI bits = (VI)x;
    VI sign = bits & (VI)S(-0.0);
    V ax = (V)(bits & 0x7fffffffffffffffLL);
    VI hx = (VI)ax >> 32;
    VI regular = (hx >= 0x3c800000) & (hx < 0x40360000);
    if (!ANY(~(regular & (hx < 0x3ff00000)))) { /* every lane in [2^-55, 1): tanh's second branch only */
        V t = EXPM1V(-2.0 * ax, mode == TANH_FMA);
        return (V)((VI)(-t / (t + 2.0)) ^ sign);
    }
    VI big = (hx >= 0x40360000) & (hx < 0x7ff00000);
    VI ge1 = hx >= 0x3ff00000;
    V arg = SEL(ge1, ax + ax, -2.0 * ax);
    arg = SEL(regular, arg, S(-0.25)); /* a harmless argument (k = 0) where the lane's result is unused */
    V t = EXPM1V(arg, mode == TANH_FMA);
    V qz = SEL(ge1, S(2.0), -t) / (t + 2.0); /* one division for both branches' quotients */
    V z = SEL(ge1, 1.0 - qz, qz);
    z = SEL(big, S(1.0 - 1.0e-300), z);
    V r = (V)((VI)z ^ sign);
    VI other = ~(regular | big);
    if (ANY(other))
        for (int j = 0; j < LANES; j++)
            if (other[j]) r[j] = tanh(x[j]);
    return r;
}
#define TANHV CAT(tanhv, NAME)

/* eight tanh from memory to memory (the check of the mode against libm) */
static __attribute__((noinline)) void CAT(tanh8, NAME)(const double *in, double *out, int mode) {
    V x;
    memcpy(&x, in, sizeof x);
    V r = TANHV(x, mode);
    memcpy(out, &r, sizeof r);
}

static inline double CAT(clamp, NAME)(double v, double tmax) {
    double m = (-tmax > v) ? -tmax : v; /* max(v, -tmax) */
    return (tmax < m) ? tmax : m;       /* min(m, tmax) */
}

/* kernel.py's capped: the exact active-set solution where the sweeps did not settle (one lane) */
static void CAT(capped, NAME)(const double *kk, double r0, double r1, double tmax, double *pa, double *pb) {
    double k00 = kk[0], k01 = kk[1], k11 = kk[2], a = 0.0, b = 0.0;
    for (int which = 0; which < 4; which++) {
        if (which < 2) {
            a = which == 0 ? tmax : -tmax;
            b = (r1 - k01 * a) * kk[7];
            double g = k00 * a + k01 * b - r0;
            if (-tmax <= b && b <= tmax && ((a > 0.0 && g <= 0.0) || (a < 0.0 && g >= 0.0))) {
                *pa = a, *pb = b;
                return;
            }
        } else {
            b = which == 2 ? tmax : -tmax;
            a = (r0 - k01 * b) * kk[6];
            double g = k01 * a + k11 * b - r1;
            if (-tmax <= a && a <= tmax && ((b > 0.0 && g <= 0.0) || (b < 0.0 && g >= 0.0))) {
                *pa = a, *pb = b;
                return;
            }
        }
    }
    for (int corner = 0; corner < 4; corner++) {
        a = corner < 2 ? tmax : -tmax;
        b = corner % 2 == 0 ? tmax : -tmax;
        double g0 = k00 * a + k01 * b - r0;
        double g1 = k01 * a + k11 * b - r1;
        if (((a > 0.0 && g0 <= 0.0) || (a < 0.0 && g0 >= 0.0)) && ((b > 0.0 && g1 <= 0.0) || (b < 0.0 && g1 >= 0.0))) {
            *pa = a, *pb = b;
            return;
        }
    }
    *pa = a, *pb = b;
}

static inline __attribute__((always_inline)) V CAT(clampv, NAME)(V v, double tmax) {
    V m = SEL(-tmax > v, S(-tmax), v);
    return SEL(tmax < m, S(tmax), m);
}

/* kernel.py's motors across lanes: the unconstrained solution, else projected Gauss-Seidel lane by
 * lane to its fixed point (each lane stops at the sweep its scalar loop stops at) */
static inline __attribute__((always_inline)) void CAT(motorsv, NAME)(const double *kk, V r0, V r1, double tmax,
                                                                    VI live, V *pa, V *pb) {
    V a = kk[3] * r0 + kk[4] * r1;
    V b = kk[4] * r0 + kk[5] * r1;
    VI free = (-tmax <= a) & (a <= tmax) & (-tmax <= b) & (b <= tmax);
    VI todo = ~free & live;
    if (ANY(todo)) {
        double k01 = kk[1];
        V ga = CAT(clampv, NAME)(r0 * kk[6], tmax);
        V gb = CAT(clampv, NAME)((r1 - k01 * ga) * kk[7], tmax);
        VI active = todo;
        for (int it = 0; it < SWEEPS && ANY(active); it++) {
            V a1 = CAT(clampv, NAME)((r0 - k01 * gb) * kk[6], tmax);
            V b1 = CAT(clampv, NAME)((r1 - k01 * a1) * kk[7], tmax);
            VI settled = (a1 == ga) & (b1 == gb);
            active &= ~settled;
            ga = SEL(active, a1, ga);
            gb = SEL(active, b1, gb);
        }
        if (ANY(active))
            for (int j = 0; j < LANES; j++)
                if (active[j]) {
                    double ca, cb;
                    CAT(capped, NAME)(kk, r0[j], r1[j], tmax, &ca, &cb);
                    ga[j] = ca;
                    gb[j] = cb;
                }
        a = SEL(todo, ga, a);
        b = SEL(todo, gb, b);
    }
    *pa = a;
    *pb = b;
}

/* a lane takes episode i from rest, or (i < 0) rests with nothing to run */
static inline __attribute__((always_inline)) void CAT(load, NAME)(Lanes *L, int j, Py_ssize_t i, const double *lights,
                                                                 const double *w) {
    L->idx[j] = i;
    if (i >= 0) {
        L->lx[j] = lights[2 * i], L->ly[j] = lights[2 * i + 1];
        L->w1[j] = w[2 * i], L->w2[j] = w[2 * i + 1];
    }
    L->live[j] = i >= 0 ? -1 : 0;
    L->x[j] = L->y[j] = L->s[j] = 0.0;
    L->c[j] = 1.0;
    L->q0[j] = L->q1[j] = L->q2[j] = L->q3[j] = L->q4[j] = L->q5[j] = 0.0;
    L->best[j] = INFINITY;
    L->hit[j] = -1;
    L->step[j] = 0;
}

/* one pass of the eight lanes of ``L``: each live lane's checks at its step, then its step */
typedef struct {
    V dt, vmax, dz2, radius2, hdt, l1x, l1y, l2x, l2y;
} CAT(KV, NAME);

static inline __attribute__((always_inline)) void CAT(pass, NAME)(Lanes *restrict Lp, const Consts *k,
                                                                 const CAT(KV, NAME) *kv, Py_ssize_t n,
                                                                 Py_ssize_t *nextp, const double *lights,
                                                                 const double *w, int stop, int mode, long long *first,
                                                                 double *dmin, long long *nsteps,
                                                                 unsigned char *finite) {
    const double *g = k->g, *hm = k->hm, *cen = k->cen;
    /* the scalars as vectors made once a call (kv): loaded with the operation, not broadcast each pass */
    const V dt = kv->dt, vmax = kv->vmax, dz2 = kv->dz2, radius2 = kv->radius2, hdt = kv->hdt;
    const V l1x = kv->l1x, l1y = kv->l1y, l2x = kv->l2x, l2y = kv->l2y;
    const double tmax = k->tmax;
    const long long steps = k->steps;
    const VI none = {0, 0, 0, 0, 0, 0, 0, 0}, one = {1, 1, 1, 1, 1, 1, 1, 1};
#define L (*Lp)
    Py_ssize_t next = *nextp;
        V x = L.x, y = L.y, c = L.c, s = L.s, q0 = L.q0, q1 = L.q1, q2 = L.q2, q3 = L.q3, q4 = L.q4, q5 = L.q5;
    /* the checks at the top of the scalar loop */
    VI fin = (VI)((x - x) == 0.0) & (VI)((y - y) == 0.0); /* isfinite(x) and isfinite(y) */
    V dx = x - L.lx;
    V dy = y - L.ly;
    V d2 = dx * dx + dy * dy;
    VI ok = L.live & fin;
    L.best = SEL(ok & (d2 < L.best), d2, L.best);
    VI newhit = ok & (L.hit < 0) & (d2 <= radius2);
    L.hit = (L.hit & ~newhit) | (L.step & newhit);
    VI ended = (L.live & ~fin) | (stop ? newhit : none);
    VI fresh = none;
    if (ANY(ended)) {
        for (int j = 0; j < LANES; j++) {
            if (!ended[j]) continue;
            long long i = L.idx[j];
            first[i] = L.hit[j];
            dmin[i] = sqrt(L.best[j]);
            nsteps[i] = L.step[j];
            finite[i] = fin[j] != 0;
            CAT(load, NAME)(&L, j, next < n ? next : -1, lights, w);
            if (next < n) next++;
            fresh[j] = -1;
        }
    }
    /* advance (kernel.py's advance) every lane; lanes loaded in this pass or resting keep their state */
    V w1 = L.w1, w2 = L.w2;
    V e1x = dx + c * l1x - s * l1y;
    V e1y = dy + s * l1x + c * l1y;
    V e2x = dx + c * l2x - s * l2y;
    V e2y = dy + s * l2x + c * l2y;
    V d1 = e1x * e1x + e1y * e1y + dz2;
    V dd2 = e2x * e2x + e2y * e2y + dz2;
    V inv = 1.0 / (d1 * dd2);
    VI run = L.live & ~fresh;
    const int idle = ANY(~run); /* some lane rests or was loaded in this pass: its results are unused */
    V arg_r = w1 * dd2 * inv, arg_l = w2 * d1 * inv;
    if (idle) { /* a harmless argument there (a resting lane's state may be anything) */
        arg_r = SEL(run, arg_r, S(0.5));
        arg_l = SEL(run, arg_l, S(0.5));
    }
    V t_right = vmax * TANHV(arg_r, mode);
    V t_left = vmax * TANHV(arg_l, mode);
    V om2 = q2 * q2;
    V f0 = g[0] * q0 + g[1] * q1 + g[2] * q2 + g[3] * q3 + g[4] * q4 + g[5] * q5 + om2 * cen[0];
    V f1 = g[6] * q0 + g[7] * q1 + g[8] * q2 + g[9] * q3 + g[10] * q4 + g[11] * q5 + om2 * cen[1];
    V f2 = g[12] * q0 + g[13] * q1 + g[14] * q2 + g[15] * q3 + g[16] * q4 + g[17] * q5 + om2 * cen[2];
    V f3 = g[18] * q0 + g[19] * q1 + g[20] * q2 + g[21] * q3 + g[22] * q4 + g[23] * q5 + om2 * cen[3];
    V f4 = g[24] * q0 + g[25] * q1 + g[26] * q2 + g[27] * q3 + g[28] * q4 + g[29] * q5 + om2 * cen[4];
    V f5 = g[30] * q0 + g[31] * q1 + g[32] * q2 + g[33] * q3 + g[34] * q4 + g[35] * q5 + om2 * cen[5];
    V la, lb;
    CAT(motorsv, NAME)(k->kk, t_left - f3, t_right - f4, tmax, run, &la, &lb);
    q0 = f0 + hm[0] * la + hm[1] * lb;
    q1 = f1 + hm[2] * la + hm[3] * lb;
    q2 = f2 + hm[4] * la + hm[5] * lb;
    q3 = f3 + hm[6] * la + hm[7] * lb;
    q4 = f4 + hm[8] * la + hm[9] * lb;
    q5 = f5 + hm[10] * la + hm[11] * lb;
    x += dt * (c * q0 - s * q1);
    y += dt * (s * q0 + c * q1);
    V t = hdt * q2;
    V nn = 1.0 / (1.0 + t * t);
    V cr = (1.0 - t * t) * nn;
    V sr = 2.0 * t * nn;
    V cn = c * cr - s * sr;
    s = s * cr + c * sr;
    c = cn;
    V q0n = cr * q0 + sr * q1;
    q1 = cr * q1 - sr * q0;
    q0 = q0n;
    if (idle) { /* lanes loaded in this pass or resting keep their state */
        x = SEL(run, x, L.x), y = SEL(run, y, L.y), c = SEL(run, c, L.c), s = SEL(run, s, L.s);
        q0 = SEL(run, q0, L.q0), q1 = SEL(run, q1, L.q1), q2 = SEL(run, q2, L.q2);
        q3 = SEL(run, q3, L.q3), q4 = SEL(run, q4, L.q4), q5 = SEL(run, q5, L.q5);
    }
    L.x = x, L.y = y, L.c = c, L.s = s, L.q0 = q0, L.q1 = q1, L.q2 = q2, L.q3 = q3, L.q4 = q4, L.q5 = q5;
    L.step += one & run;
    /* the horizon: an episode that ran every step ends finite, as the scalar loop's exit */
    VI done = run & (L.step == steps);
    if (ANY(done)) {
        for (int j = 0; j < LANES; j++) {
            if (!done[j]) continue;
            long long i = L.idx[j];
            first[i] = L.hit[j];
            dmin[i] = sqrt(L.best[j]);
            nsteps[i] = steps;
            finite[i] = 1;
            CAT(load, NAME)(&L, j, next < n ? next : -1, lights, w);
            if (next < n) next++;
        }
    }
#undef L
    *nextp = next;
}

/* episodes i = 0..n-1 (kernel.py's episode without a path) in GROUPS groups of eight lanes (their
 * dependency chains overlap on the core), each lane refilled with the next episode when its own
 * ends; a refilled lane skips the step of the pass it was loaded in and starts with the next pass's
 * checks (its step 0), as the scalar loop does */
static void NAME(const Consts *k, Py_ssize_t n, const double *lights, const double *w, int stop, int mode,
                 long long *first, double *dmin, long long *nsteps, unsigned char *finite) {
    Lanes L[GROUPS];
    Py_ssize_t next = 0;
    const double dt = k->dt, radius = k->radius;
    const CAT(KV, NAME) kv = {S(dt),           S(k->vmax),     S(k->dz2),      S(radius * radius), S(0.5 * dt),
                              S(k->sen[0]), S(k->sen[1]), S(k->sen[2]), S(k->sen[3])};
    if (k->steps <= 0) { /* the scalar loop runs no step */
        for (Py_ssize_t i = 0; i < n; i++) first[i] = -1, dmin[i] = INFINITY, nsteps[i] = 0, finite[i] = 1;
        return;
    }
    for (int q = 0; q < GROUPS; q++)
        for (int j = 0; j < LANES; j++) {
            CAT(load, NAME)(&L[q], j, next < n ? next : -1, lights, w);
            if (next < n) next++;
        }
    for (;;) {
        VI live = L[0].live;
        for (int q = 1; q < GROUPS; q++) live |= L[q].live;
        if (!ANY(live)) break;
#pragma GCC unroll 4
        for (int q = 0; q < GROUPS; q++)
            CAT(pass, NAME)(&L[q], k, &kv, n, &next, lights, w, stop, mode, first, dmin, nsteps, finite);
    }
}

#undef SEL
#undef ANY
#undef S
#undef EXPM1V
#undef TANHV
#ifdef FMA
#undef FMA
#undef FNMA
#undef FMS
#endif
