"""``python -m mechfmu_sweep FMU --param NAME=SPEC ...`` (what ``mechfmu sweep`` runs).

Exit status: 0 when the sweep ran (whatever became of individual cases: their status is in
the results), 2 for a usage error (the message names it), 1 when the sweep machinery
failed (the cluster, the FMU file, writing the results).

``mechfmu sweep`` passes its arguments through unchecked: every value is checked here
(``check_request`` for what needs no FMU, then ``Plan`` against the model description).
"""

from __future__ import annotations

import argparse
import hashlib
import math
import sys
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .design import (
    Design,
    Schedule,
    SHAPES,
    Spec,
    SpecError,
    build_design,
    parse_param,
    parse_schedule,
)
from .results import ResultsWriter
from .runner import CaseSetup, Summary, parse_summary

SETTABLE_TYPES = ("Real", "Integer", "Enumeration")


EPILOG = """\
Specs (--param NAME=SPEC; NAME is a parameter, a start value, or an input schedule's argument NAME.arg):
  5                  a constant         2:10:17            17 points from 2 to 10
  2,3,5              a list             uniform(800,1200)  random, drawn per case
  normal(mu,sigma)   random             loguniform(a,b)    random, uniform in log
Grids and lists are crossed (full factorial); --cases random draws are made at each grid point.

Input schedules (--input-schedule NAME=SHAPE(args), arguments by position or name):
  constant(value)  step(t0,value)  pulse(t0,width,value)  bangbang(t0,width,value)  ramp(t0,t1,value)
  each also has NAME.scale; sweep an argument with --param NAME.arg=SPEC.

Summaries (--summary, besides the final value of every output):
  max(v) min(v) max_abs(v) (or 'max|v|') mean(v) rms(v) final(v)

Example:
  mechfmu sweep fmus/Crane.fmu --param l=2:10:17 \\
      --input-schedule 'x_ddot=bangbang(t0=1,width=2,value=0.5)' --param x_ddot.value=0.25,0.5,1 \\
      --summary 'max_abs(phi)' --out crane.parquet --plot crane.png

Usage notes: python/mechfmu_sweep/README.md"""


def make_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="mechfmu sweep",
        description="Parameter sweep of an FMI 2.0 Co-Simulation FMU on Dask distributed.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("fmu", type=Path, help="the FMU")
    p.add_argument("--param", action="append", default=[], metavar="NAME=SPEC",
                   help="a design variable: a parameter, a start value or an input schedule's "
                        "argument (NAME.arg); SPEC is a value, a:b:n, v1,v2,..., uniform(a,b), "
                        "normal(mu,sigma) or loguniform(a,b)")
    p.add_argument("--cases", type=int, help="random draws per grid point (default 100 when a spec is random)")
    p.add_argument("--seed", type=int, help="seed of the random draws (default: a fresh one, reported)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://127.0.0.1:8786")
    p.add_argument("--workers", type=int, help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--chunk-size", type=int,
                   help="cases per Dask task (default: about 8 tasks per worker, at most 512 cases (native) or 16 (fmpy))")
    p.add_argument("--start-time", type=float, help="default: the FMU's DefaultExperiment, or 0")
    p.add_argument("--stop-time", type=float, help="default: the FMU's DefaultExperiment")
    p.add_argument("--output-interval", type=float,
                   help="communication step, the sampling of the summaries (default: as fmpy.simulate_fmu)")
    p.add_argument("--tolerance", type=float, help="relative tolerance (default: the FMU's DefaultExperiment)")
    p.add_argument("--input", type=Path, metavar="FILE.csv",
                   help="time-varying inputs for every case: fmpy-style CSV, time then one column per input")
    p.add_argument("--input-schedule", action="append", default=[], metavar="NAME=SHAPE(args)",
                   help=f"a per-case input signal; shapes: {', '.join(SHAPES)}")
    p.add_argument("--summary", action="append", default=[], metavar="EXPR",
                   help="a summary column besides the final outputs: max(v), min(v), max_abs(v) (or max|v|), "
                        "mean(v), rms(v), final(v)")
    p.add_argument("--out", type=Path, metavar="FILE", help="results, .parquet or .csv (default: CSV on stdout)")
    p.add_argument("--plot", type=Path, metavar="PNG", help="plot a swept parameter against a summary")
    p.add_argument("--plot-x", metavar="NAME", help="the design column on the x axis (default: the first swept one)")
    p.add_argument("--plot-y", metavar="COLUMN", help="the summary on the y axis (default: the first --summary)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar or progress lines")
    p.add_argument("--engine", choices=("native", "fmpy"),
                   help="what runs the cases on the workers: native (`mechfmu sweep-worker`, no Python per "
                        "step; the default where it can run) or fmpy (FMPy's FMU2Slave, the default with "
                        "--scheduler); both give the same numbers")
    return p


