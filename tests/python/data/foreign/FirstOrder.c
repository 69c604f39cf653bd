/* FirstOrder: a first-order lag and its integral, an FMI 2.0 Co-Simulation FMU written by
 * hand (not by mechfmu), the foreign FMU of tests/python/test_validate_foreign.py.
 *
 *     tau y' = u - y,   z' = y,   y(0) = y0,   z(0) = 0
 *
 * Over a communication step the input u is constant, so each step is the exact solution:
 *
 *     y(t + h) = u + (y - u) e^(-h/tau)
 *     z(t + h) = z + u h + (y - u) tau (1 - e^(-h/tau))
 *
 * Built with gcc at test time. Compile-time switches make the variants the tests need:
 *   -DREFUSE_INSTANTIATE   fmi2Instantiate returns NULL
 *   -DFAIL_AT=2.0          fmi2DoStep fails (fmi2Error) from t = 2.0 on
 *   -DCRASH_IF_NEGATIVE_Y0 fmi2DoStep writes through a NULL pointer when y0 < 0 (an FMU that
 *                          crashes its importer's process, for the sweep's native runner)
 *   -DCRASH_AT=1.0         fmi2DoStep writes through a NULL pointer from t = 1.0 on
 *   -DHANG_AT=1.0          fmi2DoStep never returns from t = 1.0 on
 *   -DTALK                 fmi2ExitInitializationMode writes a line to the process's standard
 *                          error, as many FMUs do (not through the logger)
 *   -DANY_GUID             fmi2Instantiate accepts any GUID (the standard does not require
 *                          the check)
 *   -DOWN_SOLVER           a solver of its own: RK4 substeps of tau * tol^(1/4) at most, tol
 *                          the tolerance of fmi2SetupExperiment or, when none is given, its
 *                          own default 1e-2 (so that its results depend on the tolerance, as
 *                          a Dymola FMU's with CVODE do)
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define GUID "{5f1c1e9a-6b1e-4c55-9d0e-0f1257041a01}"

enum { VR_U, VR_Y, VR_Z, VR_TAU, VR_Y0, N_VR };

typedef struct {
    fmi2CallbackFunctions callbacks;
    fmi2String name;
    double time;
    double tolerance;
    double v[N_VR];
} Instance;

/* the tolerance OWN_SOLVER integrates at when fmi2SetupExperiment gives none */
#define DEFAULT_TOLERANCE 1e-2

static void say(Instance *c, fmi2Status status, const char *message) {
    if (c->callbacks.logger) c->callbacks.logger(c->callbacks.componentEnvironment, c->name, status, "logError", "%s", message);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String categories[]) {
    (void)c; (void)on; (void)n; (void)categories;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)resources; (void)visible; (void)loggingOn;
#ifdef REFUSE_INSTANTIATE
    (void)name; (void)type; (void)guid; (void)callbacks;
    return NULL;
#else
#ifdef ANY_GUID
    if (!guid) return NULL;
#else
    if (!guid || strcmp(guid, GUID) != 0) return NULL;
#endif
    if (type != fmi2CoSimulation || !name || !callbacks) return NULL;
    Instance *c = calloc(1, sizeof(Instance));
    if (!c) return NULL;
    c->callbacks = *callbacks;
    c->name = name;
    c->v[VR_TAU] = 0.5;
    c->v[VR_Y0] = 1.0;
    return c;
#endif
}

