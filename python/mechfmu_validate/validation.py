"""The rows of one FMU: what ``mechfmu validate`` runs for each FMU it is given (:mod:`.cli`
parses the command line, prints the table and writes the report).

An FMU, FMI 2.0 or 3.0 (a :class:`~.target.Target`, the version a value): its checks
(:mod:`.checks`), then each reference case under each importer of the registry
(:mod:`.importers`) that runs its FMI version, in Co-Simulation and then in Model Exchange:
first the reference importer against the case's reference, then the others against it. An
FMI 2.0 FMU whose FMI 3.0 FMU was built beside it (``<dir>/fmi3/<Name>.fmu``) brings that one
along: its checks, the agreement of the two in Co-Simulation (:func:`~.target.agreement_row`)
and each case under its importers; an FMI 3.0 FMU given alone gets its own rows and that
agreement with the FMI 2.0 FMU beside it. The reference results the FMU carries and those
beside it (:mod:`.embedded_reference`, :mod:`.cross_check`) run under the importers too, the
reference importer's run also judged by FMPy's cross-check criterion
(:mod:`.fmpy_criterion`). An FMU against which nothing was simulated (no case, no reference)
fails, saying so.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterator

from . import cross_check, embedded_reference
from .arrays import MappingError
from .case import Case, describe
from .checks import run_checks
from .importer import CS, FMI2, FMI3, ME, CaseRun, Selection, row_name
from .importers import IMPORTERS, PLATFORMS, REFERENCE
from .importers.fmpy import model_exchange_run
from .loader import load_cases, reference_case
from .opening import OPENS, BrokenFmu
from .platform_rows import Platforms
from .progress import report
from .rows import Row
from .signals import real_signals, unknown_names
from .target import Target, agreement_row

__all__ = ["validate_fmu"]


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


def _check_rows(name: str, checks) -> Iterator[Row]:
    """Each check's row, made as the check is (lazily: each row takes its own console output)."""
    for c in checks:
        yield Row(kind="check", fmu=name, case=f"check: {c.name}",
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


def _entry(name: str, case: Case, target: Target) -> dict[str, Any]:
    """The case's plot (its verdict the rows' made in it, :func:`_append`)."""
    anchor = f"{name}-{case.name}".replace(" ", "-")
    units = _units(target.fmu.md, target.mapping) if target.version == FMI2 or target.mapping is not None else {}
    entry = dict(fmu=name, case=case.name, anchor=anchor, description=case.description, settings=_settings(case),
                 highlight=case.highlight, plot=list(case.plot),
                 units={**units, **{d: "derived" for d in case.derived}}, deviations={})
    if target.version == FMI3:
        entry["label"] = f"{REFERENCE.name} FMI 3.0 CS"
    return entry


def _append(rows: list[Row], entry: dict, made) -> None:
    """Rows appended to ``rows`` one by one, as ``made`` gives them (the sink of an isolated
    validation gives each the console output written while it was made), and to ``entry``'s
    verdict."""
    for row in made:
        rows.append(row)
        entry["passed"] = entry.get("passed", True) and row["passed"]


def _broken_row(path: Path, problem: str, name: str | None = None) -> Row:
    """The one row of an FMU that cannot be opened (:mod:`.opening`)."""
    return Row(kind="check", fmu=name or path.name, case=OPENS, importer="mechfmu", max_error=1.0, tolerance=0.0,
                passed=False, problems=[f"{path}: {problem}"], notes=[])


def _note_row(name: str, text: str) -> Row:
    return Row(kind="note", fmu=name, case=text, importer="-", max_error=None, tolerance=None, passed=True,
                problems=[], notes=[])


def _load_cases(cases_file: Path | None, name: str, rows: list[Row]) -> list[Case]:
    """The cases of the FMU's cases file; a file that does not load is a FAIL row."""
    if cases_file is None:
        return []
    try:
        return load_cases(cases_file, name)
    except Exception as e:  # noqa: BLE001 (the user's file: a row, not a crash)
        rows.append(_note_row(name, f"check: {cases_file} loads").but(kind="check", importer="mechfmu",
                         max_error=1.0, tolerance=0.0, passed=False, problems=[f"{type(e).__name__}: {e}"]))
        return []


def _unknown_row(fmu, case: Case, cases_file: Path | None, unknown: list[str]) -> Row:
    return Row(kind="case", fmu=fmu.model, case=case.name, importer="FMPy", max_error=None, tolerance=None,
                passed=False, notes=[], problems=[
                    f"the case {case.name!r} of {cases_file} names {', '.join(unknown)}, which "
                    f"{fmu.path.name} does not have (not a variable of its modelDescription.xml)"])


def _nothing_simulated_row(path: Path, name: str, why: str | None = None) -> Row:
    """The FAIL row of an FMU against which nothing was simulated (only its checks ran, or
    nothing ran): ``why``, by default that it has no reference that could be run."""
    why = why or (f"{path} has no reference that could be run: no validation/cases.py (--cases), and no "
                  f"reference results in {embedded_reference.REFERENCE_DIR}/ of the archive or {path.stem}_ref.csv "
                  "beside it that mechfmu validate can run (a SKIP row says why one cannot be); only the checks ran")
    return _note_row(name, "(nothing simulated)").but(kind="check", importer="mechfmu", passed=False,
                problems=[f"nothing simulated: {why}"])


def _case_rows(run: CaseRun, selection: Selection, rows: list[Row], entry: dict) -> None:
    """The case's rows under every importer selected that runs the FMU's version, Co-Simulation
    first (the reference importer's first of all), appended to ``rows`` and to ``entry``'s
    verdict."""
    for interface in (CS, ME) if selection.model_exchange else (CS,):
        for importer in IMPORTERS:
            if selection.uses(importer) and importer.runs.covers(interface, run.version):
                _append(rows, entry, importer.case_rows(run, interface))


def _reference_rows(target: Target, selection: Selection, rows: list[Row], plots: list[dict] | None,
                    others: bool) -> bool:
    """Each reference of the FMU (the one it carries, :mod:`.embedded_reference`, and the
    files beside it, :mod:`.cross_check`) under the reference importer (plotted when ``plots``
    is given), judged by FMPy's cross-check criterion too, and under the other importers
    selected when ``others``; False when none was simulated."""
    found = False
    for files, note in cross_check.sources(target.fmu):
        found = _reference_source_rows(target, files, note, selection, rows, plots, others) or found
    return found


def _reference_source_rows(target: Target, files: embedded_reference.Files | None, note: str | None,
                           selection: Selection, rows: list[Row], plots: list[dict] | None, others: bool) -> bool:
    """The rows of one reference (``files``; None: the one the FMU carries), see
    :func:`_reference_rows`; False when there is none, or one that cannot be simulated (its
    SKIP row says why)."""
    name = target.fmu.model
    case_name = files.case_name if files is not None else embedded_reference.CASE_NAME
    failed = _note_row(name, case_name).but(kind="reference", importer=row_name(REFERENCE.name, target.version, CS))
    try:
        ref = embedded_reference.read(target.fmu, target.names if target.version == FMI3 else None, files)
    except embedded_reference.Unsupported as e:
        rows.append(failed.but(skipped=True, problems=[str(e)]))
        return False
    except (embedded_reference.ReferenceProblem, MappingError) as e:
        rows.append(failed.but(max_error=None, passed=False, problems=[str(e)]))
        return True
    if ref is None:
        return False
    case = ref.case
    entry = _entry(name, case, target)
    run = CaseRun(target, case, entry["anchor"] if plots is not None else "", "reference", ref.problems, entry,
                  entry["deviations"] if target.version == FMI2 else None,
                  progress=lambda what: _progress(f"{name}: {case.name} ({what})"))
    [row] = REFERENCE.case_rows(run, CS)
    row["notes"] = [*row["notes"], *ref.notes, *([note] if note else [])]
    rows.append(row)
    entry["passed"] = row["passed"]
    me_importer, me_run = model_exchange_run(target)
    me = (me_importer, me_run if selection.model_exchange else None)
    rows.extend(cross_check.criterion_rows(target.fmu, ref, row, run.reference, row["importer"], me))
    real, why = real_signals(case, target.fmu)
    for importer in IMPORTERS if others else ():
        if importer.reference or not (selection.uses(importer) and importer.runs.covers(CS, target.version)):
            continue
        if real is None:
            rows.append(failed.but(importer=row_name(importer.name, target.version, CS), skipped=True,
                             problems=[why]))
            continue
        for other in importer.case_rows(CaseRun(target, real, run.anchor, "reference", [], None, run.deviations,
                                                run.reference, run.evaluation, run.progress), CS):
            other["notes"] = [*other["notes"], *([why] if why else [])]
            _append(rows, entry, [other])
    if plots is not None and run.evaluation is not None and run.evaluation.signals:
        plots.append(entry)
    return True


def _open_sibling(target: Target, selection: Selection, rows: list[Row]) -> Target | None:
    """The same mechanism's FMU in the other version, when it was built beside this one (an
    FMI 3.0 FMU beside an FMI 2.0 one only when ``selection.fmi3``); a FAIL row when it cannot
    be opened."""
    path = target.sibling()
    if path is None or (target.version == FMI2 and not selection.fmi3):
        return None
    try:
        return Target.open(path)
    except BrokenFmu as e:
        rows.append(_broken_row(path, str(e), target.fmu.model))
        return None


def validate_fmu(path: Path, cases_file: Path | None, only: list[str], selection: Selection,
                 rows: list[Row], plots: list[dict], details: list[dict]) -> None:
    """An FMU's rows, and those of the FMI 3.0 FMU beside an FMI 2.0 one (see the module's
    documentation). An FMU that cannot be opened is one FAIL row saying why; one without
    Co-Simulation (or of FMI 1.0) a SKIP row saying so and the FAIL row of nothing simulated."""
    why = cross_check.not_validated(path)
    if why is not None:
        rows.append(cross_check.skip_row(path, why))
        rows.append(_nothing_simulated_row(path, path.stem, f"{path} is not validated (the SKIP row says why)"))
        return
    try:
        target = Target.open(path)
    except BrokenFmu as e:
        rows.append(_broken_row(path, str(e)))
        return
    name = target.fmu.model
    sibling = None
    try:
        sibling = _open_sibling(target, selection, rows)
        # the FMUs validated: this one, and the FMI 3.0 one beside an FMI 2.0 one
        targets = [target, *([sibling] if sibling is not None and target.version == FMI2 else [])]
        cases = _load_cases(cases_file, name, rows)
        selected = [c for c in cases if not only or any(o in c.name for o in only)]
        _progress(f"{name}: checks" + (" (FMI 3.0)" if target.version == FMI3 else ""))
        for t in targets:
            rows.extend(_check_rows(name, run_checks(t, reference_case(cases))))
        if sibling is not None:
            fmi3, fmi2 = (sibling, target) if target.version == FMI2 else (target, sibling)
            rows.append(agreement_row(fmi3, fmi2.fmu))
        binaries = [Platforms(t.fmu, name, PLATFORMS, names=t.mapping, enabled=selection.uses(PLATFORMS))
                    for t in targets]
        rows.extend(b.summary_row() for b in binaries)
        # the reference the FMU carries: beside a mechanism's cases, a cheap extra row under FMPy
        # (its default-experiment case already runs under every importer, and is plotted); alone,
        # under each importer, plotted
        alone = cases_file is None
        if not _reference_rows(target, selection, rows, plots if alone else None, alone) and not selected:
            rows.append(_nothing_simulated_row(target.fmu.path, name))
        for case in selected:
            if target.version == FMI2:
                unknown = unknown_names(case, target.fmu)
                if unknown:
                    rows.append(_unknown_row(target.fmu, case, cases_file, unknown))
                    continue
            entry = _entry(name, case, target)
            for t in targets:
                own = t is target
                run = CaseRun(t, case, entry["anchor"], plot=entry if own else None,
                              deviations=entry["deviations"] if own and t.version == FMI2 else None,
                              progress=lambda what: _progress(f"{name}: {case.name} ({what})"))
                _case_rows(run, selection, rows, entry)
            for b, t in zip(binaries, targets):
                _progress(f"{name}: {case.name} ({b.label} on other platforms)")
                _append(rows, entry, b.case_rows(t.fmu, case))
            if entry.get("evaluation") is not None and entry["evaluation"].signals:
                plots.append(entry)
            details.append(dict(fmu=name, **describe(case)))
    finally:
        target.cleanup()
        if sibling is not None:
            sibling.cleanup()
        _progress("")
