"""The rows of one FMU: what ``mechfmu validate`` runs for each FMU it is given (:mod:`.cli`
parses the command line, prints the table and writes the report).

An FMI 2.0 FMU: the checks (:mod:`.checks`), then each reference case under FMPy (against
its reference), libcosim and the fmi crate (each against FMPy), in Model Exchange
(:mod:`.model_exchange`); and when its FMI 3.0 FMU was built beside it
(``<dir>/fmi3/<Name>.fmu``), that one's checks (:mod:`.checks3`), the agreement of the two
in Co-Simulation, and each case under the FMI 3.0 importers (:mod:`.fmi3`). An FMI 3.0 FMU
given alone: :func:`validate_fmi3`. The reference results the FMU carries and those beside
it (:mod:`.embedded_reference`, :mod:`.cross_check`) run under FMPy, each also judged by FMPy's
cross-check criterion (:mod:`.fmpy_criterion`). An FMU against which nothing was simulated
(no case, no reference) fails, saying so.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterator

from . import cross_check, cs_rows, embedded_reference, fmi3, model_exchange
from .arrays import MappingError, fmi2_sibling, fmi3_sibling
from .case import Case, describe
from .checks import run_checks
from .checks3 import run_checks3
from .cs_rows import FMI_CRATE
from .importers import Fmu, run_fmpy_me
from .loader import load_cases, reference_case
from .opening import OPENS, BrokenFmu, open_fmu
from .platform_rows import Platforms
from .progress import report

__all__ = ["validate_fmu", "validate_fmi3"]


def _progress(msg: str) -> None:
    report(msg)


def _settings(case: Case) -> str:
    parts = [f"stop {case.stop_time:g} s", f"output interval {case.output_interval:g} s",
             "relative tolerance " + ("DefaultExperiment" if case.relative_tolerance is None
                                      else f"{case.relative_tolerance:g}")]
    if case.start_values:
        parts.append("start values " + ", ".join(f"{k}={v:g}" for k, v in case.start_values.items()))
    if case.input is not None:
        parts.append("input table " + ", ".join(case.input_table().dtype.names[1:]))
    return "; ".join(parts)


def _check_rows(name: str, checks) -> Iterator[dict]:
    """Each check's row, made as the check is (lazily: each row takes its own console output)."""
    for c in checks:
        yield dict(kind="check", fmu=name, case=f"check: {c.name}",
                   importer="fmpy" if c.name.endswith("fmpy validate") else "mechfmu",
                   max_error=float(len(c.problems)) if c.max_error is None else c.max_error,
                   tolerance=0.0 if c.tolerance is None else c.tolerance,
                   passed=c.passed, problems=c.problems, notes=c.notes)


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


def _append(rows: list[dict], entry: dict, made) -> None:
    """Rows appended to ``rows`` one by one, as ``made`` gives them (the sink of an isolated
    validation gives each the console output written while it was made), and to ``entry``'s
    verdict."""
    for row in made:
        rows.append(row)
        entry["passed"] = entry.get("passed", True) and row["passed"]


def _fmi3_rows(f3, case: Case, entry: dict, rows: list[dict], use_fmi_crate: bool, use_model_exchange: bool) -> tuple:
    """The case's FMI 3.0 rows, appended to ``rows`` and to ``entry``'s verdict: FMPy's FMI 3.0
    result and its evaluation."""
    return fmi3.case_rows(f3, case, lambda row: _append(rows, entry, [row]), entry["anchor"], use_fmi_crate,
                          use_model_exchange, lambda what: _progress(f"{entry['fmu']}: {case.name} ({what})"))


def _broken_row(path: Path, problem: str, name: str | None = None) -> dict:
    """The one row of an FMU that cannot be opened (:mod:`.opening`)."""
    return dict(kind="check", fmu=name or path.name, case=OPENS, importer="mechfmu", max_error=1.0, tolerance=0.0,
                passed=False, problems=[f"{path}: {problem}"], notes=[])


def _note_row(name: str, text: str) -> dict:
    return dict(kind="note", fmu=name, case=text, importer="-", max_error=None, tolerance=None, passed=True,
                problems=[], notes=[])


def _load_cases(cases_file: Path | None, name: str, rows: list[dict]) -> list[Case]:
    """The cases of the FMU's cases file; a file that does not load is a FAIL row."""
    if cases_file is None:
        return []
    try:
        return load_cases(cases_file, name)
    except Exception as e:  # noqa: BLE001 (the user's file: a row, not a crash)
        rows.append(dict(_note_row(name, f"check: {cases_file} loads"), kind="check", importer="mechfmu",
                         max_error=1.0, tolerance=0.0, passed=False, problems=[f"{type(e).__name__}: {e}"]))
        return []


