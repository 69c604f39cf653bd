/* Decay: x' = -k x, x(0) = 1, solved exactly over each step: x(t + h) = x(t) e^(-k h).
 * Continuous, with no event: the plainest model of this folder. */

#include <math.h>

#include "model.h"

enum { TIME, X, K };

const char model_token[] = "{8d1f0b52-3c7e-4a0e-9b61-2f4c6d7e8a01}";
const Variable model_variables[] = {
    [TIME] = {REAL, 0},
    [X] = {REAL, 1},
    [K] = {REAL, 1},
};
const size_t model_variable_count = sizeof model_variables / sizeof model_variables[0];

const char *model_initialize(double v[]) { return isfinite(v[K]) ? NULL : "k must be finite"; }

int model_advance(double v[], double *t, double end) {
    v[X] *= exp(-v[K] * (end - *t));
    *t = end;
    return 0;
}
