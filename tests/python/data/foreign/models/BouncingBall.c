/* BouncingBall: a ball dropped from h = 1 m falls, h'' = g, and bounces off the floor at
 * h = 0, leaving it at e times the speed it hit it with; once that speed is below V_REST
 * the ball stays on the floor. Each bounce is a state event, which the model locates inside
 * the step where it falls: between bounces the flight is a parabola, so the time of the next
 * one is a root of h + v s + g s^2 / 2 = 0, and the whole motion is exact. */

#include <math.h>

#include "model.h"

enum { TIME, H, V, G, E };

/* the speed off the floor below which the ball stays on it (m/s) */
#define V_REST 0.1

const char model_token[] = "{8d1f0b52-3c7e-4a0e-9b61-2f4c6d7e8a02}";
const Variable model_variables[] = {
    [TIME] = {REAL, 0},
    [H] = {REAL, 1},
    [V] = {REAL, 0},
    [G] = {REAL, -9.81},
    [E] = {REAL, 0.7},
};
const size_t model_variable_count = sizeof model_variables / sizeof model_variables[0];

const char *model_initialize(double v[]) {
    if (!(v[G] < 0)) return "g must be < 0 (down)";
    if (!(v[E] >= 0 && v[E] <= 1)) return "e must be within [0, 1]";
    if (!(v[H] >= 0)) return "the ball must start above the floor";
    return NULL;
}

int model_advance(double v[], double *t, double end) {
    double g = v[G];
    while (*t < end) {
        if (v[H] <= 0 && v[V] == 0) { /* on the floor, for good */
            *t = end;
            break;
        }
        double s = end - *t, h = v[H] + v[V] * s + g * s * s / 2;
        if (h > 0) {
            v[H] = h;
            v[V] += g * s;
            *t = end;
            break;
        }
        /* the floor within the step: the root of the parabola ahead (g < 0) */
        double hit = (v[V] + sqrt(v[V] * v[V] - 2 * g * v[H])) / -g;
        double speed = -(v[V] + g * hit) * v[E];
        *t += hit;
        v[H] = 0;
        v[V] = speed < V_REST ? 0 : speed;
    }
    return 0;
}