def _unknown_row(fmu: Fmu, case: Case, cases_file: Path | None, unknown: list[str]) -> dict:
    return dict(kind="case", fmu=fmu.model, case=case.name, importer="FMPy", max_error=None, tolerance=None,
                passed=False, notes=[], problems=[
                    f"the case {case.name!r} of {cases_file} names {', '.join(unknown)}, which "
                    f"{fmu.path.name} does not have (not a variable of its modelDescription.xml)"])


def _nothing_simulated_row(path: Path, name: str, why: str | None = None) -> dict:
    """The FAIL row of an FMU against which nothing was simulated (only its checks ran, or
    nothing ran): ``why``, by default that it has no reference that could be run."""
    why = why or (f"{path} has no reference that could be run: no validation/cases.py (--cases), and no "
                  f"reference results in {embedded_reference.REFERENCE_DIR}/ of the archive or {path.stem}_ref.csv "
                  "beside it that mechfmu validate can run (a SKIP row says why one cannot be); only the checks ran")
    return dict(_note_row(name, "(nothing simulated)"), kind="check", importer="mechfmu", passed=False,
                problems=[f"nothing simulated: {why}"])


def _reference_rows(fmu: Fmu, rows: list[dict], plots: list[dict] | None, use_libcosim: bool,
                    use_fmi_crate: bool, use_model_exchange: bool = True) -> bool:
    """Each reference of the FMU (the one it carries, :mod:`.embedded_reference`, and the
    files beside it, :mod:`.cross_check`) under FMPy (plotted when ``plots`` is given), judged
    by FMPy's cross-check criterion too, and under libcosim and the fmi crate when
    ``use_libcosim``/``use_fmi_crate``; False when none was simulated."""
    found = False
    for files, note in cross_check.sources(fmu):
        found = _reference_source_rows(fmu, files, note, rows, plots, use_libcosim, use_fmi_crate,
                                       use_model_exchange) or found
    return found


def _reference_source_rows(fmu: Fmu, files: embedded_reference.Files | None, note: str | None, rows: list[dict],
                           plots: list[dict] | None, use_libcosim: bool, use_fmi_crate: bool,
                           use_model_exchange: bool) -> bool:
    """The rows of one reference (``files``; None: the one the FMU carries), see
    :func:`_reference_rows`; False when there is none, or one that cannot be simulated (its
    SKIP row says why)."""
    name = fmu.model
    case_name = files.case_name if files is not None else embedded_reference.CASE_NAME
    try:
        ref = embedded_reference.read(fmu, files=files)
    except embedded_reference.Unsupported as e:
        rows.append(dict(_note_row(name, case_name), kind="reference", importer="FMPy", skipped=True,
                         problems=[str(e)]))
        return False
    except embedded_reference.ReferenceProblem as e:
        rows.append(dict(_note_row(name, case_name), kind="reference", importer="FMPy", max_error=None,
                         passed=False, problems=[str(e)]))
        return True
    if ref is None:
        return False
    case = ref.case
    _progress(f"{name}: {case.name} (FMPy)")
    entry = _entry(name, case, _units(fmu.md))
    anchor = entry["anchor"] if plots is not None else ""
    row, result, ev = cs_rows.fmpy_row(fmu, case, anchor, kind="reference", problems=ref.problems)
    row["notes"] = [*row["notes"], *ref.notes, *([note] if note else [])]
    rows.append(row)
    entry.update(evaluation=ev, result=result, passed=row["passed"])
    me = (model_exchange.CVODE, lambda c: run_fmpy_me(fmu, c, "CVode")) if use_model_exchange else None
    rows.extend(cross_check.criterion_rows(fmu, ref, row, result, "FMPy", me))
    runs = [("libcosim", cs_rows.libcosim_row)] if use_libcosim else []
    runs += [(FMI_CRATE, cs_rows.fmi_crate_row)] if use_fmi_crate else []
    real, why = cs_rows.real_signals(case, fmu)
    for importer, run in runs:
        _progress(f"{name}: {case.name} ({importer})")
        if real is None:
            rows.append(dict(_note_row(name, case.name), kind="reference", importer=importer, skipped=True,
                             problems=[why]))
            continue
        other, plotted = run(fmu, real, result, ev, anchor, kind="reference")
        if why:
            other["notes"] = [*other["notes"], why]
        rows.append(other)
        if plotted is not None:
            entry["libcosim" if importer == "libcosim" else "fmi_crate"] = plotted
        entry["passed"] = entry["passed"] and other["passed"]
    if plots is not None and ev is not None and ev.signals:
        plots.append(entry)
    return True


