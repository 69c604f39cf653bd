#!/usr/bin/env python3
"""The Python side of `mechfmu bench`: FMUs under FMPy, and scipy on the same problem.

Run by `mechfmu bench` with the project venv (target/venv); reads a JSON configuration
(a file named as the only argument) and prints one JSON document on stdout:

- ``loops``: µs per communication step of FMPy's low-level loop (``FMU2Slave``: set the
  inputs, ``doStep``, ``getReal`` of the outputs), one reused instance, per run
  ``fmi2Reset`` + setup + initialization untimed, then the timed loop; the median of runs.
- ``simulate_fmu``: µs per step of ``fmpy.simulate_fmu`` on the same FMU (everything
  included: instantiation, recording), for context.
- ``precision``: work–precision of the Oscillator's free response over 20 s (output every
  0.1 s): the largest error of x against the exact values the caller sends, and the CPU
  time of one run, for ``scipy.integrate.solve_ivp`` (RK45, DOP853; rtol = atol = tol; the
  same equations, in Python) and for the FMU through FMPy's low-level loop on a reused
  instance (reset, setup, init, 200 × (doStep, getReal x), all timed).

Times are CPU time of this process (``time.process_time_ns``), medians of repeated runs.
Usable alone: ``target/venv/bin/python scripts/bench_fmpy.py config.json``.
"""

import json
import math
import shutil
import sys
import time

import numpy as np


def cpu_ns():
    return time.process_time_ns()


def stat(samples):
    s = sorted(x for x in samples if not math.isnan(x))
    n = len(s)
    if n == 0:
        return {"median": None, "min": None, "max": None, "runs": 0}
    median = s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])
    return {"median": median, "min": s[0], "max": s[-1], "runs": n}


class Slave:
    """One FMU2Slave instance of an FMU, reused across runs."""

    def __init__(self, fmu_path):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(fmu_path)
        self.unzipdir = extract(fmu_path)
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="bench",
        )
        self.fmu.instantiate()
        self.fresh = True

    def start(self, tol, start=0.0):
        if not self.fresh:
            self.fmu.reset()
        self.fresh = False
        self.fmu.setupExperiment(tolerance=tol, startTime=start)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.unzipdir, ignore_errors=True)


def fmpy_loop(cfg, runs):
    """µs per step of the low-level loop: setReal(inputs), doStep, getReal(outputs)."""
    slave = Slave(cfg["fmu"])
    fmu = slave.fmu
    h, tol, n, start = cfg["h"], cfg["tol"], cfg["steps"], cfg.get("start", 0.0)
    in_vrs = [vr for vr, _ in cfg["inputs"]]
    in_vals = [v for _, v in cfg["inputs"]]
    outputs = cfg["outputs"]
    samples = []
    for run in range(runs + 1):
        slave.start(tol, start)
        t = start
        t0 = cpu_ns()
        for i in range(n):
            if in_vrs:
                fmu.setReal(in_vrs, in_vals)
            # As fmpy.simulate_fmu computes its communication points.
            nxt = start + (i + 1) * h
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=nxt - t)
            fmu.getReal(outputs)
            t = nxt
        dt = cpu_ns() - t0
        if run:
            samples.append(dt / n * 1e-3)
    slave.close()
    return {"name": cfg["name"], "h": h, "tol": tol, "steps": n, "us_per_step": stat(samples)}


def simulate(cfg, runs):
    """µs per step of fmpy.simulate_fmu (whole call, instantiation and recording included)."""
    from fmpy import extract, read_model_description, simulate_fmu

    md = read_model_description(cfg["fmu"])
    unzipdir = extract(cfg["fmu"])
    n = cfg["steps"]
    samples = []
    for run in range(runs + 1):
        t0 = cpu_ns()
        simulate_fmu(
            unzipdir,
            model_description=md,
            fmi_type="CoSimulation",
            start_time=cfg.get("start", 0.0),
            stop_time=cfg.get("start", 0.0) + n * cfg["h"],
            step_size=cfg["h"],
            output_interval=cfg["h"],
            relative_tolerance=cfg["tol"],
        )
        dt = cpu_ns() - t0
        if run:
            samples.append(dt / n * 1e-3)
    shutil.rmtree(unzipdir, ignore_errors=True)
    return {"name": cfg["name"], "h": cfg["h"], "tol": cfg["tol"], "steps": n, "us_per_step": stat(samples)}


def timed_runs(run, runs, budget_s=2.0):
    """CPU seconds of `run()` (returns the error) at least 3 times, up to `runs` or until the
    time budget is spent; one untimed warm-up first."""
    error = run()
    samples = []
    spent = 0.0
    while len(samples) < runs and (len(samples) < 3 or spent < budget_s):
        t0 = cpu_ns()
        error = run()
        dt = (cpu_ns() - t0) * 1e-9
        samples.append(dt)
        spent += dt
    return error, stat(samples)


def precision(cfg, runs):
    from scipy.integrate import solve_ivp

    p = cfg["problem"]
    m, c, k = p["m"], p["c"], p["k"]
    F, F0, w = 0.0, 0.0, 1.0  # the FMU's start values (checked by the caller)
    grid = np.array(cfg["grid"])
    exact = np.array(cfg["exact"])
    t_end, dt_out = cfg["t_end"], cfg["output"]
    points = []

    # The Oscillator's equations, as its Rust `evaluate` writes them.
    def rhs(t, y):
        forcing = F + F0 * math.sin(w * t)
        return [y[1], (forcing - c * y[1] - k * y[0]) / m]

    for method in ("RK45", "DOP853"):
        for tol in cfg["tolerances"]:
            nfev = [0]

            def run():
                sol = solve_ivp(rhs, (0.0, t_end), [p["x0"], p["v0"]], method=method,
                                rtol=tol, atol=tol, t_eval=grid)
                nfev[0] = int(sol.nfev)
                if not sol.success:
                    return float("nan")
                return float(np.max(np.abs(sol.y[0] - exact)))

            error, cpu = timed_runs(run, runs)
            points.append({"method": "scipy " + method, "tol": tol, "error": error,
                           "cpu_s": cpu, "nfev": nfev[0]})

    slave = Slave(cfg["fmu"])
    fmu = slave.fmu
    vr_x = [p["vr_x"]]
    n = len(grid)
    for tol in cfg["tolerances"]:
        xs = [0.0] * n

        def run():
            slave.start(tol)
            t = 0.0
            for i in range(n):
                nxt = (i + 1) * dt_out
                fmu.doStep(currentCommunicationPoint=t, communicationStepSize=nxt - t)
                xs[i] = fmu.getReal(vr_x)[0]
                t = nxt
            return float(np.max(np.abs(np.array(xs) - exact)))

        error, cpu = timed_runs(run, runs)
        points.append({"method": "FMU (FMPy low-level loop)", "tol": tol, "error": error, "cpu_s": cpu})
    slave.close()
    return points


def main():
    with open(sys.argv[1]) as f:
        cfg = json.load(f)
    runs = cfg.get("runs", 7)
    out = {"versions": {}}
    import fmpy
    import scipy

    out["versions"] = {"python": sys.version.split()[0], "fmpy": fmpy.__version__,
                       "scipy": scipy.__version__, "numpy": np.__version__}
    out["loops"] = [fmpy_loop(c, runs) for c in cfg.get("loops", [])]
    out["simulate_fmu"] = [simulate(c, max(3, runs // 2)) for c in cfg.get("simulate", [])]
    if cfg.get("precision"):
        out["precision"] = precision(cfg["precision"], runs)
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