# ---------------------------------------------------------------------------------------
# Checking the request: the values on their own


def check_out(path: Path) -> None:
    if path.suffix.lower() not in (".parquet", ".csv"):
        raise SpecError(f"--out {path}: the extension says the format, .parquet or .csv")


def check_plot(path: Path) -> None:
    if path.suffix.lower() != ".png":
        raise SpecError(f"--plot {path}: the plot is a PNG, give a .png file")


def check_scheduler(address: str) -> None:
    """``[tcp://]HOST:PORT``, e.g. ``tcp://127.0.0.1:8786``."""
    text = address.strip()
    hostport = text.split("://", 1)[1] if "://" in text else text
    host, sep, port = hostport.rpartition(":")
    if not (sep and host and port.isascii() and port.isdigit() and int(port) <= 65535):
        raise SpecError(f"--scheduler {address}: a scheduler address is [tcp://]HOST:PORT, e.g. tcp://127.0.0.1:8786")


def check_request(args: argparse.Namespace) -> None:
    """Every value of the request that can be checked without the FMU: the grammar of the
    specs, schedules and summaries, the files' extensions, the numbers and the address.
    Raises SpecError naming the first problem."""
    for text in args.param:
        parse_param(text)
    for text in args.input_schedule:
        parse_schedule(text)
    for text in args.summary:
        parse_summary(text)
    if args.out is not None:
        check_out(args.out)
    if args.plot is not None:
        check_plot(args.plot)
    if args.scheduler is not None:
        check_scheduler(args.scheduler)
    for option, value in (("--start-time", args.start_time), ("--stop-time", args.stop_time)):
        if value is not None and not math.isfinite(value):
            raise SpecError(f"{option} {value}: not a number (a finite value is needed)")
    for option, value in (("--output-interval", args.output_interval), ("--tolerance", args.tolerance)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise SpecError(f"{option} {value}: must be a finite number > 0")
    for option, value in (("--cases", args.cases), ("--workers", args.workers), ("--chunk-size", args.chunk_size)):
        if value is not None and value < 1:
            raise SpecError(f"{option} must be >= 1")
    if args.seed is not None and not 0 <= args.seed < 2**64:
        raise SpecError(f"--seed {args.seed}: must be an integer from 0 to 2^64 - 1")


# ---------------------------------------------------------------------------------------
# Checking the request against the model description


def _variables(md) -> dict[str, Any]:
    return {v.name: v for v in md.modelVariables}


def _settable(v) -> bool:
    if v.type not in SETTABLE_TYPES or v.variability == "constant" or v.causality == "independent":
        return False
    return v.causality == "input" or (v.causality in ("parameter", "output", "local") and v.initial in ("exact", "approx"))


def _close_names(name: str, names: Sequence[str]) -> str:
    import difflib

    near = difflib.get_close_matches(name, names, n=3)
    return f" (did you mean {', '.join(near)}?)" if near else ""


def default_output_interval(md, start: float, stop: float) -> float:
    """What ``fmpy.simulate_fmu`` uses for a Co-Simulation FMU when given none."""
    from fmpy.util import auto_interval

    cs, ex = md.coSimulation, md.defaultExperiment
    h = None
    if cs is not None and cs.fixedInternalStepSize is not None:
        h = float(cs.fixedInternalStepSize)
    elif ex is not None and ex.stepSize is not None:
        h = float(ex.stepSize)
    if h is not None:
        while (stop - start) / h > 1000:
            h *= 2
        return h
    return float(auto_interval(stop - start))


def read_fmu(fmu: Path):
    """The model description of the FMU file, which must be an FMI 2.0 Co-Simulation FMU."""
    from fmpy import read_model_description

    if not fmu.is_file():
        raise SpecError(f"no FMU at {fmu} (build one with `mechfmu build NAME`, which writes fmus/NAME.fmu)")
    try:
        md = read_model_description(str(fmu), validate=False)
    except Exception as e:  # noqa: BLE001
        raise SpecError(f"{fmu}: not a readable FMU ({e})") from None
    if md.fmiVersion != "2.0" or md.coSimulation is None:
        raise SpecError(f"{fmu}: an FMI 2.0 Co-Simulation FMU is needed (this one: FMI {md.fmiVersion}, "
                        f"{'Co-Simulation' if md.coSimulation else 'no Co-Simulation'})")
    return md


class Plan:
    """The validated request: design, per-case setup and what to write."""

    def __init__(self, args: argparse.Namespace):
        check_request(args)
        if args.scheduler is not None:
            args.scheduler = args.scheduler.strip()
        self.args = args
        self.md = read_fmu(args.fmu)
        self.model = self.md.coSimulation.modelIdentifier
        variables = _variables(self.md)
        schedules, base_input = self._inputs(variables)
        self.specs, start_columns, schedule_args, base_scales = self._design_variables(variables, schedules,
                                                                                        base_input)
        self.design: Design = self._design(variables, start_columns)
        start, stop, interval, tolerance = self._experiment()
        summaries = self._summaries(variables)
        self.chosen = [parse_summary(t).column for t in args.summary]
        self.setup = CaseSetup(
            columns=list(self.design.columns),
            start_columns=start_columns,
            schedules=schedules,
            schedule_args=schedule_args,
            base_input=base_input,
            base_scales=base_scales,
            start_time=start,
            stop_time=stop,
            tolerance=tolerance,
            output_interval=interval,
            summaries=summaries,
        )
        self._check_cluster_and_plot()

    def _inputs(self, variables) -> tuple[dict[str, Schedule], np.ndarray | None]:
        """The input schedules (``--input-schedule``) and the CSV (``--input``): a time signal
        for each input they name, from one of them only."""
        args, names = self.args, list(variables)
        schedules: dict[str, Schedule] = {}
        for text in args.input_schedule:
            s = parse_schedule(text)
            v = variables.get(s.input)
            if v is None:
                raise SpecError(f"--input-schedule {text}: {self.model} has no variable `{s.input}`"
                                f"{_close_names(s.input, names)}")
            if v.causality != "input" or v.type != "Real":
                raise SpecError(f"--input-schedule {text}: `{s.input}` is not a Real input of {self.model} "
                                f"(inputs: {', '.join(n for n, w in variables.items() if w.causality == 'input') or 'none'})")
            if s.input in schedules:
                raise SpecError(f"--input-schedule given twice for {s.input}")
            schedules[s.input] = s
        base_input = None
        if args.input is not None:
            base_input = self._read_csv(args.input, variables)
            both = sorted(set(base_input.dtype.names[1:]) & set(schedules))
            if both:
                raise SpecError(f"{', '.join(both)} given both by --input {args.input} and by --input-schedule")
        return schedules, base_input

    def _design_variables(self, variables, schedules: dict[str, Schedule], base_input: np.ndarray | None):
        """What each ``--param`` sweeps: (the specs, {column: the variable whose start value it
        sets}, {input: {schedule argument: column}}, {CSV input: the column of its scale})."""
        args, names = self.args, list(variables)
        specs: list[Spec] = []
        start_columns: dict[str, str] = {}
        schedule_args: dict[str, dict[str, str]] = {}
        base_scales: dict[str, str] = {}
        csv_inputs = set(base_input.dtype.names[1:]) if base_input is not None else set()
        for text in args.param:
            spec = parse_param(text)
            name = spec.name
            specs.append(spec)
            v = variables.get(name)
            if v is not None:
                if not _settable(v):
                    raise SpecError(f"--param {text}: `{name}` cannot be set (causality {v.causality}, "
                                    f"variability {v.variability}, initial {v.initial}); a design variable is a "
                                    "parameter, a start value (initial exact/approx) or an input")
                if name in schedules or name in csv_inputs:
                    raise SpecError(f"--param {text}: input `{name}` already has a time signal; sweep its "
                                    f"arguments instead ({name}.value, {name}.scale, ...)")
                start_columns[name] = name
                continue
            base, _, arg = name.rpartition(".")
            if base in schedules:
                allowed = list(SHAPES[schedules[base].shape].args) + ["scale"]
                if arg not in allowed:
                    raise SpecError(f"--param {text}: the schedule of {base} ({schedules[base].shape}) has no "
                                    f"argument `{arg}` (it has {', '.join(allowed)})")
                schedule_args.setdefault(base, {})[arg] = name
            elif base in csv_inputs:
                if arg != "scale":
                    raise SpecError(f"--param {text}: an input read from {args.input} has only `scale`")
                base_scales[base] = name
            else:
                raise SpecError(f"--param {text}: {self.model} has no variable `{name}`{_close_names(name, names)}")
        if not specs:
            raise SpecError("nothing to sweep: give at least one --param NAME=SPEC")
        return specs, start_columns, schedule_args, base_scales

    def _design(self, variables, start_columns: dict[str, str]) -> Design:
        """The cases (a fresh seed when a spec is random and none is given); an Integer or
        Enumeration start value must be swept over whole numbers."""
        seed = self.args.seed
        if seed is None and any(s.is_random for s in self.specs):
            seed = int(np.random.SeedSequence().entropy % (2**32))
        design = build_design(self.specs, self.args.cases, seed)
        for j, col in enumerate(design.columns):
            v = variables.get(col)
            if v is not None and col in start_columns and v.type != "Real":
                vals = design.values[:, j]
                if not np.all(vals == np.round(vals)):
                    raise SpecError(f"--param {col}: `{col}` is an {v.type}; its spec gives non-integer values")
        return design

    def _experiment(self) -> tuple[float, float, float, float | None]:
        """(start time, stop time, output interval, tolerance): the options', else the FMU's
        DefaultExperiment's, else FMPy's defaults."""
        args, md = self.args, self.md
        ex = md.defaultExperiment
        start = args.start_time if args.start_time is not None else (
            float(ex.startTime) if ex is not None and ex.startTime is not None else 0.0)
        stop = args.stop_time if args.stop_time is not None else (
            float(ex.stopTime) if ex is not None and ex.stopTime is not None else start + 1.0)
        if not (math.isfinite(stop) and stop > start):
            raise SpecError(f"--stop-time {stop} must be after the start time {start}")
        interval = args.output_interval if args.output_interval is not None else default_output_interval(md, start, stop)
        if not (math.isfinite(interval) and interval > 0):
            raise SpecError(f"--output-interval {interval} must be > 0")
        tol = args.tolerance if args.tolerance is not None else (
            float(ex.tolerance) if ex is not None and ex.tolerance is not None else None)
        if tol is not None and not tol > 0:
            raise SpecError(f"--tolerance {tol} must be > 0")
        return start, stop, interval, tol

    def _summaries(self, variables) -> list[Summary]:
        """The final value of every output, then the chosen ones (``--summary``)."""
        summaries = [Summary("final", v.name) for v in self.md.modelVariables if v.causality == "output"]
        for text in self.args.summary:
            s = parse_summary(text)
            v = variables.get(s.var)
            if v is None:
                raise SpecError(f"--summary {text}: {self.model} has no variable `{s.var}`"
                                f"{_close_names(s.var, list(variables))}")
            if v.type != "Real":
                raise SpecError(f"--summary {text}: `{s.var}` is not a Real variable")
            if s not in summaries:
                summaries.append(s)
        return summaries

    def _check_cluster_and_plot(self) -> None:
        """The options that name the cluster's size and the plot's axes."""
        args = self.args
        if args.workers is not None and args.scheduler:
            raise SpecError("--workers sizes the local cluster; with --scheduler the cluster is given")
        if args.plot_x is not None and args.plot_x not in self.design.columns:
            raise SpecError(f"--plot-x {args.plot_x}: not a design column ({', '.join(self.design.columns)})")
        if args.plot_y is not None and args.plot_y not in self.setup.result_columns:
            raise SpecError(f"--plot-y {args.plot_y}: not a summary column ({', '.join(self.setup.result_columns)})")

    def _read_csv(self, path: Path, variables) -> np.ndarray:
        from fmpy.util import read_csv

        if not path.is_file():
            raise SpecError(f"--input {path}: no such file")
        try:
            table = read_csv(str(path))
        except Exception as e:  # noqa: BLE001
            raise SpecError(f"--input {path}: not an fmpy-style CSV (time, then one column per input): {e}") from None
        cols = table.dtype.names
        if len(cols) < 2:
            raise SpecError(f"--input {path}: no input columns after the time column")
        t = table[cols[0]]
        if np.any(np.diff(t) < 0):
            raise SpecError(f"--input {path}: the time column ({cols[0]}) must not decrease")
        for c in cols[1:]:
            v = variables.get(c)
            if v is None or not (v.causality == "input" or v.variability == "tunable"):
                raise SpecError(f"--input {path}: column `{c}` is not an input of {self.model}"
                                f"{_close_names(c, list(variables))}")
        return table

    def metadata(self, fmu_sha: str) -> dict[str, Any]:
        a = self.args
        return {
            "fmu": str(a.fmu), "fmu_sha256": fmu_sha, "model": self.model,
            "params": a.param, "input_schedules": a.input_schedule,
            "input": str(a.input) if a.input else None, "summaries": a.summary,
            "cases": len(self.design), "seed": self.design.seed,
            "start_time": self.setup.start_time, "stop_time": self.setup.stop_time,
            "output_interval": self.setup.output_interval, "tolerance": self.setup.tolerance,
        }


# ---------------------------------------------------------------------------------------
# Results


def choose_engine(args: argparse.Namespace, plan: Plan) -> tuple[str, str | None]:
    """The engine that runs the cases, and a note when it is not the one the user would
    expect."""
    from .native import unavailable

    if args.engine == "fmpy":
        return "fmpy", None
    if args.engine is None and args.scheduler:
        return "fmpy", "an existing cluster runs the FMPy engine (--engine native needs `mechfmu` on its workers)"
    reason = unavailable(args.fmu, plan.setup)
    if reason is None:
        return "native", None
    if args.engine == "native":
        raise SpecError(f"--engine native: {reason}")
    return "fmpy", f"the FMPy engine runs the cases: the native one cannot ({reason})"


# ---------------------------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> int:
    parser = make_parser()
    args = parser.parse_args(argv)
    try:
        plan = Plan(args)
    except SpecError as e:
        print(f"mechfmu sweep: error: {e}", file=sys.stderr)
        return 2

    from .engine import run_on_dask

    try:
        engine, note = choose_engine(args, plan)
    except SpecError as e:
        print(f"mechfmu sweep: error: {e}", file=sys.stderr)
        return 2
    try:
        fmu_bytes = args.fmu.read_bytes()
    except OSError as e:
        print(f"mechfmu sweep: error: cannot read {args.fmu}: {e}", file=sys.stderr)
        return 1
    sha = hashlib.sha256(fmu_bytes).hexdigest()
    meta = plan.metadata(sha)
    meta["engine"] = engine
    n = len(plan.design)
    seed_note = f", seed {plan.design.seed}" if plan.design.seed is not None else ""
    progress = not args.no_progress
    if progress:
        print(f"sweep {plan.model}: {n} cases ({', '.join(f'{s.name}={s.text}' for s in plan.specs)}{seed_note}), "
              f"t = {plan.setup.start_time:g}..{plan.setup.stop_time:g} s every {plan.setup.output_interval:g} s, "
              f"{engine} engine", file=sys.stderr)
    if note:
        print(f"  note: {note}", file=sys.stderr)
    t0 = time.perf_counter()
    try:
        writer = ResultsWriter(plan.design, plan.setup.result_columns, meta, args.out, keep=args.plot is not None)
        run = run_on_dask(fmu_bytes, plan.setup, plan.design, scheduler=args.scheduler, workers=args.workers,
                          chunk_size=args.chunk_size, progress=progress, engine=engine, on_rows=writer.add)
    except KeyboardInterrupt:
        print("mechfmu sweep: interrupted; the results are incomplete", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - the machinery failed: say so, exit 1
        print(f"mechfmu sweep: error: the sweep could not run: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    meta.update(workers=run.workers, chunk_size=run.chunk_size, wall_s=run.wall_s, scheduler=run.address,
                shipped_package=run.shipped_package)
    try:
        table = writer.close(meta)
        if args.plot is not None:
            from .plot import plot_sweep

            plot_sweep(table, plan, args.plot, x=args.plot_x, y=args.plot_y)
    except Exception as e:  # noqa: BLE001
        print(f"mechfmu sweep: error: cannot write the results: {type(e).__name__}: {e}", file=sys.stderr)
        return 1

    counts = writer.counts
    total = time.perf_counter() - t0
    print(f"swept {n} cases in {run.wall_s:.2f} s ({n / max(run.wall_s, 1e-9):.1f} cases/s) on {run.workers} "
          f"worker{'s' if run.workers != 1 else ''} ({total:.1f} s with the cluster's start): "
          + ", ".join(f"{k} {v}" for k, v in counts.items()), file=sys.stderr)
    for r in writer.failed:
        case = plan.design.case(r["case"])
        print(f"  case {r['case']} ({', '.join(f'{k}={v:g}' for k, v in case.items())}): {r['status']}: "
              f"{r['message']}", file=sys.stderr)
    if writer.n_failed > len(writer.failed):
        print(f"  ... and {writer.n_failed - len(writer.failed)} more failed cases (see the status column)",
              file=sys.stderr)
    for e in run.errors[:3]:
        print(f"  note: {e}", file=sys.stderr)
    where = f" to {args.out}" if args.out else ""
    if args.out or args.plot:
        print(f"wrote{where}{' and ' + str(args.plot) if args.plot else ''}", file=sys.stderr)
    return 0
