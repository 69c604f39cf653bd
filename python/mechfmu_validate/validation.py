"""The rows of one FMU: what ``mechfmu validate`` runs for each FMU it is given (:mod:`.cli`
parses the command line, prints the table and writes the report).

An FMI 2.0 FMU: the checks (:mod:`.checks`), then each reference case under FMPy (against
its reference), libcosim and the fmi crate (each against FMPy), in Model Exchange
(:mod:`.model_exchange`); and when its FMI 3.0 FMU was built beside it
(``<dir>/fmi3/<Name>.fmu``), that one's checks (:mod:`.checks3`), the agreement of the two
in Co-Simulation, and each case under the FMI 3.0 importers (:mod:`.fmi3`). An FMI 3.0 FMU
given alone: :func:`validate_fmi3`.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import Any

from . import fmi3, model_exchange
from .arrays import fmi2_sibling
from .case import Case, describe, evaluate
from .checks import run_checks
from .checks3 import run_checks3
from .importers import (FMI_CRATE_NOTE, LIBCOSIM_NOTE, Fmu, agreement, run_fmi_crate, run_fmpy, run_libcosim)
from .loader import default_case, load_cases
from .platform_rows import Platforms

__all__ = ["LIBCOSIM_TOLERANCE", "FMI_CRATE_TOLERANCE", "FMI_CRATE", "validate_fmu", "validate_fmi3"]

#: libcosim must agree with FMPy to this, relative (max |a - b| / max |b|), at the same settings
LIBCOSIM_TOLERANCE = 1e-9

#: the fmi crate must agree with FMPy to this, relative, both at the case's tolerance
FMI_CRATE_TOLERANCE = 1e-9

#: the importer column of the fmi crate's rows
FMI_CRATE = "fmi crate"


def _progress(msg: str) -> None:
    if sys.stderr.isatty():
        sys.stderr.write(f"\r\033[K{msg}")
        sys.stderr.flush()


def _settings(case: Case) -> str:
    parts = [f"stop {case.stop_time:g} s", f"output interval {case.output_interval:g} s",
             "relative tolerance " + ("DefaultExperiment" if case.relative_tolerance is None
                                      else f"{case.relative_tolerance:g}")]
    if case.start_values:
        parts.append("start values " + ", ".join(f"{k}={v:g}" for k, v in case.start_values.items()))
    if case.input is not None:
        parts.append("input table " + ", ".join(case.input_table().dtype.names[1:]))
    return "; ".join(parts)


def _check_rows(name: str, checks) -> list[dict]:
    return [dict(kind="check", fmu=name, case=f"check: {c.name}",
                 importer="fmpy" if c.name.endswith("fmpy validate") else "mechfmu",
                 max_error=float(len(c.problems)) if c.max_error is None else c.max_error,
                 tolerance=0.0 if c.tolerance is None else c.tolerance,
                 passed=c.passed, problems=c.problems, notes=c.notes) for c in checks]


def _units(md, names=None) -> dict[str, str]:
    """Each variable's unit (an FMI 3.0 array's for each of its FMI 2.0 elements, by ``names``)."""
    units = {}
    for v in md.modelVariables:
        u = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
        units[v.name] = u or ""
    if names is not None:
        for a, scalars in names.elements.items():
            units.update({s: units.get(a, "") for s in scalars})
    return units


def _entry(name: str, case: Case, units: dict[str, str]) -> dict[str, Any]:
    anchor = f"{name}-{case.name}".replace(" ", "-")
    return dict(fmu=name, case=case.name, anchor=anchor, description=case.description, settings=_settings(case),
                highlight=case.highlight, plot=list(case.plot), units={**units, **{d: "derived" for d in case.derived}})


def _fmi3_rows(f3, case: Case, entry: dict, rows: list[dict], use_fmi_crate: bool, use_model_exchange: bool) -> tuple:
    """The case's FMI 3.0 rows, appended to ``rows`` and to ``entry``'s verdict."""
    out = fmi3.case_rows(f3, case, entry["anchor"], use_fmi_crate, use_model_exchange,
                         lambda what: _progress(f"{entry['fmu']}: {case.name} ({what})"))
    rows.extend(out[0])
    entry["passed"] = entry.get("passed", True) and all(r["passed"] for r in out[0])
    return out


def validate_fmu(path: Path, cases_file: Path | None, only: list[str], use_libcosim: bool,
                 rows: list[dict], plots: list[dict], details: list[dict], use_fmi_crate: bool = True,
                 use_model_exchange: bool = True, use_fmi3: bool = True) -> None:
    """An FMI 2.0 FMU's rows, and its FMI 3.0 FMU's (``<dir>/fmi3/<Name>.fmu``, when built and
    ``use_fmi3``); an FMI 3.0 FMU given alone: :func:`validate_fmi3`."""
    fmu = Fmu(path)
    if fmu.fmi3:
        fmu.cleanup()
        return validate_fmi3(path, cases_file, only, rows, plots, details, use_fmi_crate, use_model_exchange)
    name = fmu.model
    f3 = None
    try:
        f3 = fmi3.Fmi3.beside(fmu) if use_fmi3 else None
        cases: list[Case] = load_cases(cases_file, name) if cases_file else []
        selected = [c for c in cases if not only or any(o in c.name for o in only)]
        _progress(f"{name}: checks")
        rows.extend(_check_rows(name, run_checks(fmu, default_case(cases))))
        if f3 is not None:
            rows.extend(_check_rows(name, run_checks3(f3)))
            rows.append(fmi3.agreement_row(f3, fmu))
        binaries = [Platforms(path, name, FMI_CRATE, enabled=use_fmi_crate)]
        if f3 is not None:
            binaries.append(Platforms(f3.fmu.path, name, fmi3.FMI3_CRATE, names=f3.mapping, enabled=use_fmi_crate))
        rows.extend(b.summary_row() for b in binaries)
        if cases_file is None:
            rows.append(dict(kind="note", fmu=name, case="(no validation/cases.py: no reference cases)",
                             importer="-", max_error=None, tolerance=None, passed=True, problems=[], notes=[]))
        units = _units(fmu.md)
        for case in selected:
            _progress(f"{name}: {case.name} (FMPy)")
            entry = _entry(name, case, units)
            anchor = entry["anchor"]
            t0 = time.perf_counter()
            fmpy_result = None
            try:
                fmpy_result = run_fmpy(fmu, case)
                ev = evaluate(case, fmpy_result)
            except Exception as e:
                ev = None
                problem = f"FMPy run failed: {type(e).__name__}: {e}"
            if ev is not None:
                problem = ev.problem
                worst = ev.worst
                rows.append(dict(kind="case", fmu=name, case=case.name, importer="FMPy", anchor=anchor,
                                 max_error=None if worst is None else worst.max_error,
                                 tolerance=None if worst is None else worst.tolerance,
                                 passed=ev.passed, problems=[problem] if problem else [],
                                 notes=[f"worst signal {worst.name} at t = {worst.at_time:g}"] if worst else [],
                                 signals={s.name: dict(max_error=s.max_error, at_time=s.at_time, scale=s.scale,
                                                       tolerance=s.tolerance, passed=s.passed) for s in ev.signals},
                                 seconds=time.perf_counter() - t0,
                                 log=fmpy_result.log[-20:] if fmpy_result else []))
            else:
                rows.append(dict(kind="case", fmu=name, case=case.name, importer="FMPy", anchor=anchor,
                                 max_error=math.inf, tolerance=None, passed=False, problems=[problem], notes=[]))
            entry["evaluation"] = ev
            entry["result"] = fmpy_result
            entry["passed"] = ev is not None and ev.passed
            if use_libcosim:
                _progress(f"{name}: {case.name} (libcosim)")
                lc_row = dict(kind="case", fmu=name, case=case.name, importer="libcosim", anchor=anchor,
                              tolerance=LIBCOSIM_TOLERANCE, problems=[], notes=[LIBCOSIM_NOTE])
                try:
                    same = fmpy_result if (case.relative_tolerance is None and fmpy_result is not None) \
                        else run_fmpy(fmu, case, relative_tolerance=None)
                    lc = run_libcosim(fmu, case)
                    floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
                    worst, where, when, over_time = agreement(lc, same, case.recorded(), floors)
                    lc_row.update(max_error=worst, passed=bool(worst <= LIBCOSIM_TOLERANCE),
                                  notes=[f"worst signal {where} at t = {when:g}", LIBCOSIM_NOTE])
                    entry["libcosim"] = dict(time=lc.time, error_over_time=over_time, tolerance=LIBCOSIM_TOLERANCE,
                                             max_error=worst)
                except Exception as e:
                    lc_row.update(max_error=math.inf, passed=False,
                                  problems=[f"libcosim run failed: {type(e).__name__}: {e}"])
                rows.append(lc_row)
                entry["passed"] = entry["passed"] and lc_row["passed"]
            if use_fmi_crate:
                _progress(f"{name}: {case.name} (fmi crate)")
                fc_row = dict(kind="case", fmu=name, case=case.name, importer=FMI_CRATE, anchor=anchor,
                              tolerance=FMI_CRATE_TOLERANCE, problems=[], notes=[FMI_CRATE_NOTE])
                t1 = time.perf_counter()
                try:
                    fc = run_fmi_crate(fmu, case)
                    if fmpy_result is None:
                        raise RuntimeError("the FMPy run failed: nothing to compare with")
                    floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
                    worst, where, when, over_time = agreement(fc, fmpy_result, case.recorded(), floors)
                    fc_row.update(max_error=worst, passed=bool(worst <= FMI_CRATE_TOLERANCE),
                                  notes=[f"worst signal {where} at t = {when:g}", FMI_CRATE_NOTE],
                                  seconds=time.perf_counter() - t1, log=fc.log[-20:])
                    entry["fmi_crate"] = dict(time=fc.time, error_over_time=over_time,
                                              tolerance=FMI_CRATE_TOLERANCE, max_error=worst)
                except Exception as e:
                    fc_row.update(max_error=math.inf, passed=False,
                                  problems=[f"fmi crate run failed: {type(e).__name__}: {e}"])
                rows.append(fc_row)
                entry["passed"] = entry["passed"] and fc_row["passed"]
            if use_model_exchange:
                for me_row in model_exchange.rows(fmu, case, anchor, entry, use_fmi_crate,
                                                  lambda what: _progress(f"{name}: {case.name} ({what})")):
                    rows.append(me_row)
                    entry["passed"] = entry["passed"] and me_row["passed"]
            if f3 is not None:
                _fmi3_rows(f3, case, entry, rows, use_fmi_crate, use_model_exchange)
            for b, platform_fmu in zip(binaries, [fmu, f3.fmu if f3 is not None else None]):
                _progress(f"{name}: {case.name} ({b.label} on other platforms)")
                platform_rows = b.case_rows(platform_fmu, case)
                rows.extend(platform_rows)
                entry["passed"] = entry["passed"] and all(r["passed"] for r in platform_rows)
            if ev is not None and ev.signals:
                plots.append(entry)
            details.append(dict(fmu=name, **describe(case)))
    finally:
        fmu.cleanup()
        if f3 is not None:
            f3.cleanup()
        _progress("")


def validate_fmi3(path: Path, cases_file: Path | None, only: list[str], rows: list[dict], plots: list[dict],
                  details: list[dict], use_fmi_crate: bool = True, use_model_exchange: bool = True) -> None:
    """An FMI 3.0 FMU given alone: its checks, the agreement with the FMI 2.0 FMU beside it
    (``<dir>/../<Name>.fmu``) if there is one, and the cases under the FMI 3.0 importers
    (FMPy's Co-Simulation being the plotted run)."""
    sibling = fmi2_sibling(path)
    fmu2 = Fmu(sibling) if sibling is not None else None
    f3 = fmi3.Fmi3.open(path)
    name = f3.fmu.model
    try:
        cases: list[Case] = load_cases(cases_file, name) if cases_file else []
        selected = [c for c in cases if not only or any(o in c.name for o in only)]
        _progress(f"{name}: checks (FMI 3.0)")
        rows.extend(_check_rows(name, run_checks3(f3)))
        if fmu2 is not None:
            rows.append(fmi3.agreement_row(f3, fmu2))
        binaries = Platforms(path, name, fmi3.FMI3_CRATE, names=f3.mapping, enabled=use_fmi_crate)
        rows.append(binaries.summary_row())
        if cases_file is None:
            rows.append(dict(kind="note", fmu=name, case="(no validation/cases.py: no reference cases)",
                             importer="-", max_error=None, tolerance=None, passed=True, problems=[], notes=[]))
        units = _units(f3.fmu.md, f3.mapping) if f3.mapping is not None else {}
        for case in selected:
            entry = dict(_entry(name, case, units), label="FMPy FMI 3.0 CS")
            _, result, ev = _fmi3_rows(f3, case, entry, rows, use_fmi_crate, use_model_exchange)
            rows.extend(binaries.case_rows(f3.fmu, case))
            entry.update(evaluation=ev, result=result)
            if ev is not None and ev.signals:
                plots.append(entry)
            details.append(dict(fmu=name, **describe(case)))
    finally:
        f3.cleanup()
        if fmu2 is not None:
            fmu2.cleanup()
        _progress("")
