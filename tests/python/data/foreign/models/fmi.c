/* The FMI Co-Simulation functions of a model of this folder (model.h), for FMI 2.0 or 3.0 as
 * FMI_VERSION says: gcc -shared -DFMI_VERSION=2 Model.c fmi.c. Instantiation checks the GUID
 * (the instantiation token), variables are set before the initialization ends, and each step
 * is the model's. A model that ends the simulation ends the step there: in FMI 2.0 the step
 * is fmi2Discard, with fmi2Terminated true and that time as fmi2LastSuccessfulTime (FMI 2.0.5
 * §4.2.2, §4.2.3); in FMI 3.0, fmi3DoStep's terminateSimulation and lastSuccessfulTime say so
 * (FMI 3.0 §4.2.1). Nothing else is offered: no FMU states, no derivatives, no event mode. */

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

#if FMI_VERSION == 2
#include "fmi2Functions.h"
typedef fmi2ValueReference Reference;
typedef fmi2CallbackLogger Logger;
#elif FMI_VERSION == 3
#include "fmi3Functions.h"
typedef fmi3ValueReference Reference;
typedef fmi3LogMessageCallback Logger;
#else
#error "compile with -DFMI_VERSION=2 or -DFMI_VERSION=3"
#endif

/* The statuses the two versions share, by their common values (fmi2OK = fmi3OK = 0, ...) */
enum { OK = 0, DISCARD = 2, ERROR = 3 };

typedef struct {
    char *name;
    void *environment; /* the importer's, given back to its logger */
    double time;
    int initialized; /* the initialization has ended */
    int ended;       /* the model has ended the simulation */
    Logger logger;
    double v[]; /* by value reference; v[0] is unused, time is `time` */
} Fmu;

static void complain(Fmu *fmu, const char *message) {
    if (!fmu->logger) return;
#if FMI_VERSION == 2
    fmu->logger(fmu->environment, fmu->name, fmi2Error, "logStatusError", "%s", message);
#else
    fmu->logger(fmu->environment, fmi3Error, "logStatusError", message);
#endif
}

static void start(Fmu *fmu) {
    for (size_t vr = 0; vr < model_variable_count; vr++) fmu->v[vr] = model_variables[vr].start;
    fmu->time = 0;
    fmu->initialized = fmu->ended = 0;
}

static Fmu *instantiate(const char *name, const char *token, Logger logger, void *environment) {
    if (!name || !token || strcmp(token, model_token) != 0) return NULL;
    Fmu *fmu = calloc(1, sizeof(Fmu) + model_variable_count * sizeof(double));
    if (!fmu || !(fmu->name = malloc(strlen(name) + 1))) {
        free(fmu);
        return NULL;
    }
    strcpy(fmu->name, name);
    fmu->logger = logger;
    fmu->environment = environment;
    start(fmu);
    return fmu;
}

static void free_instance(Fmu *fmu) {
    if (!fmu) return;
    free(fmu->name);
    free(fmu);
}

static int exists(const Fmu *fmu) { return fmu ? OK : ERROR; }

static int start_at(Fmu *fmu, double time) {
    if (!fmu) return ERROR;
    fmu->time = time;
    return OK;
}

static int reset(Fmu *fmu) {
    if (!fmu) return ERROR;
    start(fmu);
    return OK;
}

static int end_initialization(Fmu *fmu) {
    if (!fmu) return ERROR;
    const char *refused = model_initialize(fmu->v);
    if (refused) {
        complain(fmu, refused);
        return ERROR;
    }
    fmu->initialized = 1;
    return OK;
}

/* whether `n` values of `kind` can be read from (or written to) `vr` */
static int can_access(Fmu *fmu, const Reference vr[], size_t n, const void *values, Kind kind, int writing) {
    if (!fmu || (n && (!vr || !values))) return 0;
    for (size_t k = 0; k < n; k++) {
        if (vr[k] >= model_variable_count || model_variables[vr[k]].kind != kind) return 0;
        if (writing && (vr[k] == 0 || fmu->initialized)) {
            complain(fmu, "a variable can be set only before the initialization ends, and time not at all");
            return 0;
        }
    }
    return 1;
}

