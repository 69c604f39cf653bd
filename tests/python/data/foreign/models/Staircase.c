/* Staircase: an Integer counter of the seconds, 1 at t = 0, up by one at each whole second
 * (a time event), which ends the simulation when it reaches TOP, at t = 9, before the stop
 * time of its default experiment (10 s). The next event is at t = counter. */

#include "model.h"

enum { TIME, COUNTER };

#define TOP 10

const char model_token[] = "{8d1f0b52-3c7e-4a0e-9b61-2f4c6d7e8a03}";
const Variable model_variables[] = {
    [TIME] = {REAL, 0},
    [COUNTER] = {INTEGER, 1},
};
const size_t model_variable_count = sizeof model_variables / sizeof model_variables[0];

const char *model_initialize(double v[]) { return v[COUNTER] >= 1 && v[COUNTER] < TOP ? NULL : "counter must be within [1, 9]"; }

int model_advance(double v[], double *t, double end) {
    /* an event at the end of the step, to round-off, is the step's */
    for (double next = v[COUNTER]; next <= end + 1e-9 * (1 + end); next = v[COUNTER]) {
        *t = next;
        if (++v[COUNTER] >= TOP) return 1;
    }
    *t = end;
    return 0;
}
