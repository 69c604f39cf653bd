"""The reference files every FMU ships (``extra/org.fmi-standard.fmi-ls-ref/``, committed
under fmus/<crate>/reference/) pass FMPy's cross-check criterion,
``fmpy.cross_check.validate_result``, when the FMU runs as an importer runs the cross-check:
the settings of ``<Id>_ref.opt`` (StopTime, RelTol, OutputIntervalLength), the inputs of
``<Id>_in.csv``, no start values, the reference's columns recorded.

The importers: FMPy in Co-Simulation, FMPy in Model Exchange with CVode, and libcosim (which
passes fmi2SetupExperiment no tolerance: the FMU integrates at its own default one). The
FMI 3.0 FMUs carry the same files, an array's element named as the element (``w[1]``): FMPy
runs them in both interfaces, and each element's column is held to the criterion.

The files also keep the rules that give the criterion a meaning: at most 10 variables, each
an output of the FMU (the cross-check reads the reference against the outputs), only inputs
in ``_in.csv``, something that moves, and no invariant written with its solver's round-off
(a column whose range is within 1e-6 of its value): the criterion's band is 10 % of a
signal's range, or of its value when it is constant, so such a column would leave a band no
importer stays in.
"""

from __future__ import annotations

import re
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.cross_check import validate_result
from fmpy.util import read_csv, read_ref_opt_file

import fmutest

from mechfmu_validate.case import CONSTANT, Case
from mechfmu_validate.embedded_reference import REFERENCE_DIR
from mechfmu_validate.fmu import Fmu
from mechfmu_validate.importers.libcosim import libcosim_available, run_libcosim
from mechfmu_validate.reference import MAX_COLUMNS, write_references
from mechanisms import mechanisms


# FMPy's criterion imports its filters from scipy's deprecated namespace
pytestmark = pytest.mark.filterwarnings("ignore:Please import:DeprecationWarning")

MODELS = [m.model for m in mechanisms() if (m.crate / "reference").is_dir()]
IMPORTERS = ["FMPy CS", "FMPy ME CVode", "libcosim"]
FMI3_IMPORTERS = ["FMPy CS", "FMPy ME CVode"]
ELEMENT = re.compile(r"^(?P<array>[^\[]+)\[(?P<index>[0-9, ]+)\]$")


class Shipped:
    """An FMU and the reference files it carries, read as FMPy's cross-check reads them."""

    def __init__(self, path: Path, directory: Path):
        self.path = path
        with zipfile.ZipFile(path) as z:
            names = set(z.namelist())
            for suffix in ("_ref.csv", "_in.csv", "_ref.opt"):
                name = f"{REFERENCE_DIR}/{path.stem}{suffix}"
                if name in names:
                    z.extract(name, directory)
        files = directory / REFERENCE_DIR
        self.reference = read_csv(files / f"{path.stem}_ref.csv")
        self.options = read_ref_opt_file(files / f"{path.stem}_ref.opt")
        inputs = files / f"{path.stem}_in.csv"
        self.inputs = read_csv(inputs) if inputs.is_file() else None
        self.md = fmpy.read_model_description(str(path), validate=False)

    @property
    def columns(self) -> list[str]:
        return list(self.reference.dtype.names[1:])

    @property
    def interval(self) -> float:
        return self.options.get("OutputIntervalLength") or self.options["StepSize"]

    def verdict(self, result: np.ndarray) -> str | None:
        return validate_result(result, self.reference, self.options["StartTime"], self.options["StopTime"])


_shipped: dict[Path, Shipped] = {}


@pytest.fixture(scope="module")
def shipped(tmp_path_factory):
    def get(path: Path) -> Shipped:
        if path not in _shipped:
            _shipped[path] = Shipped(path, tmp_path_factory.mktemp(path.stem))
        return _shipped[path]

    yield get
    _shipped.clear()


def _fmpy(s: Shipped, interface: str, inputs: np.ndarray | None, output: list[str]) -> np.ndarray:
    """``simulate_fmu`` as FMPy's cross-check calls it, with the options file's tolerance and
    output interval."""
    return fmpy.simulate_fmu(str(s.path), validate=False, fmi_type=interface, solver="CVode",
                             start_time=s.options["StartTime"], stop_time=s.options["StopTime"],
                             relative_tolerance=s.options["RelTol"], output_interval=s.interval,
                             input=inputs, output=output)


