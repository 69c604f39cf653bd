"""Self-checks of tests/python/refs/oscillator.py, the independent reference of Oscillator:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from refs import oscillator, step_input


@pytest.mark.parametrize("c, expected", [(5.0, "overdamped"), (4.0, "critical"), (0.4, "underdamped"),
                                         (0.0, "undamped")])
def test_oscillator_free_response_all_regimes(c, expected):
    p = oscillator.params(c=c)  # m = 1, k = 4: c = 4 is critical
    assert oscillator.regime(p) == expected
    t = np.linspace(0.0, 20.0, 2001)
    r = oscillator.simulate(p, {"x": 1.0, "x_dot": -0.7}, t)
    x, v = oscillator.free_response(p, 1.0, -0.7, t)
    assert np.max(np.abs(r["x"] - x)) < 1e-9
    assert np.max(np.abs(r["x_dot"] - v)) < 1e-9
    assert np.max(np.abs(r["x_ddot"] - (-(c * v + 4.0 * x)))) < 1e-8


def test_oscillator_overdamped_form_equals_notes_exponentials():
    p = oscillator.params(c=5.0)
    s1, s2 = oscillator.overdamped_roots(p)
    x0, v0 = 1.0, -0.7
    B = (v0 - s1 * x0) / (s2 - s1)
    A = x0 - B
    t = np.linspace(0, 10, 101)
    x, _ = oscillator.free_response(p, x0, v0, t)
    assert np.max(np.abs(x - (A * np.exp(s1 * t) + B * np.exp(s2 * t)))) < 1e-13


def test_oscillator_step_response_with_input_switch():
    """F = 0 until t = 2, then F = 3 (zero-order hold): closed form in two pieces."""
    p = oscillator.params()
    t = np.linspace(0.0, 20.0, 2001)
    inp = step_input(["F"], [0.0, 2.0], [[0.0], [3.0]], t_end=20.0)
    r = oscillator.simulate(p, {"x": 1.0, "x_dot": 0.0}, t, inp)
    x1, v1 = oscillator.free_response(p, 1.0, 0.0, t)
    x2s, v2s = oscillator.free_response(p, 1.0, 0.0, np.array([2.0]))
    x2, v2 = oscillator.step_response(p, 3.0, x2s[0], v2s[0], t - 2.0)
    xe = np.where(t < 2.0, x1, x2)
    assert np.max(np.abs(r["x"] - xe)) < 1e-9
    i2 = int(np.flatnonzero(t == 2.0)[0])
    assert r["F"][i2] == 3.0 and r["F"][i2 - 1] == 0.0
    assert abs(r["x"][-1] - 3.0 / 4.0) < 2e-3          # settles to F/k
    rb = oscillator.simulate(p, {"x": 1.0, "x_dot": 0.0}, t, inp, switch_outputs="before")
    assert rb["F"][i2] == 0.0 and np.array_equal(rb["x"], r["x"])


@pytest.mark.parametrize("c, omega", [(0.4, 1.7), (0.4, 2.0), (0.0, 1.3), (0.0, 2.0), (6.0, 0.5)])
def test_oscillator_complete_harmonic_response(c, omega):
    p = oscillator.params(c=c, F0=2.0, omega=omega)
    t = np.linspace(0.0, 20.0, 2001)
    r = oscillator.simulate(p, {"x": 0.3, "x_dot": 0.5}, t)
    x, v = oscillator.response(p, 0.3, 0.5, t)
    assert np.max(np.abs(r["x"] - x)) < 1e-9 * max(1.0, np.max(np.abs(x)))
    assert np.max(np.abs(r["x_dot"] - v)) < 1e-9 * max(1.0, np.max(np.abs(v)))


def test_oscillator_steady_amplitude_and_phase():
    p = oscillator.params(c=0.8, F0=2.0, omega=1.5)
    X, psi = oscillator.steady_amplitude_phase(p)
    w = 1.5
    # X e^{i psi} (k - m w^2 + i c w) = F0 (phasor of m x'' + c x' + k x = F0 sin w t)
    z = X * np.exp(1j * psi) * (4.0 - w * w + 1j * 0.8 * w)
    assert abs(z - 2.0) < 1e-12
    t = np.linspace(60.0, 80.0, 201)  # transient gone (e^{-0.4 * 60})
    r = oscillator.simulate(p, {"x": 0.0, "x_dot": 0.0}, np.concatenate([[0.0], t]))
    assert np.max(np.abs(r["x"][1:] - X * np.sin(w * t + psi))) < 1e-9


def test_oscillator_peak_of_amplitude_response():
    p = oscillator.params(c=0.4, F0=1.0)
    wp, Xp = oscillator.peak(p)
    ws = np.linspace(wp - 1e-3, wp + 1e-3, 2001)
    Xs = [oscillator.steady_amplitude_phase(p, w)[0] for w in ws]
    assert abs(ws[int(np.argmax(Xs))] - wp) < 2e-6
    assert abs(max(Xs) - Xp) < 1e-12 * Xp