static double value_of(const Fmu *fmu, Reference vr) { return vr == 0 ? fmu->time : fmu->v[vr]; }

/* A getter and a setter of the variables of one kind: their bodies, the same in both versions */
#define GET(kind)                                                                                   \
    {                                                                                               \
        if (!can_access(c, vr, n, value, kind, 0)) return ERROR;                                    \
        for (size_t k = 0; k < n; k++) value[k] = value_of(c, vr[k]);                               \
        return OK;                                                                                  \
    }
#define SET(kind)                                                                                   \
    {                                                                                               \
        if (!can_access(c, vr, n, value, kind, 1)) return ERROR;                                    \
        for (size_t k = 0; k < n; k++) ((Fmu *)c)->v[vr[k]] = value[k];                             \
        return OK;                                                                                  \
    }
/* ... and of a type no variable has: only an empty request succeeds */
#define NONE { (void)vr, (void)value; return c && n == 0 ? OK : ERROR; }

/* The functions of the two versions that differ only in their prefix and types */
#define LIFECYCLE(prefix, Status, Instance)                                                           \
    void prefix##FreeInstance(Instance c) { free_instance(c); }                                        \
    Status prefix##ExitInitializationMode(Instance c) { return end_initialization(c); }                \
    Status prefix##Terminate(Instance c) { return exists(c); }                                         \
    Status prefix##Reset(Instance c) { return reset(c); }

static int step(Fmu *fmu, double t, double h) {
    if (!fmu || !fmu->initialized || fmu->ended || !(h >= 0) || fabs(t - fmu->time) > 1e-9 * (1 + fabs(t))) {
        if (fmu) complain(fmu, "a step before the initialization ended, after the model ended the simulation, "
                               "or not from the time reached");
        return ERROR;
    }
    fmu->ended = model_advance(fmu->v, &fmu->time, t + h);
    return fmu->ended ? DISCARD : OK;
}

#if FMI_VERSION == 2

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String categories[]) {
    (void)on, (void)n, (void)categories;
    return exists(c);
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)resources, (void)visible, (void)loggingOn;
    if (type != fmi2CoSimulation || !callbacks) return NULL;
    return instantiate(name, guid, callbacks->logger, callbacks->componentEnvironment);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
    return start_at(c, startTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return exists(c); }
LIFECYCLE(fmi2, fmi2Status, fmi2Component)

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) GET(REAL)
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer value[])
    GET(INTEGER)
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[])
    SET(REAL)
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer value[])
    SET(INTEGER)
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean value[]) NONE
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String value[]) NONE
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean value[])
    NONE
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String value[])
    NONE

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    return step(c, t, h);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value) {
    if (!c || !value || kind != fmi2LastSuccessfulTime) return fmi2Error;
    *value = ((Fmu *)c)->time;
    return fmi2OK;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value) {
    if (!c || !value || kind != fmi2Terminated) return fmi2Error;
    *value = ((Fmu *)c)->ended ? fmi2True : fmi2False;
    return fmi2OK;
}

/* What the model description does not claim is refused. */
#define REFUSED(function, ...) fmi2Status function(fmi2Component c, __VA_ARGS__) { (void)c; return fmi2Error; }
REFUSED(fmi2GetFMUstate, fmi2FMUstate *state)
REFUSED(fmi2SetFMUstate, fmi2FMUstate state)
REFUSED(fmi2FreeFMUstate, fmi2FMUstate *state)
REFUSED(fmi2SerializedFMUstateSize, fmi2FMUstate state, size_t *size)
REFUSED(fmi2SerializeFMUstate, fmi2FMUstate state, fmi2Byte bytes[], size_t size)
REFUSED(fmi2DeSerializeFMUstate, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state)
REFUSED(fmi2GetDirectionalDerivative, const fmi2ValueReference unknowns[], size_t nUnknowns,
        const fmi2ValueReference knowns[], size_t nKnowns, const fmi2Real seed[], fmi2Real sensitivity[])
REFUSED(fmi2SetRealInputDerivatives, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
        const fmi2Real value[])
REFUSED(fmi2GetRealOutputDerivatives, const fmi2ValueReference vr[], size_t n, const fmi2Integer order[],
        fmi2Real value[])