def _libcosim(s: Shipped) -> np.ndarray:
    ok, why = libcosim_available()
    assert ok, f"libcosimpy does not run here: {why}"
    case = Case("cross-check", stop_time=s.options["StopTime"], output_interval=s.interval, outputs=s.columns,
                reference=lambda t: {}, input=s.inputs)
    with Fmu(s.path) as fmu:
        run = run_libcosim(fmu, case)
    table = np.zeros(len(run.time), dtype=[(n, np.float64) for n in ["time", *s.columns]])
    for name in table.dtype.names:
        table[name] = run[name]
    return table


def _arrays(names: list[str]) -> dict[str, tuple[int, ...]]:
    """The arrays whose elements some of ``names`` are, with their shapes (the largest index
    of each dimension: the files write every element)."""
    shapes: dict[str, tuple[int, ...]] = {}
    for name in names:
        m = ELEMENT.match(name)
        if m:
            index = tuple(int(i) for i in m["index"].split(","))
            old = shapes.get(m["array"], (0,) * len(index))
            shapes[m["array"]] = tuple(max(a, b) for a, b in zip(old, index))
    return shapes


def _element(name: str, shapes: dict[str, tuple[int, ...]]) -> tuple[str, int] | None:
    """(array, row-major index) of an element's column; None for a scalar's."""
    m = ELEMENT.match(name)
    if m is None:
        return None
    index = tuple(int(i) - 1 for i in m["index"].split(","))
    return m["array"], int(np.ravel_multi_index(index, shapes[m["array"]]))


def _fmi3_inputs(table: np.ndarray | None) -> np.ndarray | None:
    """The inputs file with an array's element columns gathered into the array (FMPy sets an
    FMI 3.0 array input from one field)."""
    if table is None:
        return None
    names = list(table.dtype.names[1:])
    shapes = _arrays(names)
    scalars = [n for n in names if _element(n, shapes) is None]
    fields = [("time", np.float64), *[(n, np.float64) for n in scalars],
              *[(a, np.float64, (int(np.prod(shape)),)) for a, shape in shapes.items()]]
    out = np.zeros(len(table), dtype=fields)
    for n in ["time", *scalars]:
        out[n] = table[n]
    for n in names:
        element = _element(n, shapes)
        if element is not None:
            out[element[0]][:, element[1]] = table[n]
    return out


def _fmi3(s: Shipped, interface: str) -> np.ndarray:
    """An FMI 3.0 run recording the reference's arrays whole, then split into the columns the
    reference names."""
    shapes = _arrays(s.columns)
    elements = {n: _element(n, shapes) for n in s.columns}
    recorded = list(dict.fromkeys(e[0] if e else n for n, e in elements.items()))
    result = _fmpy(s, interface, _fmi3_inputs(s.inputs), recorded)
    table = np.zeros(len(result), dtype=[(n, np.float64) for n in ["time", *s.columns]])
    table["time"] = result["time"]
    for n, element in elements.items():
        if element is None:
            table[n] = result[n]
        else:
            array, k = element
            table[n] = np.asarray(result[array]).reshape(len(result), -1)[:, k]
    return table


def _run(s: Shipped, importer: str) -> np.ndarray:
    if importer == "libcosim":
        return _libcosim(s)
    interface = "CoSimulation" if importer == "FMPy CS" else "ModelExchange"
    return _fmpy(s, interface, s.inputs, s.columns)


@pytest.mark.parametrize("importer", IMPORTERS)
@pytest.mark.parametrize("model", MODELS)
def test_reference_passes_fmpy_criterion(model, importer, shipped):
    s = shipped(fmutest.fmu_path(model))
    verdict = s.verdict(_run(s, importer))
    assert verdict is None, f"{model}_ref.csv under {importer}: {verdict}"


