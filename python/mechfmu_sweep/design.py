"""The design of a sweep: parameter specs, input schedules and the table of cases.

Specs (``--param NAME=SPEC``)::

    5                  a constant
    2:10:17            a grid: 17 points from 2 to 10, ends included (numpy.linspace)
    2,3,5              a list
    uniform(800,1200)  random, drawn per case
    normal(0,0.1)      random (mu, sigma)
    loguniform(1,100)  random, uniform in log(value)

Grids, lists and constants are crossed in a full factorial (the first ``--param`` varies
slowest); random specs are drawn ``cases`` times at each grid point, from one
``numpy.random.default_rng(seed)`` in the order the random parameters are given.

This module is the one implementation of this grammar: ``mechfmu sweep`` (Rust) passes its
arguments through, and a ``SpecError`` raised here is the message the user sees.

Input schedules (``--input-schedule NAME=SHAPE(args)``) give a per-case time signal to an
input of the FMU as a piecewise-linear table (the form ``fmpy.simulate_fmu(input=...)``
takes). Their arguments are design variables named ``NAME.arg`` that ``--param`` sweeps
like any other, e.g. ``--input-schedule "x_ddot=bangbang(t0=1,width=2,value=0.5)"
--param x_ddot.value=0.1:1:10``. Every scheduled input, and every input read from the
``--input`` CSV, also has ``NAME.scale`` (default 1), a factor on the whole signal.
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np


class SpecError(ValueError):
    """A spec, schedule or option the user wrote is wrong; the message says how."""


# ---------------------------------------------------------------------------------------
# Parameter specs

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_RE_GRID = re.compile(rf"^\s*({_NUMBER})\s*:\s*({_NUMBER})\s*:\s*(\d+)\s*$")
_RE_CALL = re.compile(r"^\s*([A-Za-z_]\w*)\s*\((.*)\)\s*$")
RANDOM_KINDS = ("uniform", "normal", "loguniform")


def _number(text: str, what: str) -> float:
    text = text.strip()
    try:
        value = float(text)
    except ValueError:
        raise SpecError(f"{what}: `{text}` is not a number") from None
    if not math.isfinite(value):
        raise SpecError(f"{what}: `{text}` is not a number (a finite value is needed)")
    return value


@dataclass(frozen=True)
class Spec:
    """One design variable: fixed ``values`` (grid, list, constant) or a ``random`` law."""

    name: str
    text: str
    values: tuple[float, ...] = ()
    random: tuple[str, float, float] | None = None  # (kind, a, b)

    @property
    def is_random(self) -> bool:
        return self.random is not None

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        kind, a, b = self.random  # type: ignore[misc]
        if kind == "uniform":
            return rng.uniform(a, b, n)
        if kind == "normal":
            return rng.normal(a, b, n)
        return np.exp(rng.uniform(math.log(a), math.log(b), n))  # loguniform


def parse_spec(name: str, text: str) -> Spec:
    """``parse_spec('l', '2:10:17')`` -> a Spec; raises SpecError naming the problem."""
    what = f"--param {name}={text}"
    if not text.strip():
        raise SpecError(f"{what}: empty spec (want a value, a:b:n, v1,v2,..., uniform(a,b) or normal(mu,sigma))")
    m = _RE_CALL.match(text)
    if m:
        kind, args = m.group(1), m.group(2)
        if kind not in RANDOM_KINDS:
            raise SpecError(f"{what}: unknown distribution `{kind}` (known: {', '.join(RANDOM_KINDS)})")
        parts = args.split(",")
        if len(parts) != 2:
            raise SpecError(f"{what}: {kind} takes 2 arguments, got {len(parts)}")
        a, b = (_number(p, what) for p in parts)
        if kind == "uniform" and not a < b:
            raise SpecError(f"{what}: uniform(a,b) needs a < b")
        if kind == "normal" and not b > 0:
            raise SpecError(f"{what}: normal(mu,sigma) needs sigma > 0")
        if kind == "loguniform" and not 0 < a < b:
            raise SpecError(f"{what}: loguniform(a,b) needs 0 < a < b")
        return Spec(name, text, random=(kind, a, b))
    m = _RE_GRID.match(text)
    if m:
        a, b, n = _number(m.group(1), what), _number(m.group(2), what), int(m.group(3))
        if n < 1:
            raise SpecError(f"{what}: a grid is start:stop:count (a:b:n) and needs n >= 1 points, e.g. 2:10:17")
        if n == 1 and a != b:
            raise SpecError(f"{what}: a grid of 1 point needs a == b (or write the value alone)")
        return Spec(name, text, values=tuple(float(v) for v in np.linspace(a, b, n)))
    if ":" in text:
        raise SpecError(f"{what}: a grid is start:stop:count, e.g. 2:10:17 (count an integer >= 1)")
    values = tuple(_number(p, what) for p in text.split(","))
    return Spec(name, text, values=values)


def split_assignment(text: str, option: str, form: str = "NAME=SPEC") -> tuple[str, str]:
    """``'l=2:10:17'`` -> ``('l', '2:10:17')``."""
    name, sep, rest = text.partition("=")
    if not sep or not name.strip():
        raise SpecError(f"{option} {text}: expected {form}")
    return name.strip(), rest.strip()


def parse_param(text: str) -> Spec:
    """``parse_param('l=2:10:17')``: one ``--param NAME=SPEC``; raises SpecError naming the problem."""
    name, spec = split_assignment(text, "--param", "NAME=SPEC, e.g. l=2:10:17")
    return parse_spec(name, spec)


# ---------------------------------------------------------------------------------------
# Input schedules


@dataclass(frozen=True)
class Shape:
    name: str
    args: tuple[str, ...]
    defaults: tuple[float, ...]
    doc: str


SHAPES: dict[str, Shape] = {
    s.name: s
    for s in (
        Shape("constant", ("value",), (0.0,), "value throughout"),
        Shape("step", ("t0", "value"), (0.0, 1.0), "0 before t0, value from t0 on"),
        Shape("pulse", ("t0", "width", "value"), (0.0, 1.0, 1.0), "value on [t0, t0+width), 0 elsewhere"),
        Shape(
            "bangbang",
            ("t0", "width", "value"),
            (0.0, 1.0, 1.0),
            "+value on [t0, t0+width), -value on [t0+width, t0+2 width), 0 elsewhere "
            "(an acceleration that moves by value*width^2 and stops)",
        ),
        Shape("ramp", ("t0", "t1", "value"), (0.0, 1.0, 1.0), "0 up to t0, linear to value at t1, then value"),
    )
}


def breakpoints(shape: str, args: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """The piecewise-linear table of a shape: (t, v), a repeated t for a jump.

    These tables are what the FMU is given (fmpy interpolates linearly between points and
    holds the first and last values outside them); the README lists them so that a test
    or another tool can rebuild the same input exactly.
    """
    a = args
    if shape == "constant":
        return np.array([0.0]), np.array([a["value"]])
    if shape == "step":
        t0, v = a["t0"], a["value"]
        return np.array([t0, t0]), np.array([0.0, v])
    if shape == "pulse":
        t0, w, v = a["t0"], a["width"], a["value"]
        return np.array([t0, t0, t0 + w, t0 + w]), np.array([0.0, v, v, 0.0])
    if shape == "bangbang":
        t0, w, v = a["t0"], a["width"], a["value"]
        t1, t2 = t0 + w, t0 + 2 * w
        return np.array([t0, t0, t1, t1, t2, t2]), np.array([0.0, v, v, -v, -v, 0.0])
    if shape == "ramp":
        t0, t1, v = a["t0"], a["t1"], a["value"]
        return np.array([t0, t1]), np.array([0.0, v])
    raise SpecError(f"unknown shape {shape}")


def _check_shape_args(shape: str, args: dict[str, float], what: str) -> None:
    if shape in ("pulse", "bangbang") and not args["width"] > 0:
        raise SpecError(f"{what}: width must be > 0 (got {args['width']})")
    if shape == "ramp" and not args["t1"] > args["t0"]:
        raise SpecError(f"{what}: ramp needs t1 > t0 (got t0={args['t0']}, t1={args['t1']})")


@dataclass(frozen=True)
class Schedule:
    """``--input-schedule x_ddot=bangbang(t0=1,width=2,value=0.5)``."""

    input: str
    shape: str
    args: dict[str, float] = field(default_factory=dict)

    def table(self, overrides: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
        args = {k: overrides.get(k, v) for k, v in self.args.items()}
        _check_shape_args(self.shape, args, f"--input-schedule {self.input}")
        t, v = breakpoints(self.shape, args)
        if len(t) > 1:
            # A lead-in point 1 s before the first breakpoint: fmpy holds a table's first
            # row at its own time even when the table jumps there, which would delay a
            # step at t0 by one communication interval.
            t, v = np.concatenate([[t[0] - 1.0], t]), np.concatenate([[v[0]], v])
        return t, v * overrides.get("scale", 1.0)


def parse_schedule(text: str) -> Schedule:
    name, rest = split_assignment(text, "--input-schedule", "NAME=SHAPE(args), e.g. x_ddot=step(1,0.5)")
    what = f"--input-schedule {text}"
    m = _RE_CALL.match(rest)
    if not m:
        raise SpecError(f"{what}: expected NAME=SHAPE(args), shapes: {', '.join(SHAPES)}")
    kind, argtext = m.group(1), m.group(2)
    shape = SHAPES.get(kind)
    if shape is None:
        raise SpecError(f"{what}: unknown shape `{kind}` (known: {', '.join(SHAPES)})")
    values = dict(zip(shape.args, shape.defaults))
    parts = [p.strip() for p in argtext.split(",")] if argtext.strip() else []
    if len(parts) > len(shape.args):
        raise SpecError(f"{what}: {kind} takes at most {len(shape.args)} arguments ({', '.join(shape.args)})")
    seen_keyword = False
    for i, part in enumerate(parts):
        key, sep, val = part.partition("=")
        if sep:
            key = key.strip()
            if key not in shape.args:
                raise SpecError(f"{what}: {kind} has no argument `{key}` (it has {', '.join(shape.args)})")
            seen_keyword = True
        else:
            if seen_keyword:
                raise SpecError(f"{what}: a positional argument after a keyword one")
            key, val = shape.args[i], part
        values[key] = _number(val, what)
    _check_shape_args(kind, values, what)
    return Schedule(name, kind, values)


# ---------------------------------------------------------------------------------------
# Combining piecewise-linear signals into one fmpy input table


def _limits(t: np.ndarray, v: np.ndarray, tau: float) -> tuple[float, float]:
    """(left, right) values of a piecewise-linear signal at tau (held outside its range)."""
    lo = int(np.searchsorted(t, tau, side="left"))
    hi = int(np.searchsorted(t, tau, side="right"))
    if hi > lo:  # tau is a breakpoint: left = first, right = last of the group
        return float(v[lo]), float(v[hi - 1])
    if lo == 0:
        return float(v[0]), float(v[0])
    if lo == len(t):
        return float(v[-1]), float(v[-1])
    t0, t1, v0, v1 = t[lo - 1], t[lo], v[lo - 1], v[lo]
    w0 = (t1 - tau) / (t1 - t0)
    x = float(w0 * v0 + (1 - w0) * v1)
    return x, x


def input_table(signals: dict[str, tuple[np.ndarray, np.ndarray]]) -> np.ndarray | None:
    """One structured array (``time`` + one column per signal) for ``simulate_fmu(input=)``.

    A single signal is returned as its own table, untouched (so that the FMU sees exactly
    the values that table gives). Several are merged on the union of their breakpoints,
    with two rows (left and right limits) where any of them jumps.
    """
    if not signals:
        return None
    names = list(signals)
    dtype = [("time", np.float64)] + [(n, np.float64) for n in names]
    if len(signals) == 1:
        t, v = signals[names[0]]
        arr = np.empty(len(t), dtype=dtype)
        arr["time"], arr[names[0]] = t, v
        return arr
    times = np.unique(np.concatenate([s[0] for s in signals.values()]))
    rows = []
    for tau in times:
        lim = [_limits(t, v, tau) for t, v in signals.values()]
        jump = any(
            int(np.searchsorted(t, tau, "right") - np.searchsorted(t, tau, "left")) > 1 for t, _ in signals.values()
        )
        rows.append((tau, *(left for left, _ in lim)))
        if jump:
            rows.append((tau, *(right for _, right in lim)))
    return np.array(rows, dtype=dtype)


def scaled(table: np.ndarray, name: str, factor: float) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(table["time"], dtype=float)
    return t, np.asarray(table[name], dtype=float) * factor


# ---------------------------------------------------------------------------------------
# The table of cases


@dataclass
class Design:
    """The cases: ``columns`` (design variable names) and ``values[case, column]``."""

    columns: list[str]
    values: np.ndarray  # shape (n_cases, n_columns)
    seed: int | None

    def __len__(self) -> int:
        return self.values.shape[0]

    def case(self, i: int) -> dict[str, float]:
        return {c: float(v) for c, v in zip(self.columns, self.values[i])}


def build_design(specs: Sequence[Spec], cases: int | None, seed: int | None) -> Design:
    """Full factorial of the fixed specs, times ``cases`` random draws at each grid point."""
    names = [s.name for s in specs]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise SpecError(f"--param given twice for {', '.join(dupes)}")
    fixed = [s for s in specs if not s.is_random]
    random = [s for s in specs if s.is_random]
    if not random and cases is not None:
        raise SpecError("--cases sets the number of random draws, but no --param is random "
                        "(uniform/normal/loguniform); a grid's size is the product of its axes")
    n_draw = (cases if cases is not None else 100) if random else 1
    if n_draw < 1:
        raise SpecError("--cases must be >= 1")
    grid = list(itertools.product(*(s.values for s in fixed))) if fixed else [()]
    n = len(grid) * n_draw
    values = np.empty((n, len(specs)))
    col = {s.name: j for j, s in enumerate(specs)}
    for k, s in enumerate(fixed):
        values[:, col[s.name]] = np.repeat([g[k] for g in grid], n_draw)
    if random:
        rng = np.random.default_rng(seed)
        for s in random:
            values[:, col[s.name]] = s.draw(rng, n)
    return Design(columns=names, values=values, seed=seed if random else None)


def describe(specs: Iterable[Spec]) -> str:
    return " × ".join(f"{s.name} ({s.text})" for s in specs)
