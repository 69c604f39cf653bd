"""Self-checks of the independent references in tests/python/refs (no FMU needed): here what
they share (the inputs, the names they accept, the checks below), in test_refs_<module>.py
each mechanism's.

Every test compares two routes that do not share code or equations: the DOP853 solution
against a closed form, Lagrange against Newton-Euler (sympy), a conservation law or a
work-energy balance integrated alongside, or a hand-computed value.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from refs import oscillator, step_input
from refs._common import _table, zoh_value


def rel_err(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


# ============================================================================ inputs (ZOH)

def test_step_input_table_is_fmpy_style_and_switches_at_listed_time():
    tab = step_input(["F"], [0.0, 2.0, 5.0], [[0.0], [3.0], [-1.0]], t_end=10.0)
    assert tab.dtype.names == ("time", "F")
    assert list(tab["time"]) == [0.0, 2.0, 2.0, 5.0, 5.0, 10.0]
    tb = _table(tab, {"F": 0.0})
    assert zoh_value(tb, {"F": 9.0}, -1.0)["F"] == 0.0           # before the first row
    assert zoh_value(tb, {"F": 9.0}, 1.999999)["F"] == 0.0
    assert zoh_value(tb, {"F": 9.0}, 2.0)["F"] == 3.0             # switches AT t = 2
    assert zoh_value(tb, {"F": 9.0}, 2.0, before=True)["F"] == 0.0
    assert zoh_value(tb, {"F": 9.0}, 5.0)["F"] == -1.0
    assert zoh_value(tb, {"F": 9.0}, 50.0)["F"] == -1.0


def test_zoh_rows_without_duplicates_read_the_same():
    a = step_input(["F"], [0.0, 2.0], [[0.0], [3.0]], t_end=4.0)
    b = np.array([(0.0, 0.0), (2.0, 3.0)], dtype=[("time", float), ("F", float)])
    t = np.linspace(0, 4, 41)
    ra, rb = oscillator.simulate(None, None, t, a), oscillator.simulate(None, None, t, b)
    assert np.array_equal(ra["x"], rb["x"])


def test_unknown_names_are_rejected():
    with pytest.raises(KeyError):
        oscillator.simulate({"mass": 2.0}, None, [0.0, 1.0])
    with pytest.raises(KeyError):
        oscillator.simulate(None, {"y": 2.0}, [0.0, 1.0])
    with pytest.raises(KeyError):
        oscillator.simulate(None, None, [0.0, 1.0], step_input(["G"], [0.0], [[1.0]]))


# ============================================================================ energy rate, pointwise

def energy_rate_check(S, states, rhs, p, pnames, inputs, power, n=15):
    """dE/dt = grad(E) . y' at random states equals the power of the non-conservative forces."""
    order = [S["q"][0], S["qd"][0], S["q"][1], S["qd"][1]] + ([S["q"][2], S["qd"][2]] if len(S["q"]) > 2 else [])
    grad = sp.lambdify(order + S["params"], [sp.diff(S["energy"], v) for v in order], "numpy")
    for y, u in states(n):
        g = np.array(grad(*y, *[p[k] for k in pnames]), float)
        yd = np.asarray(rhs(0.0, y, p, u), float)[: len(order)]
        P = power(y, p, u)
        assert abs(g @ yd - P) < 1e-10 * max(1.0, np.max(np.abs(g * yd))), (g @ yd, P)
