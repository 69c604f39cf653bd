"""Every mechanism's reference cases (fmus/*/validation/cases.py), under FMPy and libcosim.

One definition, two uses: these are the cases `mechfmu validate` runs. Each case runs its
FMU under FMPy's simulate_fmu and compares the outputs with the case's independent
reference (closed forms, invariants, DOP853 at rtol 1e-12) to the case's tolerance; the same
case under libcosim must agree with FMPy to 1e-9 (relative) at the same settings. Also: the
FMUs pass the model-description, binary and GUID checks, and the reference results committed
under fmus/<crate>/reference/ (packaged into each FMU) are current.
"""

from __future__ import annotations

import dataclasses
import zipfile
from pathlib import Path

import numpy as np
import pytest

import fmutest

from mechfmu_validate.agreement import agreement
from mechfmu_validate.case import evaluate, signal_scale
from mechfmu_validate.checks import REFERENCE_CSV_TOLERANCE, REFERENCE_DIR, read_csv, run_checks
from mechfmu_validate.importers.fmpy import run_fmpy
from mechfmu_validate.importers.libcosim import LIBCOSIM_TOLERANCE, libcosim_available, run_libcosim
from mechfmu_validate.target import Target
from mechfmu_validate.loader import default_case, load_cases, reference_case
from mechfmu_validate.reference import reference_table
from mechanisms import mechanisms

REPO = fmutest.REPO_ROOT


CRATES: list[tuple[str, Path]] = [(m.model, m.crate) for m in mechanisms()]
CASES = [(model, case) for model, d in CRATES if (d / "validation/cases.py").is_file()
         for case in load_cases(d / "validation/cases.py", model)]
MODELS = [m for m, _ in CRATES]

fmu_of = fmutest.validation_fmu


def _ids(p):
    return f"{p[0]}-{p[1].name}"


def test_every_mechanism_declares_reference_cases():
    assert len(CRATES) >= 6, f"mechanism crates found: {CRATES}"
    for model, d in CRATES:
        path = d / "validation/cases.py"
        assert path.is_file(), f"{model}: no {path.relative_to(REPO)}"
        cases = load_cases(path, model)
        assert len(cases) >= 3, f"{model}: only {len(cases)} cases"
        assert default_case(cases) is not None, f"{model}: no case is marked default_experiment"


@pytest.mark.parametrize("model, case", CASES, ids=[_ids(p) for p in CASES])
def test_case_under_fmpy(model, case):
    fmu = fmu_of(model)
    ev = evaluate(case, run_fmpy(fmu, case))
    assert ev.problem is None, ev.problem
    failed = [f"{s.name}: {s.max_error:.3e} of scale {s.scale:.4g} at t = {s.at_time:g} (tolerance {s.tolerance:g})"
              for s in ev.signals if not s.passed]
    assert not failed, f"{model} / {case.name}:\n" + "\n".join(failed)


def test_a_run_that_fails_says_why_the_fmu_refused_it():
    """FMPy's exception names the FMI call that failed; the FMU's log says why. The row of a
    failed run carries both (here the Oscillator refusing a mass that is not > 0)."""
    case = next(c for m, c in CASES if m == "Oscillator")
    refused = dataclasses.replace(case, start_values={**case.start_values, "m": -1.0})
    with pytest.raises(Exception) as failure:
        run_fmpy(fmu_of("Oscillator"), refused)
    text = str(failure.value)
    assert "the FMU logged:" in text and "m = -1" in text, text


@pytest.mark.parametrize("model, case", CASES, ids=[_ids(p) for p in CASES])
def test_case_under_libcosim_agrees_with_fmpy(model, case):
    ok, why = libcosim_available()
    assert ok, f"libcosimpy does not run here: {why}"
    fmu = fmu_of(model)
    # libcosim sets up the experiment without a tolerance: compare at the FMU's default one
    same = run_fmpy(fmu, case, relative_tolerance=None)
    lc = run_libcosim(fmu, case)
    assert np.allclose(lc.time, same.time, rtol=0, atol=1e-12)
    # signals that stay at zero are compared on the case's scale (absolute), as the CLI does
    floors = {s.name: s.scale for s in evaluate(case, same).signals}
    worst, name, t, _ = agreement(lc, same, case.recorded(), floors)
    assert worst <= LIBCOSIM_TOLERANCE, f"libcosim differs from FMPy by {worst:.2e} (relative) in {name} at t = {t:g}"


@pytest.mark.parametrize("model", MODELS)
def test_checks_pass(model):
    fmu = fmu_of(model)
    cases = load_cases(dict(CRATES)[model] / "validation/cases.py", model)
    failed = [f"{c.name}: {p}" for c in run_checks(Target(fmu), reference_case(cases)) for p in c.problems]
    assert not failed, "\n".join(failed)


@pytest.mark.parametrize("model", MODELS)
def test_committed_references_are_current_and_packaged(model):
    """fmus/<crate>/reference/<Id>_ref.csv equals what the reference case's reference gives
    now (to 1e-9 of each signal's scale: the file keeps 13 digits), and the FMU carries
    exactly the committed files."""
    d = dict(CRATES)[model]
    fmu = fmu_of(model)
    case = reference_case(load_cases(d / "validation/cases.py", model))
    committed = d / "reference" / f"{model}_ref.csv"
    assert committed.is_file(), f"{committed} missing: run `cargo run --release -- validate --write-references {model}`"
    names, table = read_csv(committed.read_text())
    want_names, want_cols = reference_table(fmu, case)
    assert names == want_names
    for j, n in enumerate(names[1:], start=1):
        err = np.max(np.abs(table[:, j] - want_cols[j])) / signal_scale(want_cols[j])
        assert err <= REFERENCE_CSV_TOLERANCE, \
            f"{committed.name}: {n} differs by {err:.2e} of scale: regenerate the references"
    with zipfile.ZipFile(fmu.path) as z:
        for suffix in ("_ref.csv", "_in.csv", "_ref.opt"):
            name = f"{model}{suffix}"
            if suffix == "_in.csv" and not (d / "reference" / name).is_file():
                # an FMU without inputs has no input file, packaged or committed
                assert f"{REFERENCE_DIR}/{name}" not in z.namelist() and not fmu.inputs()
                continue
            packaged = z.read(f"{REFERENCE_DIR}/{name}")
            assert packaged == (d / "reference" / name).read_bytes(), \
                f"the FMU's {name} is not the committed one: rebuild with `cargo run --release -- build {model}`"
        html = z.read("documentation/index.html").decode()
        assert f"<h1>{model}</h1>" in html and "<svg" in html
