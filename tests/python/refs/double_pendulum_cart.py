"""Reference for `DoublePendulumCart` (docs/mechanisms/DoublePendulumCart.md, docs/derivations.md):
a cart M on a track (force F, drag c x'), a massless rod l1 to a point mass m1, a massless rod
l2 from m1 to a point mass m2; phi1, phi2 from the downward vertical, counter-clockwise.

The accelerations come from Newton's law written for the three bodies separately, the rod
tensions T1, T2 as unknowns, solved as one linear system at each call (the FMU forms
Lagrange's equations from its energies instead). With e_i = (sin phi_i, -cos phi_i) from
the upper end of rod i to its mass, a rod in tension pulls its mass by -T_i e_i and its
upper end by +T_i e_i:

    cart:  M x''    = F - c x' + T1 sin phi1            (horizontally; the track holds it vertically)
    m1:    m1 p1''  = -T1 e1 + T2 e2 - m1 g J
    m2:    m2 p2''  = -T2 e2 - m2 g J

    p1 = (x + l1 sin phi1, -l1 cos phi1),  p2 = p1 + (l2 sin phi2, -l2 cos phi2)
    E   = 1/2 M x'^2 + 1/2 m1 |p1'|^2 + 1/2 m2 |p2'|^2 + g (m1 p1y + m2 p2y)
    p_x = M x' + m1 p1x' + m2 p2x'
    dE/dt = F x' - c x'^2,   dp_x/dt = F - c x'
"""

from __future__ import annotations

import math

import numpy as np

from ._common import case_settings, merge, run

PARAMS = {"M": 1.0, "m1": 0.5, "m2": 0.5, "l1": 0.5, "l2": 0.5, "g": 9.81, "c": 0.0}
INPUTS = {"F": 0.0}
STATES = ("x", "x_dot", "phi1", "phi1_dot", "phi2", "phi2_dot")
START = {"x": 0.0, "x_dot": 0.0, "phi1": 1.0, "phi1_dot": 0.0, "phi2": 0.5, "phi2_dot": 0.0}
OUTPUTS = ("tip_x", "tip_y", "E", "p_x")
EXTRA = ("x_ddot", "phi1_ddot", "phi2_ddot", "T1", "T2", "E_dot", "p_x_dot", "W_nc", "J_nc")
EXPERIMENT = {"start": 0.0, "stop": 10.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def newton(y, p, F):
    """(x'', phi1'', phi2'', T1, T2): Newton's law on the cart (horizontally), m1 and m2 (both
    components), the accelerations of p1 and p2 from differentiating their positions twice."""
    x, v, a, wa, b, wb = y[:6]
    M, m1, m2, l1, l2, g = (p[k] for k in ("M", "m1", "m2", "l1", "l2", "g"))
    s1, c1, s2, c2 = math.sin(a), math.cos(a), math.sin(b), math.cos(b)
    # p1'' = (x'' + l1 c1 phi1'' - l1 wa^2 s1, l1 s1 phi1'' + l1 wa^2 c1); p2'' adds rod 2's part
    k1 = (-l1 * wa * wa * s1, l1 * wa * wa * c1)
    k2 = (-l2 * wb * wb * s2, l2 * wb * wb * c2)
    A = np.array([
        [M, 0.0, 0.0, -s1, 0.0],                        # cart, I
        [m1, m1 * l1 * c1, 0.0, s1, -s2],               # m1, I
        [0.0, m1 * l1 * s1, 0.0, -c1, c2],              # m1, J
        [m2, m2 * l1 * c1, m2 * l2 * c2, 0.0, s2],      # m2, I
        [0.0, m2 * l1 * s1, m2 * l2 * s2, 0.0, -c2],    # m2, J
    ])
    rhs = np.array([
        F - p["c"] * v,
        -m1 * k1[0],
        -m1 * k1[1] - m1 * g,
        -m2 * (k1[0] + k2[0]),
        -m2 * (k1[1] + k2[1]) - m2 * g,
    ])
    return np.linalg.solve(A, rhs)


def accelerations(y, p, F):
    """(x'', phi1'', phi2'') from Newton's law (the tensions dropped)."""
    return newton(y, p, F)[:3]


def positions(y, p):
    x, a, b = y[0], y[2], y[4]
    p1 = (x + p["l1"] * math.sin(a), -p["l1"] * math.cos(a))
    return p1, (p1[0] + p["l2"] * math.sin(b), p1[1] - p["l2"] * math.cos(b))


def velocities(y, p):
    v, a, wa, b, wb = y[1], y[2], y[3], y[4], y[5]
    v1 = (v + p["l1"] * wa * math.cos(a), p["l1"] * wa * math.sin(a))
    return v1, (v1[0] + p["l2"] * wb * math.cos(b), v1[1] + p["l2"] * wb * math.sin(b))


def energy(y, p):
    (_, y1), (_, y2) = positions(y, p)
    v1, v2 = velocities(y, p)
    kinetic = 0.5 * (p["M"] * y[1] ** 2 + p["m1"] * (v1[0] ** 2 + v1[1] ** 2) + p["m2"] * (v2[0] ** 2 + v2[1] ** 2))
    return kinetic + p["g"] * (p["m1"] * y1 + p["m2"] * y2)


def momentum(y, p):
    v1, v2 = velocities(y, p)
    return p["M"] * y[1] + p["m1"] * v1[0] + p["m2"] * v2[0]


def power(y, p, F):
    """dE/dt = F x' - c x'^2: the force and the drag act on the cart alone."""
    return (F - p["c"] * y[1]) * y[1]


def horizontal_force(y, p, F):
    """dp_x/dt = F - c x': the external horizontal forces (the track's is vertical)."""
    return F - p["c"] * y[1]


def rhs(t, y, p, u):
    xa, aa, ba = accelerations(y, p, u["F"])
    out = [y[1], xa, y[3], aa, y[5], ba]
    if len(y) > 6:  # work and impulse of the force and the drag, integrated alongside
        out += [power(y, p, u["F"]), horizontal_force(y, p, u["F"])]
    return out


def _outputs(t, y, p, u):
    xa, aa, ba, T1, T2 = newton(y, p, u["F"])
    _, (tx, ty) = positions(y, p)
    return {"x_ddot": xa, "phi1_ddot": aa, "phi2_ddot": ba, "T1": T1, "T2": T2, "tip_x": tx, "tip_y": ty,
            "E": energy(y, p), "p_x": momentum(y, p), "E_dot": power(y, p, u["F"]),
            "p_x_dot": horizontal_force(y, p, u["F"])}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution; returns the states, the accelerations, the tensions T1, T2, tip_x,
    tip_y, E, p_x, E_dot, p_x_dot, W_nc and J_nc (the work and the impulse of F and the drag
    since t_out[0], integrated with the states) and F."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    return run(rhs, _outputs, STATES + ("W_nc", "J_nc"), [s[n] for n in STATES] + [0.0, 0.0], t_out, p,
               INPUTS, inputs, rtol, atol, switch_outputs)