REFUSED(fmi2GetStatus, const fmi2StatusKind kind, fmi2Status *value)
REFUSED(fmi2GetIntegerStatus, const fmi2StatusKind kind, fmi2Integer *value)
REFUSED(fmi2GetStringStatus, const fmi2StatusKind kind, fmi2String *value)
fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }

#else /* FMI 3.0 */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n, const fmi3String categories[]) {
    (void)on, (void)n, (void)categories;
    return exists(c);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
                                         fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
                                         fmi3Boolean earlyReturnAllowed, const fmi3ValueReference intermediate[],
                                         size_t nIntermediate, fmi3InstanceEnvironment environment,
                                         fmi3LogMessageCallback logger, fmi3IntermediateUpdateCallback update) {
    (void)resources, (void)visible, (void)loggingOn, (void)earlyReturnAllowed, (void)intermediate;
    (void)nIntermediate, (void)update;
    if (eventModeUsed) return NULL; /* the model description says it has no event mode */
    return instantiate(name, token, logger, environment);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
    return start_at(c, startTime);
}

LIFECYCLE(fmi3, fmi3Status, fmi3Instance)

#define ACCESSORS(Type, body_get, body_set)                                                              \
    fmi3Status fmi3Get##Type(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3##Type value[],   \
                             size_t nValues) { (void)nValues; body_get }                                  \
    fmi3Status fmi3Set##Type(fmi3Instance c, const fmi3ValueReference vr[], size_t n,                       \
                             const fmi3##Type value[], size_t nValues) { (void)nValues; body_set }
ACCESSORS(Float64, GET(REAL), SET(REAL))
ACCESSORS(Int32, GET(INTEGER), SET(INTEGER))
ACCESSORS(Float32, NONE, NONE)
ACCESSORS(Int8, NONE, NONE)
ACCESSORS(UInt8, NONE, NONE)
ACCESSORS(Int16, NONE, NONE)
ACCESSORS(UInt16, NONE, NONE)
ACCESSORS(UInt32, NONE, NONE)
ACCESSORS(Int64, NONE, NONE)
ACCESSORS(UInt64, NONE, NONE)
ACCESSORS(Boolean, NONE, NONE)
ACCESSORS(String, NONE, NONE)

fmi3Status fmi3GetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t n, size_t sizes[], fmi3Binary value[],
                         size_t nValues) { (void)sizes, (void)nValues; NONE }
fmi3Status fmi3SetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const size_t sizes[],
                         const fmi3Binary value[], size_t nValues) { (void)sizes, (void)nValues; NONE }
fmi3Status fmi3GetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3Clock value[]) NONE
fmi3Status fmi3SetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Clock value[]) NONE

fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime) {
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime) return fmi3Error;
    int status = step(c, t, h);
    if (status == ERROR) return fmi3Error;
    *eventHandlingNeeded = *earlyReturn = fmi3False;
    *terminateSimulation = status == DISCARD;
    *lastSuccessfulTime = ((Fmu *)c)->time;
    return fmi3OK;
}

/* Nothing else is offered: Model Exchange and Scheduled Execution do not instantiate, and
 * what the model description does not claim is refused. */
fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
                                          fmi3Boolean loggingOn, fmi3InstanceEnvironment environment,
                                          fmi3LogMessageCallback logger) {
    (void)name, (void)token, (void)resources, (void)visible, (void)loggingOn, (void)environment, (void)logger;
    return NULL;
}
fmi3Instance fmi3InstantiateScheduledExecution(fmi3String name, fmi3String token, fmi3String resources,
                                               fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment environment, fmi3LogMessageCallback logger,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)name, (void)token, (void)resources, (void)visible, (void)loggingOn, (void)environment, (void)logger;
    (void)clockUpdate, (void)lockPreemption, (void)unlockPreemption;
    return NULL;
}

