/* What one of the small models of this folder gives the FMI layer (fmi.c), which makes it an
 * FMI 2.0 or 3.0 Co-Simulation FMU. A model's variables are doubles, indexed by
 * value reference; value reference 0 is time, kept by the layer. A model moves its
 * variables on by itself over each communication step, handling its events inside the step
 * (so nothing of Model Exchange is offered). */

#ifndef MODEL_H
#define MODEL_H

#include <stddef.h>

typedef enum {
    REAL,    /* fmi2Real, fmi3Float64 */
    INTEGER, /* fmi2Integer, fmi3Int32 */
} Kind;

/* Every variable but time has initial="exact": the importer may set it before the
 * initialization ends, and not after. */
typedef struct {
    Kind kind;
    double start;
} Variable;

/* The GUID (FMI 2.0), the instantiation token (FMI 3.0): the model descriptions' */
extern const char model_token[];
/* By value reference: model_variables[0] is time */
extern const Variable model_variables[];
extern const size_t model_variable_count;

/* At the end of the initialization: NULL, or why the values in v (which the importer may
 * have set) are refused. */
const char *model_initialize(double v[]);

/* Moves v on from *t to `end`, leaving *t where it stopped: `end`, or where the model ends
 * the simulation, which it says by returning 1. */
int model_advance(double v[], double *t, double end);

#endif