def validate_fmu(path: Path, cases_file: Path | None, only: list[str], use_libcosim: bool,
                 rows: list[dict], plots: list[dict], details: list[dict], use_fmi_crate: bool = True,
                 use_model_exchange: bool = True, use_fmi3: bool = True) -> None:
    """An FMI 2.0 FMU's rows, and its FMI 3.0 FMU's (``<dir>/fmi3/<Name>.fmu``, when built and
    ``use_fmi3``); an FMI 3.0 FMU given alone: :func:`validate_fmi3`. An FMU that cannot be
    opened is one FAIL row saying why; one without Co-Simulation (or of FMI 1.0) a SKIP row
    saying so and the FAIL row of nothing simulated."""
    why = cross_check.not_validated(path)
    if why is not None:
        rows.append(cross_check.skip_row(path, why))
        rows.append(_nothing_simulated_row(path, path.stem, f"{path} is not validated (the SKIP row says why)"))
        return
    try:
        fmu = open_fmu(path)
    except BrokenFmu as e:
        rows.append(_broken_row(path, str(e)))
        return
    if fmu.fmi3:
        fmu.cleanup()
        return validate_fmi3(path, cases_file, only, rows, plots, details, use_fmi_crate, use_model_exchange)
    name = fmu.model
    f3 = None
    try:
        if use_fmi3 and fmi3_sibling(fmu.path) is not None:
            try:
                f3 = fmi3.Fmi3.open(fmi3_sibling(fmu.path))
            except BrokenFmu as e:
                rows.append(_broken_row(fmi3_sibling(fmu.path), str(e), name))
        cases = _load_cases(cases_file, name, rows)
        selected = [c for c in cases if not only or any(o in c.name for o in only)]
        _progress(f"{name}: checks")
        rows.extend(_check_rows(name, run_checks(fmu, reference_case(cases))))
        if f3 is not None:
            rows.extend(_check_rows(name, run_checks3(f3)))
            rows.append(fmi3.agreement_row(f3, fmu))
        binaries = [Platforms(fmu, name, FMI_CRATE, enabled=use_fmi_crate)]
        if f3 is not None:
            binaries.append(Platforms(f3.fmu, name, fmi3.FMI3_CRATE, names=f3.mapping, enabled=use_fmi_crate))
        rows.extend(b.summary_row() for b in binaries)
        # the reference the FMU carries: beside a mechanism's cases, a cheap extra row under FMPy
        # (its default-experiment case already runs under every importer, and is plotted); alone,
        # under each importer, plotted
        alone = cases_file is None
        if not _reference_rows(fmu, rows, plots if alone else None, use_libcosim and alone, use_fmi_crate and alone,
                               use_model_exchange) and not selected:
            rows.append(_nothing_simulated_row(fmu.path, name))
        units = _units(fmu.md)
        for case in selected:
            unknown = cs_rows.unknown_names(case, fmu)
            if unknown:
                rows.append(_unknown_row(fmu, case, cases_file, unknown))
                continue
            _progress(f"{name}: {case.name} (FMPy)")
            entry = _entry(name, case, units)
            anchor = entry["anchor"]
            row, fmpy_result, ev = cs_rows.fmpy_row(fmu, case, anchor)
            rows.append(row)
            entry.update(evaluation=ev, result=fmpy_result, passed=row["passed"])
            for importer, run, key, wanted in (("libcosim", cs_rows.libcosim_row, "libcosim", use_libcosim),
                                               (FMI_CRATE, cs_rows.fmi_crate_row, "fmi_crate", use_fmi_crate)):
                if wanted:
                    _progress(f"{name}: {case.name} ({importer})")
                    other, plotted = run(fmu, case, fmpy_result, ev, anchor)
                    rows.append(other)
                    if plotted is not None:
                        entry[key] = plotted
                    entry["passed"] = entry["passed"] and other["passed"]
            if use_model_exchange:
                for me_row in model_exchange.rows(fmu, case, anchor, entry, use_fmi_crate,
                                                  lambda what: _progress(f"{name}: {case.name} ({what})")):
                    rows.append(me_row)
                    entry["passed"] = entry["passed"] and me_row["passed"]
            if f3 is not None:
                _fmi3_rows(f3, case, entry, rows, use_fmi_crate, use_model_exchange)
            for b, platform_fmu in zip(binaries, [fmu, f3.fmu if f3 is not None else None]):
                _progress(f"{name}: {case.name} ({b.label} on other platforms)")
                _append(rows, entry, b.case_rows(platform_fmu, case))
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
    try:
        f3 = fmi3.Fmi3.open(path)
    except BrokenFmu as e:
        rows.append(_broken_row(path, str(e)))
        return
    name = f3.fmu.model
    fmu2 = None
    try:
        sibling = fmi2_sibling(path)
        if sibling is not None:
            try:
                fmu2 = open_fmu(sibling)
            except BrokenFmu as e:
                rows.append(_broken_row(sibling, str(e), name))
        cases = _load_cases(cases_file, name, rows)
        selected = [c for c in cases if not only or any(o in c.name for o in only)]
        _progress(f"{name}: checks (FMI 3.0)")
        rows.extend(_check_rows(name, run_checks3(f3)))
        if fmu2 is not None:
            rows.append(fmi3.agreement_row(f3, fmu2))
        binaries = Platforms(f3.fmu, name, fmi3.FMI3_CRATE, names=f3.mapping, enabled=use_fmi_crate)
        rows.append(binaries.summary_row())
        alone = cases_file is None
        if not _reference_rows3(f3, rows, plots if alone else None, use_fmi_crate and alone, use_model_exchange) \
                and not selected:
            rows.append(_nothing_simulated_row(f3.fmu.path, name))
        units = _units(f3.fmu.md, f3.mapping) if f3.mapping is not None else {}
        for case in selected:
            entry = dict(_entry(name, case, units), label="FMPy FMI 3.0 CS")
            result, ev = _fmi3_rows(f3, case, entry, rows, use_fmi_crate, use_model_exchange)
            _append(rows, entry, binaries.case_rows(f3.fmu, case))
            entry.update(evaluation=ev, result=result)
            if ev is not None and ev.signals:
                plots.append(entry)
            details.append(dict(fmu=name, **describe(case)))
    finally:
        f3.cleanup()
        if fmu2 is not None:
            fmu2.cleanup()
        _progress("")


