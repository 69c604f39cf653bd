/*
 * The yardstick of `mechfmu bench`: the Oscillator's communication step written plainly in
 * C, as a hand-coded FMU would do it. An adaptive Dormand-Prince 5(4) with the error norm
 * and step-size control of Hairer's DOPRI5 (dopri5.f: the RMS of err_i / (atol + rtol
 * max(|y_i|, |y_new_i|)), the PI controller with BETA 0.04, SAFE 0.9, FAC1 0.2, FAC2 10, two
 * calls of pow per step, no growth after a rejection), first same as last, landing on the
 * communication point by shortening the last step, atol = rtol = the tolerance, as the
 * FMUs use it.
 *
 *   m x'' + c x' + k x = F + F0 sin(omega t)
 */
#include <math.h>
#include <stdint.h>

typedef struct {
    double m, c, k, F0, omega, F;
    double t, y[2], k1[2]; /* k1: f(t, y), kept from the last stage (FSAL) */
    double h;              /* the proposed step size, 0 before the first step */
    double facold;         /* the previous accepted error norm, floored at 1e-4 */
    double tol;
    uint64_t evaluations, accepted, rejected;
} CStepOscillator;

static void rhs(CStepOscillator *s, double t, const double y[2], double dy[2]) {
    double harmonic = s->F0 == 0.0 ? 0.0 : s->F0 * sin(s->omega * t);
    dy[0] = y[1];
    dy[1] = (s->F + harmonic - s->c * y[1] - s->k * y[0]) / s->m;
    s->evaluations++;
}

/* The Oscillator at its start values, with tolerance `tol`. */
void mechfmu_c_oscillator_start(CStepOscillator *s, double tol) {
    s->m = 1.0; s->c = 0.4; s->k = 4.0; s->F0 = 0.0; s->omega = 1.0; s->F = 0.0;
    s->t = 0.0; s->y[0] = 1.0; s->y[1] = 0.0;
    s->h = 0.0; s->facold = 1e-4; s->tol = tol;
    s->evaluations = s->accepted = s->rejected = 0;
    rhs(s, s->t, s->y, s->k1);
}

/* Advances to `t_end` (> t); returns 0, or -1 when the step size falls below the
 * smallest that still moves t. */
int mechfmu_c_oscillator_advance(CStepOscillator *s, double t_end) {
    static const double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
    static const double a21 = 1.0 / 5;
    static const double a31 = 3.0 / 40, a32 = 9.0 / 40;
    static const double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
    static const double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                        a54 = -212.0 / 729;
    static const double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247,
                        a64 = 49.0 / 176, a65 = -5103.0 / 18656;
    static const double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192,
                        a75 = -2187.0 / 6784, a76 = 11.0 / 84;
    static const double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920,
                        e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;
    const double beta = 0.04, expo1 = 0.2 - beta * 0.75, safe = 0.9;
    const double facc1 = 1.0 / 0.2, facc2 = 1.0 / 10.0;
    const double atol = s->tol, rtol = s->tol;
    double h = s->h > 0.0 ? s->h : fmin(0.01 * (t_end - s->t), 1e-3); /* a first guess */
    int reject = 0;
    for (;;) {
        int last = 0;
        double proposed = h;
        if (s->t + 1.01 * h >= t_end) {
            h = t_end - s->t;
            last = 1;
        }
        if (h <= 16.0 * 2.220446049250313e-16 * fmax(fabs(s->t), 1.0) && !last)
            return -1;
        const double *y = s->y, *k1 = s->k1;
        double y1[2], k2[2], k3[2], k4[2], k5[2], k6[2], k7[2], ysti[2];
        for (int i = 0; i < 2; i++) y1[i] = y[i] + h * a21 * k1[i];
        rhs(s, s->t + c2 * h, y1, k2);
        for (int i = 0; i < 2; i++) y1[i] = y[i] + h * (a31 * k1[i] + a32 * k2[i]);
        rhs(s, s->t + c3 * h, y1, k3);
        for (int i = 0; i < 2; i++) y1[i] = y[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
        rhs(s, s->t + c4 * h, y1, k4);
        for (int i = 0; i < 2; i++)
            y1[i] = y[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        rhs(s, s->t + c5 * h, y1, k5);
        for (int i = 0; i < 2; i++)
            ysti[i] = y[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        double t_new = last ? t_end : s->t + h;
        rhs(s, t_new, ysti, k6);
        for (int i = 0; i < 2; i++)
            y1[i] = y[i] + h * (a71 * k1[i] + a73 * k3[i] + a74 * k4[i] + a75 * k5[i] + a76 * k6[i]);
        rhs(s, t_new, y1, k7);
        double err = 0.0;
        for (int i = 0; i < 2; i++) {
            double e = h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
            double sk = atol + rtol * fmax(fabs(y[i]), fabs(y1[i]));
            err += (e / sk) * (e / sk);
        }
        err = sqrt(err / 2.0);
        double fac11 = pow(err, expo1);
        double fac = fac11 / pow(s->facold, beta);
        fac = fmax(facc2, fmin(facc1, fac / safe));
        double hnew = h / fac;
        if (err <= 1.0) {
            s->facold = fmax(err, 1e-4);
            s->accepted++;
            if (reject) hnew = fmin(hnew, h);
            reject = 0;
            s->y[0] = y1[0]; s->y[1] = y1[1];
            s->k1[0] = k7[0]; s->k1[1] = k7[1];
            s->t = t_new;
            if (last) {
                /* a step shortened to land, not by its error, keeps the longer proposal */
                s->h = hnew >= h ? fmax(hnew, proposed) : hnew;
                return 0;
            }
            s->h = hnew;
            h = hnew;
        } else {
            hnew = h / fmin(facc1, fac11 / safe);
            reject = 1;
            s->rejected++;
            h = hnew;
        }
    }
}

/* x after the last step: what an importer's fmi2GetReal of the output would read. */
double mechfmu_c_oscillator_x(const CStepOscillator *s) { return s->y[0]; }