@pytest.mark.parametrize("importer", FMI3_IMPORTERS)
@pytest.mark.parametrize("model", MODELS)
def test_fmi3_reference_passes_fmpy_criterion(model, importer, shipped):
    s = shipped(fmutest.FMU_DIR / "fmi3" / f"{model}.fmu")
    assert s.path.is_file(), f"{s.path} does not exist: {fmutest.BUILD_HINT}"
    interface = "CoSimulation" if importer == "FMPy CS" else "ModelExchange"
    verdict = s.verdict(_fmi3(s, interface))
    assert verdict is None, f"FMI 3.0 {model}_ref.csv under {importer}: {verdict}"


@pytest.mark.parametrize("model", MODELS)
def test_reference_keeps_the_rules(model, shipped):
    s = shipped(fmutest.fmu_path(model))
    columns = s.columns
    assert 1 <= len(columns) <= MAX_COLUMNS, f"{model}_ref.csv has {len(columns)} variables (at most {MAX_COLUMNS})"
    causality = {v.name: v.causality for v in s.md.modelVariables}
    not_outputs = [n for n in columns if causality.get(n) != "output"]
    assert not not_outputs, f"{model}_ref.csv: {not_outputs} are not outputs of the FMU"
    if s.inputs is not None:
        not_inputs = [n for n in s.inputs.dtype.names[1:] if causality.get(n) != "input"]
        assert not not_inputs, f"{model}_in.csv: {not_inputs} are not inputs of the FMU"
    ranges = {n: float(np.ptp(s.reference[n])) for n in columns}
    assert any(r > 0 for r in ranges.values()), f"nothing moves in {model}_ref.csv: every column is constant"
    round_off = [n for n, r in ranges.items() if 0 < r <= CONSTANT * float(np.max(np.abs(s.reference[n])))]
    assert not round_off, (f"{model}_ref.csv: {round_off} vary by their solver's round-off only: write the "
                           "invariant's exact value")


# ---------------------------------------------------------------------------------------
# What `mechfmu validate --write-references` refuses to write


def _oscillator_case(**overrides) -> Case:
    """A case over the Oscillator's DefaultExperiment (20 s, 0.01 s) with a made-up reference."""
    fields = dict(stop_time=20.0, output_interval=0.01, outputs=["x", "x_dot"],
                  reference=lambda t: {"x": np.cos(t), "x_dot": -np.sin(t)})
    return Case("made_up", **{**fields, **overrides})


@pytest.mark.parametrize("overrides, refusal", [
    (dict(outputs=["x"] * 11), "allow 10"),
    (dict(start_values={"x": 0.5}), "sets start values"),
    (dict(reference=lambda t: {"x": np.cos(t), "x_dot": 1.0 + 1e-12 * np.sin(t)}), "round-off"),
    (dict(reference=lambda t: {"x": np.ones_like(t), "x_dot": np.zeros_like(t)}), "nothing moves"),
], ids=["11 columns", "start values", "round-off invariant", "standing still"])
def test_write_references_refuses(overrides, refusal, tmp_path):
    with Fmu(fmutest.fmu_path("Oscillator")) as fmu:
        with pytest.raises(ValueError, match=refusal):
            write_references(fmu, _oscillator_case(**overrides), tmp_path)
    assert not list(tmp_path.iterdir())


def test_write_references_names_its_case_and_why(tmp_path):
    """From a case that is not the DefaultExperiment's, whose case stands still: the README
    says which case and why, the columns are ``reference_files``, and an exact invariant is
    a constant column."""
    still = _oscillator_case(reference=lambda t: {"x": np.zeros_like(t), "x_dot": np.zeros_like(t)},
                             default_experiment=True)
    moving = _oscillator_case(reference=lambda t: {"x": np.cos(t), "x_dot": -np.sin(t),
                                                   "x_ddot": np.full_like(t, -4.0)},
                              outputs=["x", "x_dot", "x_ddot"], reference_files=["x", "x_ddot"])
    with Fmu(fmutest.fmu_path("Oscillator")) as fmu:
        write_references(fmu, moving, tmp_path, default=still)
    readme = (tmp_path / "README.md").read_text()
    assert "from the case `made_up`" in readme and "nothing moves in it" in readme
    assert "`x_ddot` is constant" in readme and "(`x_dot`) are not in `_ref.csv`" in readme
    ref = read_csv(tmp_path / "Oscillator_ref.csv")
    assert ref.dtype.names == ("time", "x", "x_ddot") and np.all(ref["x_ddot"] == -4.0)
