"""The optional FMI 2.0 co-simulation capabilities, through FMPy: FMU state and
its serialized form (across processes), reset, input interpolation. (The directional
derivatives: a linearization, in test_pendulum_cart.py.)"""

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import fmi2Error

from fmutest import Slave, fmu_path
from mechanisms import models

MECHANISMS = models()


def outputs(md):
    return [v.name for v in md.modelVariables if v.causality == "output"]


def run_steps(s, t0, n, h):
    for i in range(n):
        s.step(t0 + i * h, h)
    return t0 + n * h


@pytest.mark.parametrize("name", MECHANISMS)
def test_capabilities_are_declared(name):
    cs = read_model_description(str(fmu_path(name))).coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canInterpolateInputs and cs.maxOutputDerivativeOrder >= 1
    assert cs.providesDirectionalDerivative


@pytest.mark.parametrize("name", MECHANISMS)
def test_rollback_is_bit_identical(name):
    with Slave(fmu_path(name)) as s:
        names = outputs(s.md)
        s.initialize()
        t = run_steps(s, 0.0, 30, 0.01)
        state = s.fmu.getFMUstate()
        run_steps(s, t, 40, 0.01)
        first = s.get(*names)
        s.fmu.setFMUstate(state)
        run_steps(s, t, 40, 0.01)
        assert s.get(*names) == first
        s.fmu.freeFMUstate(state)


@pytest.mark.parametrize("name", MECHANISMS)
def test_reset_then_rerun_equals_a_fresh_instance(name):
    with Slave(fmu_path(name)) as reused, Slave(fmu_path(name)) as fresh:
        names = outputs(reused.md)
        reused.initialize()
        run_steps(reused, 0.0, 25, 0.01)
        reused.fmu.reset()
        for s in (reused, fresh):
            s.initialize()
            run_steps(s, 0.0, 50, 0.01)
        assert reused.get(*names) == fresh.get(*names)


CONTINUE = textwrap.dedent("""
    import sys
    sys.path.insert(0, {tests!r})
    from fmutest import Slave
    with Slave({fmu!r}) as s:
        state = s.fmu.deSerializeFMUstate(open({path!r}, "rb").read())
        s.fmu.setFMUstate(state)
        t = {t!r}
        for i in range(40):
            s.step(t + i * 0.01, 0.01)
        print(repr(s.get(*{names!r})))
""")


@pytest.mark.parametrize("name", ["Oscillator", "Crane", "RigidBody"])
def test_a_state_serialized_in_one_process_continues_in_another(name, tmp_path):
    path = fmu_path(name)
    with Slave(path) as s:
        names = outputs(s.md)
        s.initialize()
        t = run_steps(s, 0.0, 30, 0.01)
        state = s.fmu.getFMUstate()
        blob = s.fmu.serializeFMUstate(state)
        s.fmu.freeFMUstate(state)
        run_steps(s, t, 40, 0.01)
        here = s.get(*names)
    (tmp_path / "state.bin").write_bytes(blob)
    script = CONTINUE.format(tests=str(Path(__file__).parent), fmu=str(path), path=str(tmp_path / "state.bin"),
                             t=t, names=names)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert eval(done.stdout.strip()) == here


REFUSE = textwrap.dedent("""
    import sys
    sys.path.insert(0, {tests!r})
    from fmpy.fmi1 import FMICallException
    from fmutest import Slave
    with Slave({fmu!r}) as s:
        try:
            s.fmu.deSerializeFMUstate({blob!r})
        except FMICallException as e:
            print("refused", int(e.status), s.log.text().replace(chr(10), " "))
        else:
            print("accepted")
""")


def serialized(name):
    with Slave(fmu_path(name)) as s:
        s.initialize()
        run_steps(s, 0.0, 10, 0.01)
        state = s.fmu.getFMUstate()
        blob = s.fmu.serializeFMUstate(state)
        s.fmu.freeFMUstate(state)
    return blob