void fmi2FreeInstance(fmi2Component c) { free(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol, fmi2Real start,
                               fmi2Boolean stopDefined, fmi2Real stop) {
    (void)stopDefined; (void)stop;
    ((Instance *)c)->time = start;
    ((Instance *)c)->tolerance = tolDefined && tol > 0 ? tol : DEFAULT_TOLERANCE;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *i = c;
    if (!(i->v[VR_TAU] > 0)) {
        say(i, fmi2Error, "tau must be > 0");
        return fmi2Error;
    }
    i->v[VR_Y] = i->v[VR_Y0];
    i->v[VR_Z] = 0;
#ifdef TALK
    fprintf(stderr, "FirstOrder on stderr: initialized with y0 = %g\n", i->v[VR_Y0]);
#endif
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *i = c;
    memset(i->v, 0, sizeof i->v);
    i->v[VR_TAU] = 0.5;
    i->v[VR_Y0] = 1.0;
    i->time = 0;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
    Instance *i = c;
    for (size_t k = 0; k < n; k++) {
        if (vr[k] >= N_VR) return fmi2Error;
        value[k] = i->v[vr[k]];
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
    Instance *i = c;
    for (size_t k = 0; k < n; k++) {
        if (vr[k] >= N_VR || vr[k] == VR_Y || vr[k] == VR_Z) return fmi2Error;
        i->v[vr[k]] = value[k];
    }
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *i = c;
    (void)noSetFMUStatePriorToCurrentPoint;
#ifdef FAIL_AT
    if (t + h > FAIL_AT) {
        say(i, fmi2Error, "FirstOrder was built to fail here (FAIL_AT)");
        return fmi2Error;
    }
#endif
#ifdef CRASH_IF_NEGATIVE_Y0
    if (i->v[VR_Y0] < 0) {
        volatile int *nowhere = NULL;
        *nowhere = 1;
    }
#endif
#ifdef CRASH_AT
    if (t + h > CRASH_AT) {
        volatile int *nowhere = NULL;
        *nowhere = 1;
    }
#endif
#ifdef HANG_AT
    for (volatile int forever = 1; forever && t + h > HANG_AT;) {
    }
#endif
    double u = i->v[VR_U], y = i->v[VR_Y], tau = i->v[VR_TAU];
#ifdef OWN_SOLVER
    /* RK4 on (y, z)' = ((u - y) / tau, y): exact for z given y, so only y's error matters */
    int n = (int)ceil(h / (tau * pow(i->tolerance, 0.25)));
    double dt = h / n, z = i->v[VR_Z];
    for (int k = 0; k < n; k++) {
        double k1 = (u - y) / tau, k2 = (u - (y + dt / 2 * k1)) / tau, k3 = (u - (y + dt / 2 * k2)) / tau,
               k4 = (u - (y + dt * k3)) / tau;
        double y_next = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        z += dt / 6 * (y + 2 * (y + dt / 2 * k1) + 2 * (y + dt / 2 * k2) + (y + dt * k3));
        y = y_next;
    }
    i->v[VR_Z] = z;
    i->v[VR_Y] = y;
#else
    double decay = exp(-h / tau);
    i->v[VR_Z] += u * h + (y - u) * tau * (1 - decay);
    i->v[VR_Y] = u + (y - u) * decay;
#endif
    i->time = t + h;
    return fmi2OK;
}

/* What this FMU does not offer refuses, as the standard allows. */
#define REFUSE(c) do { (void)(c); return fmi2Error; } while (0)

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) { (void)vr; (void)v; if (n == 0) return fmi2OK; REFUSE(c); }
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)s; REFUSE(c); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { (void)s; REFUSE(c); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)s; REFUSE(c); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n) { (void)s; (void)n; REFUSE(c); }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) { (void)s; (void)b; (void)n; REFUSE(c); }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s) { (void)b; (void)n; (void)s; REFUSE(c); }
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu, const fmi2ValueReference z[],
                                        size_t nz, const fmi2Real du[], fmi2Real dz[]) { (void)u; (void)nu; (void)z; (void)nz; (void)du; (void)dz; REFUSE(c); }
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
                                       const fmi2Real value[]) { (void)vr; (void)n; (void)order; (void)value; REFUSE(c); }
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
                                        fmi2Real value[]) { (void)vr; (void)n; (void)order; (void)value; REFUSE(c); }
fmi2Status fmi2CancelStep(fmi2Component c) { REFUSE(c); }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) { (void)k; (void)v; REFUSE(c); }
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    if (k != fmi2LastSuccessfulTime) REFUSE(c);
    *v = ((Instance *)c)->time;
    return fmi2OK;
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v) { (void)k; (void)v; REFUSE(c); }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    if (k != fmi2Terminated) REFUSE(c);
    *v = fmi2False;
    return fmi2OK;
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v) { (void)k; (void)v; REFUSE(c); }