#define REFUSED(function, ...) fmi3Status function(fmi3Instance c, __VA_ARGS__) { (void)c; return fmi3Error; }
#define REFUSED_ALONE(function) fmi3Status function(fmi3Instance c) { (void)c; return fmi3Error; }
REFUSED_ALONE(fmi3EnterEventMode)
REFUSED_ALONE(fmi3EnterStepMode)
REFUSED_ALONE(fmi3EnterConfigurationMode)
REFUSED_ALONE(fmi3ExitConfigurationMode)
REFUSED_ALONE(fmi3EvaluateDiscreteStates)
REFUSED_ALONE(fmi3EnterContinuousTimeMode)
REFUSED(fmi3UpdateDiscreteStates, fmi3Boolean *needUpdate, fmi3Boolean *terminate, fmi3Boolean *nominalsChanged,
        fmi3Boolean *valuesChanged, fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime)
REFUSED(fmi3GetNumberOfVariableDependencies, fmi3ValueReference vr, size_t *n)
REFUSED(fmi3GetVariableDependencies, fmi3ValueReference dependent, size_t elementsOfDependent[],
        fmi3ValueReference independents[], size_t elementsOfIndependents[], fmi3DependencyKind kinds[], size_t n)
REFUSED(fmi3GetFMUState, fmi3FMUState *state)
REFUSED(fmi3SetFMUState, fmi3FMUState state)
REFUSED(fmi3FreeFMUState, fmi3FMUState *state)
REFUSED(fmi3SerializedFMUStateSize, fmi3FMUState state, size_t *size)
REFUSED(fmi3SerializeFMUState, fmi3FMUState state, fmi3Byte bytes[], size_t size)
REFUSED(fmi3DeserializeFMUState, const fmi3Byte bytes[], size_t size, fmi3FMUState *state)
REFUSED(fmi3GetDirectionalDerivative, const fmi3ValueReference unknowns[], size_t nUnknowns,
        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
        fmi3Float64 sensitivity[], size_t nSensitivity)
REFUSED(fmi3GetAdjointDerivative, const fmi3ValueReference unknowns[], size_t nUnknowns,
        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
        fmi3Float64 sensitivity[], size_t nSensitivity)
REFUSED(fmi3GetIntervalDecimal, const fmi3ValueReference vr[], size_t n, fmi3Float64 intervals[],
        fmi3IntervalQualifier qualifiers[])
REFUSED(fmi3GetIntervalFraction, const fmi3ValueReference vr[], size_t n, fmi3UInt64 counters[],
        fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
REFUSED(fmi3GetShiftDecimal, const fmi3ValueReference vr[], size_t n, fmi3Float64 shifts[])
REFUSED(fmi3GetShiftFraction, const fmi3ValueReference vr[], size_t n, fmi3UInt64 counters[],
        fmi3UInt64 resolutions[])
REFUSED(fmi3SetIntervalDecimal, const fmi3ValueReference vr[], size_t n, const fmi3Float64 intervals[])
REFUSED(fmi3SetIntervalFraction, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 counters[],
        const fmi3UInt64 resolutions[])
REFUSED(fmi3SetShiftDecimal, const fmi3ValueReference vr[], size_t n, const fmi3Float64 shifts[])
REFUSED(fmi3SetShiftFraction, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 counters[],
        const fmi3UInt64 resolutions[])
REFUSED(fmi3CompletedIntegratorStep, fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *enterEventMode,
        fmi3Boolean *terminate)
REFUSED(fmi3SetTime, fmi3Float64 time)
REFUSED(fmi3SetContinuousStates, const fmi3Float64 states[], size_t n)
REFUSED(fmi3GetContinuousStateDerivatives, fmi3Float64 derivatives[], size_t n)
REFUSED(fmi3GetEventIndicators, fmi3Float64 indicators[], size_t n)
REFUSED(fmi3GetContinuousStates, fmi3Float64 states[], size_t n)
REFUSED(fmi3GetNominalsOfContinuousStates, fmi3Float64 nominals[], size_t n)
REFUSED(fmi3GetNumberOfEventIndicators, size_t *n)
REFUSED(fmi3GetNumberOfContinuousStates, size_t *n)
REFUSED(fmi3GetOutputDerivatives, const fmi3ValueReference vr[], size_t n, const fmi3Int32 orders[],
        fmi3Float64 values[], size_t nValues)
REFUSED(fmi3ActivateModelPartition, fmi3ValueReference clock, fmi3Float64 activationTime)

#endif