def test_malformed_serialized_states_are_refused_in_a_subprocess():
    good = serialized("Oscillator")
    wrong_version = good[:8] + bytes([good[8] + 1]) + good[9:]
    cases = {
        "garbage": b"\x00\x17garbage" * 11,
        "truncated": good[: len(good) // 2],
        "corrupted": good[:40] + bytes([good[40] ^ 0xFF]) + good[41:],
        "wrong version": wrong_version,
        "wrong model": serialized("Crane"),
        "empty": b"",
    }
    for what, blob in cases.items():
        script = REFUSE.format(tests=str(Path(__file__).parent), fmu=str(fmu_path("Oscillator")), blob=blob)
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, f"{what}: the process died ({done.returncode}): {done.stderr}"
        out = done.stdout
        assert out.startswith(f"refused {fmi2Error}"), f"{what}: {out}"
        assert "fmi2DeSerializeFMUstate" in out, f"{what}: no message: {out}"
    assert "format version" in subprocess.run(
        [sys.executable, "-c", REFUSE.format(tests=str(Path(__file__).parent), fmu=str(fmu_path("Oscillator")),
                                            blob=wrong_version)], capture_output=True, text=True).stdout
    assert "Crane" in subprocess.run(
        [sys.executable, "-c", REFUSE.format(tests=str(Path(__file__).parent), fmu=str(fmu_path("Oscillator")),
                                            blob=cases["wrong model"])], capture_output=True, text=True).stdout


def polynomial_response(t, a, b, q, m=1.0, c=0.4, k=4.0, x0=1.0, v0=0.0):
    """m x'' + c x' + k x = a + b t + q t²: the particular solution A t² + B t + C plus the
    free response that meets x(0) = x0, x'(0) = v0 (underdamped here)."""
    A = q / k
    B = (b - 2 * c * A) / k
    C = (a - 2 * m * A - c * B) / k
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(m * k))
    wd = wn * np.sqrt(1 - zeta**2)
    X0, V0 = x0 - C, v0 - B
    free = np.exp(-zeta * wn * t) * (X0 * np.cos(wd * t) + (V0 + zeta * wn * X0) / wd * np.sin(wd * t))
    return A * t**2 + B * t + C + free


def drive_with_polynomial_input(h, a, b, q, derivatives):
    """The Oscillator under F(t) = a + b t + q t², set at every communication point with (or
    without) its first and second derivatives, through fmi2SetRealInputDerivatives.

    (FMPy's own `simulate_fmu(set_input_derivatives=True)` cannot be used: FMPy 0.3.32 sizes
    its derivative buffer for exactly 9 inputs and fails for any other number.)"""
    from ctypes import c_double, c_int, c_uint
    with Slave(fmu_path("Oscillator")) as s:
        s.initialize(tolerance=1e-10)
        vr = (c_uint * 2)(s.vr["F"], s.vr["F"])
        order = (c_int * 2)(1, 2)
        times, xs = [0.0], [s.get("x")[0]]
        n = int(round(20.0 / h))
        for i in range(n):
            t = i * h
            s.set(F=a + b * t + q * t * t)
            if derivatives:
                status = s.call("fmi2SetRealInputDerivatives", vr, 2, order, (c_double * 2)(b + 2 * q * t, 2 * q))
                s.expect_ok("fmi2SetRealInputDerivatives", status)
            s.step(t, h)
            times.append((i + 1) * h)
            xs.append(s.get("x")[0])
        return np.array(times), np.array(xs)


@pytest.mark.parametrize("q", [0.0, 0.01], ids=["ramp", "quadratic"])
@pytest.mark.parametrize("h", [0.1, 0.5])
def test_a_polynomial_input_with_derivatives_gives_the_exact_response(h, q):
    a, b = 0.5, 0.3
    t, smooth = drive_with_polynomial_input(h, a, b, q, derivatives=True)
    _, held = drive_with_polynomial_input(h, a, b, q, derivatives=False)
    exact = polynomial_response(t, a, b, q)
    scale = np.ptp(exact)
    err_smooth = np.max(np.abs(smooth - exact)) / scale
    err_held = np.max(np.abs(held - exact)) / scale
    assert err_smooth < 1e-8, f"with derivatives: {err_smooth:.2e} of range"
    assert err_held > 100 * max(err_smooth, 1e-12) and err_held > 1e-4, f"held: {err_held:.2e} of range"


def test_input_derivatives_of_order_3_or_of_an_output_are_refused():
    from ctypes import c_double, c_int, c_uint
    with Slave(fmu_path("Oscillator")) as s:
        s.initialize()
        for name, order in [("F", 3), ("x", 1)]:
            status = s.call("fmi2SetRealInputDerivatives", (c_uint * 1)(s.vr[name]), 1, (c_int * 1)(order),
                            (c_double * 1)(1.0))
            assert status == fmi2Error