def _reference_rows3(f3: fmi3.Fmi3, rows: list[dict], plots: list[dict] | None, use_fmi_crate: bool,
                     use_model_exchange: bool = True) -> bool:
    """Each reference of an FMI 3.0 FMU (the one it carries and the files beside it), under
    FMPy's FMI 3.0 Co-Simulation (plotted when ``plots`` is given), judged by FMPy's
    cross-check criterion too, and the fmi crate's run against it when ``use_fmi_crate``;
    False when none was simulated."""
    found = False
    for files, note in cross_check.sources(f3.fmu):
        found = _reference_source_rows3(f3, files, note, rows, plots, use_fmi_crate, use_model_exchange) or found
    return found


def _reference_source_rows3(f3: fmi3.Fmi3, files: embedded_reference.Files | None, note: str | None,
                            rows: list[dict], plots: list[dict] | None, use_fmi_crate: bool,
                            use_model_exchange: bool) -> bool:
    """The rows of one reference of an FMI 3.0 FMU (``files``; None: the one it carries), see
    :func:`_reference_rows3`; False when there is none, or one that cannot be simulated."""
    name = f3.fmu.model
    case_name = files.case_name if files is not None else embedded_reference.CASE_NAME
    failed = dict(_note_row(name, case_name), kind="reference", importer=fmi3.FMI3_CS)
    try:
        ref = embedded_reference.read(f3.fmu, f3.names, files)
    except embedded_reference.Unsupported as e:
        rows.append(dict(failed, skipped=True, problems=[str(e)]))
        return False
    except (embedded_reference.ReferenceProblem, MappingError) as e:
        rows.append(dict(failed, max_error=None, passed=False, problems=[str(e)]))
        return True
    if ref is None:
        return False
    _progress(f"{name}: {ref.case.name} ({fmi3.FMI3_CS})")
    entry = dict(_entry(name, ref.case, _units(f3.fmu.md, f3.mapping)), label="FMPy FMI 3.0 CS")
    anchor = entry["anchor"] if plots is not None else ""
    row, result, ev = fmi3.cs_row(f3, ref.case, anchor)
    row.update(kind="reference", notes=[*row["notes"], *ref.notes, *([note] if note else [])],
               problems=[*ref.problems, *row["problems"]], passed=row["passed"] and not ref.problems)
    rows.append(row)
    me = (fmi3.FMI3_CVODE, lambda c: fmi3.run_fmpy3_me(f3, c, "CVode")) if use_model_exchange else None
    rows.extend(cross_check.criterion_rows(f3.fmu, ref, row, result, fmi3.FMI3_CS, me))
    if plots is not None and ev is not None and ev.signals:
        plots.append(dict(entry, evaluation=ev, result=result, passed=row["passed"]))
    if use_fmi_crate:
        real, why = cs_rows.real_signals(ref.case, f3.fmu)
        if real is None:
            rows.append(dict(failed, importer=fmi3.FMI3_CRATE, skipped=True, problems=[why]))
        else:
            crate = fmi3.crate_row(f3, real, result, ev, anchor)
            crate.update(kind="reference", notes=[*crate["notes"], *([why] if why else [])])
            rows.append(crate)
    return True
