"""The systems of the repository (`systems/*`) as `mechfmu build` ships them, one SSP each
(`fmus/<System>.ssp`): valid SSP 1.0 with every FMU inside, the default parameter set bound
and every other set a variant; the solution `mechfmu validate` measures co-simulations
against agrees with the systems' monolithic solutions (TwoMassOscillator's closed form, an
independent solution of the controlled crane); `mechfmu validate` passes both SSPs in FMPy
libcosim and Ecos (and OMSimulator where it is built), each within its own master's coupling
error, first order in the step.
"""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest
from lxml import etree

import fmutest
from mechanisms import models, systems
from mechfmu_validate.systems import FACTOR, archive, jacobi
from refs import controlled_crane

SCHEMA = Path(fmpy.__file__).parent / "ssp" / "schema"
NAMES = [name for name, _ in systems()]


def ssp_path(name: str) -> Path:
    path = fmutest.FMU_DIR / f"{name}.ssp"
    if not path.is_file():
        pytest.fail(f"{path} does not exist: build it with `cargo run --release -- build`")
    return path


def test_the_shipped_systems_are_the_contracts():
    assert NAMES == ["ControlledCrane", "TwoOscillators"]


@pytest.mark.parametrize("name", NAMES)
def test_every_ssd_and_ssv_is_valid_ssp_1_0(name):
    ssd_schema = etree.XMLSchema(etree.parse(str(SCHEMA / "SystemStructureDescription.xsd")))
    ssv_schema = etree.XMLSchema(etree.parse(str(SCHEMA / "SystemStructureParameterValues.xsd")))
    with zipfile.ZipFile(ssp_path(name)) as z:
        names = z.namelist()
        assert "SystemStructure.ssd" in names
        for file in names:
            if file.endswith((".ssd", ".ssv")):
                schema = ssd_schema if file.endswith(".ssd") else ssv_schema
                doc = etree.fromstring(z.read(file))
                assert schema.validate(doc), f"{name}.ssp/{file}: {schema.error_log}"
                assert doc.get("version") == "1.0", file


@pytest.mark.parametrize("name", NAMES)
def test_the_default_set_is_bound_and_every_other_set_is_a_variant(name, tmp_path):
    ssp = archive.read(ssp_path(name), tmp_path)
    root = etree.parse(str(tmp_path / "SystemStructure.ssd")).getroot()
    for component in root.iterfind(f"{archive.SSD}System/{archive.SSD}Elements/{archive.SSD}Component"):
        assert component.get("type") == "application/x-fmu-sharedlibrary"
        assert (tmp_path / component.get("source")).is_file()
        bindings = [b.get("source") for b in
                    component.findall(f"{archive.SSD}ParameterBindings/{archive.SSD}ParameterBinding")]
        # one set bound, once (libcosim applies the first binding, OMSimulator every one)
        assert bindings in ([], [f"resources/default/{component.get('name')}.ssv"]), bindings
        # every input that is not connected is left out (FMPy fails on one)
        connected = {to for _, to in ssp.connections}
        for connector in component.iterfind(f"{archive.SSD}Connectors/{archive.SSD}Connector"):
            if connector.get("kind") == "input":
                assert (component.get("name"), connector.get("name")) in connected
    assert list(ssp.sets)[0] == "default" and len(ssp.sets) == 2
    for set_name, file in ssp.set_files.items():
        assert file == ("SystemStructure.ssd" if set_name == "default" else f"{set_name}.ssd")
    # every set gives a value to the same variables: applying one undoes any other
    assert len({frozenset(values) for values in ssp.sets.values()}) == 1
    assert ssp.step == 0.01 and ssp.stop == 30.0


def test_two_oscillators_sets_are_two_mass_oscillators(tmp_path):
    ssp = archive.read(ssp_path("TwoOscillators"), tmp_path)
    default, damped = ssp.sets["default"], ssp.sets["damped"]
    assert default[("b", "x")] == 0.0 and default[("a", "x")] == 1.0
    # a set other than the default is the default with its own values over it
    assert damped[("b", "x")] == 0.0 and damped[("b", "m")] == 2.0 and damped[("spring", "c")] == 0.05


def _solution(name: str, set_name: str, signals, work: Path):
    ssp = archive.read(ssp_path(name), work / "ssp")
    return jacobi.solution(ssp, ssp.sets[set_name], ssp.stop, signals, work)


def test_the_solution_of_two_oscillators_is_two_mass_oscillators(tmp_path):
    """The default set against TwoMassOscillator's closed form (unit masses and springs,
    undamped: modes at 1 and sqrt(3) rad/s); the damped set against the TwoMassOscillator FMU
    at the same parameters, integrated at tolerance 1e-10."""
    signals = [("a", "x"), ("a", "x_dot"), ("b", "x"), ("b", "x_dot")]
    t, sol = _solution("TwoOscillators", "default", signals, tmp_path)
    w = np.sqrt(3.0)
    exact = {("a", "x"): 0.5 * np.cos(t) + 0.5 * np.cos(w * t), ("b", "x"): 0.5 * np.cos(t) - 0.5 * np.cos(w * t),
             ("a", "x_dot"): -0.5 * np.sin(t) - 0.5 * w * np.sin(w * t),
             ("b", "x_dot"): -0.5 * np.sin(t) + 0.5 * w * np.sin(w * t)}
    for s in signals:
        assert np.max(np.abs(sol[s] - exact[s])) / np.ptp(exact[s]) < 1e-4, s
    t, sol = _solution("TwoOscillators", "damped", signals, tmp_path)
    res = fmpy.simulate_fmu(str(fmutest.fmu_path("TwoMassOscillator")), stop_time=30.0, output_interval=0.01,
                            relative_tolerance=1e-10,
                            start_values={"m1": 1.0, "m2": 2.0, "k1": 1.0, "k2": 0.5, "k3": 2.0,
                                          "c1": 0.1, "c2": 0.2, "c3": 0.05, "x1": 1.0, "x2": 0.0},
                            output=["x1", "x1_dot", "x2", "x2_dot"])
    for (c, v), monolithic in ((("a", "x"), "x1"), (("a", "x_dot"), "x1_dot"), (("b", "x"), "x2"),
                               (("b", "x_dot"), "x2_dot")):
        exact = np.interp(t, res["time"], res[monolithic])
        assert np.max(np.abs(sol[(c, v)] - exact)) / np.ptp(exact) < 1e-4, (c, v)


def test_the_solution_of_the_controlled_crane_is_the_closed_loops(tmp_path):
    states = ("x", "x_dot", "theta", "theta_dot", "phi_dot")
    for set_name, controller in (("default", None), ("reach", {"x_ref": 15.0, "theta_ref": 0.3})):
        t, sol = _solution("ControlledCrane", set_name, [("crane", s) for s in states], tmp_path / set_name)
        ref = controlled_crane.simulate(controller, t_out=t)
        for s in states:
            assert np.max(np.abs(sol[("crane", s)] - ref[s])) / np.ptp(ref[s]) < 1e-4, (set_name, s)
        # the controller gets there: the trolley and the boom at their set points
        want = controller or {"x_ref": 12.0, "theta_ref": 0.6}
        assert abs(ref["x"][-1] - want["x_ref"]) < 0.05 and abs(ref["theta"][-1] - want["theta_ref"]) < 0.01


@pytest.fixture(scope="module")
def validated(tmp_path_factory) -> list[dict]:
    folder = tmp_path_factory.mktemp("validate")
    out = folder / "systems.json"
    done = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "validate",
                           *(str(ssp_path(n)) for n in NAMES), "--json", str(out), "--readme", str(folder / "docs")],
                          cwd=fmutest.REPO_ROOT, capture_output=True, text=True, timeout=1800)
    assert out.is_file(), f"{done.stdout[-4000:]}\n{done.stderr[-4000:]}"
    assert done.returncode == 0, f"{done.stdout[-4000:]}\n{done.stderr[-4000:]}"
    # --readme with SSPs alone: each system's coupling figure, and no validation tables
    for figure in ("two-oscillators-coupling.png", "controlled-crane-coupling.png"):
        assert (folder / "docs" / "validation" / figure).stat().st_size > 20_000
    assert not (folder / "docs" / "validation.md").exists()
    return json.loads(out.read_text())["rows"]


def test_mechfmu_validate_runs_every_set_in_every_ssp_importer(validated):
    rows = {(r["fmu"], r["case"], r["importer"]): r for r in validated}
    sets = {"TwoOscillators": ("default", "damped"), "ControlledCrane": ("default", "reach")}
    for name, names in sets.items():
        for set_name in names:
            case = f"{set_name} (SSP)"
            jacobi_row = rows[(name, case, "plain Jacobi")]
            for importer in ("FMPy SSP", "libcosim SSP", "Ecos SSP", "OMSimulator SSP", "OMSimulator CLI"):
                r = rows[(name, case, importer)]
                # OMSimulator has no wheel: it runs where it was built from source; Ecos and
                # OMSimulator's command line load no variant: the default set only
                optional = importer.startswith("OMSimulator") or (importer == "Ecos SSP" and set_name != "default")
                assert r["passed"] and (not r.get("skipped") or optional), r
                if r.get("limited") or r.get("skipped"):
                    continue
                if importer == "OMSimulator CLI":  # the SSD's step only
                    assert r["max_error"] <= r["tolerance"], r
                    continue
                # within its own scheme's error, and first order: half the error at half the step
                assert r["max_error"] <= r["tolerance"] and r["tolerance"] <= FACTOR * 30 * jacobi_row["max_error"]
                assert 1.6 < r["max_error"] / r["half_step_error"] < 2.6, r
                # the step a user reads: the error under 1e-3 of range at that order
                order = r["coupling_order"]
                assert 0.7 < order < 1.4, r
                assert r["largest_step"] == pytest.approx(0.01 * (1e-3 / r["max_error"]) ** (1 / order), rel=1e-9)
            # measured against the system's own FMU, beside the SSP
            assert "the system's FMU" in jacobi_row["notes"][0], jacobi_row
    # libcosim cannot set a state's start value from a parameter set: TwoOscillators' b.x = 0
    for set_name in ("default", "damped"):
        r = rows[("TwoOscillators", f"{set_name} (SSP)", "libcosim SSP")]
        assert r["limited"] and "b.x" in r["notes"][0], r
    for set_name in ("default", "reach"):
        assert not rows[("ControlledCrane", f"{set_name} (SSP)", "libcosim SSP")].get("limited")


def test_the_fmi3_terminals_are_valid_and_name_the_fmus_variables():
    """terminalsAndIcons/terminalsAndIcons.xml against FMI 3.0's schema (FMPy's copy): each
    member a variable of the FMU, members matched by name (`plug`); every mechanism the shipped
    systems are made of (they join terminal to terminal) has the file."""
    schema = etree.XMLSchema(etree.parse(str(Path(fmpy.__file__).parent / "schema" / "fmi3" /
                                             "fmi3TerminalsAndIcons.xsd")))
    with_terminals = set()
    for model in models():
        with zipfile.ZipFile(fmutest.FMU_DIR / "fmi3" / f"{model}.fmu") as z:
            if "terminalsAndIcons/terminalsAndIcons.xml" not in z.namelist():
                continue
            doc = etree.fromstring(z.read("terminalsAndIcons/terminalsAndIcons.xml"))
            md = etree.fromstring(z.read("modelDescription.xml"))
        assert schema.validate(doc), (model, schema.error_log)
        variables = {v.get("name") for v in md.find("ModelVariables")}
        terminals = doc.findall("Terminals/Terminal")
        assert terminals, model
        for terminal in terminals:
            assert terminal.get("matchingRule") == "plug" and terminal.get("terminalKind").startswith("org.mechfmu.")
            for member in terminal.findall("TerminalMemberVariable"):
                assert member.get("variableName") in variables, (model, terminal.get("name"), member.get("variableName"))
                assert member.get("variableKind") == "signal"
        with_terminals.add(model)
    for name in NAMES:
        with zipfile.ZipFile(ssp_path(name)) as z:
            components = {Path(n).stem for n in z.namelist() if n.startswith("resources/") and n.endswith(".fmu")}
        assert components <= with_terminals, (name, components - with_terminals)


def test_an_fmu_without_terminals_has_no_terminals_file():
    with zipfile.ZipFile(fmutest.FMU_DIR / "fmi3" / "TwoMassOscillator.fmu") as z:
        assert not any(n.startswith("terminalsAndIcons/") for n in z.namelist())
    with zipfile.ZipFile(fmutest.FMU_DIR / "Oscillator.fmu") as z:  # FMI 2.0 has no terminals
        assert not any(n.startswith("terminalsAndIcons/") for n in z.namelist())


def test_an_ssp_mechfmu_did_not_write_validates_too(tmp_path):
    """An SSP written as another tool writes one: its step in OpenModelica's annotation
    alone, a parameter set inline in the SSD, connectors without units, a system named
    apart from its file. `mechfmu validate` runs it in every importer and measures each
    against its solution, here TwoMassOscillator's closed form at its defaults."""
    ssd = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"
    xmlns:oms="https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"
    version="1.0" name="Pair">
  <ssd:System name="Pair">
    <ssd:Elements>
      {components}
    </ssd:Elements>
    <ssd:Connections>
      {connections}
    </ssd:Connections>
    <ssd:Annotations><ssc:Annotation type="org.openmodelica"><oms:Annotations><oms:SimulationInformation>
      <oms:FixedStepMaster description="oms-ma" stepSize="0.01" absoluteTolerance="1e-4" relativeTolerance="1e-4"/>
    </oms:SimulationInformation></oms:Annotations></ssc:Annotation></ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="10"/>
</ssd:SystemStructureDescription>"""
    links = [("a", "x", "s", "x_a"), ("a", "x_dot", "s", "v_a"), ("b", "x", "s", "x_b"), ("b", "x_dot", "s", "v_b"),
             ("s", "F_a", "a", "F"), ("s", "F_b", "b", "F")]
    values = {"a": {"k": 1.0, "c": 0.0}, "b": {"k": 1.0, "c": 0.0, "x": 0.0}}
    components = []
    for name, model in (("a", "Oscillator"), ("s", "SpringDamper"), ("b", "Oscillator")):
        connectors = "".join(f'<ssd:Connector name="{v}" kind="output"><ssc:Real/></ssd:Connector>'
                             for c, v, _, _ in links if c == name)
        connectors += "".join(f'<ssd:Connector name="{v}" kind="input"><ssc:Real/></ssd:Connector>'
                              for _, _, c, v in links if c == name)
        bound = ""
        if name in values:
            parameters = "".join(f'<ssv:Parameter name="{k}"><ssv:Real value="{x}"/></ssv:Parameter>'
                                 for k, x in values[name].items())
            bound = ('<ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>'
                     f'<ssv:ParameterSet version="1.0" name="start"><ssv:Parameters>{parameters}</ssv:Parameters>'
                     '</ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>')
        components.append(f'<ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" '
                          f'source="resources/{model}.fmu"><ssd:Connectors>{connectors}</ssd:Connectors>{bound}'
                          '</ssd:Component>')
    connections = "".join(f'<ssd:Connection startElement="{a}" startConnector="{x}" endElement="{b}" endConnector="{y}"/>'
                          for a, x, b, y in links)
    path = tmp_path / "pair.ssp"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("SystemStructure.ssd", ssd.format(components="".join(components), connections=connections))
        for model in ("Oscillator", "SpringDamper"):
            z.write(fmutest.fmu_path(model), f"resources/{model}.fmu")
    ssp = archive.read(path, tmp_path / "read")
    assert ssp.step == 0.01 and ssp.stop == 10.0 and ssp.sets["start"][("b", "x")] == 0.0
    from mechfmu_validate.systems import validate_system

    rows = {r.importer: r for r in validate_system(path)}
    assert rows["FMPy SSP"].passed and rows["FMPy SSP"].max_error < 0.1, rows["FMPy SSP"]
    assert rows["plain Jacobi"].max_error < 0.05
    # libcosim reads an inline set too, and leaves the state's start value (a LIMIT)
    assert rows["libcosim SSP"].passed and rows["libcosim SSP"].limited
    # and the solution is the monolithic one: TwoMassOscillator at its defaults
    t, solution = jacobi.solution(ssp, ssp.sets["start"], ssp.stop, [("a", "x")], tmp_path)
    exact = 0.5 * np.cos(t) + 0.5 * np.cos(np.sqrt(3.0) * t)
    assert np.max(np.abs(solution[("a", "x")] - exact)) < 1e-4


@pytest.mark.parametrize("version", ["2.0", "3.0"])
@pytest.mark.parametrize("interface", ["CoSimulation", "ModelExchange"])
def test_the_system_fmu_is_two_mass_oscillator(version, interface):
    """TwoOscillators.fmu, the system compiled into one FMU, is TwoMassOscillator.fmu at equal
    parameters: 1e-8 of each state's range at relative tolerance 1e-10 (FMPy's CVode in Model
    Exchange), with the `damped` set's values and a start apart."""
    folder = fmutest.FMU_DIR if version == "2.0" else fmutest.FMU_DIR / "fmi3"
    system = {"b.m": 2.0, "b.k": 0.5, "spring.k": 2.0, "a.c": 0.1, "b.c": 0.2, "spring.c": 0.05, "a.x": 0.3,
              "b.x": -0.2}
    two_mass = {"m2": 2.0, "k2": 0.5, "k3": 2.0, "c1": 0.1, "c2": 0.2, "c3": 0.05, "x1": 0.3, "x2": -0.2}
    pairs = {"a.x": "x1", "b.x": "x2", "a.x_dot": "x1_dot", "b.x_dot": "x2_dot"}
    options = dict(fmi_type=interface, relative_tolerance=1e-10, output_interval=0.01, stop_time=30.0)
    ours = fmpy.simulate_fmu(str(folder / "TwoOscillators.fmu"), start_values=system, output=list(pairs), **options)
    theirs = fmpy.simulate_fmu(str(folder / "TwoMassOscillator.fmu"), start_values=two_mass,
                               output=list(pairs.values()), **options)
    assert len(ours) == len(theirs) == 3001
    for a, b in pairs.items():
        assert np.max(np.abs(ours[a] - theirs[b])) <= 1e-8 * np.ptp(theirs[b]), a


SYSTEM_OF_FILES = '''//! A system whose components are FMU files.

use mechfmu::model::Experiment;

mechfmu::system! {
    /// Two oscillators from FMU files, joined by a spring from another.
    pub struct Pair {
        components {
            /// The first mass
            a: fmu("parts/Oscillator.fmu"),
            /// The spring
            spring: fmu("parts/SpringDamper.fmu"),
            /// The second mass
            b: fmu("parts/Oscillator.fmu"),
        }
        connections {
            a.x => spring.x_a, a.x_dot => spring.v_a, b.x => spring.x_b, b.x_dot => spring.v_b,
            spring.F_a => a.F, spring.F_b => b.F,
        }
        parameter_sets {
            /// The second mass at rest at 0
            default { b.x = 0.0, spring.k = 2.0 }
        }
        experiment: Experiment::until(10.0).step(0.01),
    }
}

mechfmu::export_system!(Pair);
'''


def test_a_system_of_fmu_files_is_built_into_an_ssp(tmp_path):
    """A user's system crate of FMU files (`fmu("parts/Oscillator.fmu")`), alone in its
    workspace: `mechfmu build` reads the files' model descriptions, checks the connections
    against them and writes the SSP with the files inside (no FMU of the system: the files'
    equations are not the compiler's); `mechfmu validate` runs it. A connection to a variable
    the file lacks is refused by the build, naming it."""
    crate = tmp_path / "pair"
    (crate / "src").mkdir(parents=True)
    (crate / "parts").mkdir()
    for model in ("Oscillator", "SpringDamper"):
        (crate / "parts" / f"{model}.fmu").write_bytes(fmutest.fmu_path(model).read_bytes())
    runtime = (fmutest.REPO_ROOT / "crates" / "runtime").as_posix()
    (crate / "Cargo.toml").write_text(f'''[package]
name = "pair-system"
version = "0.1.0"
edition = "2021"
publish = false

[lib]
name = "pair"
crate-type = ["cdylib", "rlib"]

[dependencies]
mechfmu = {{ path = "{runtime}" }}

[package.metadata.mechfmu]
system = "Pair"
''')
    (crate / "src" / "lib.rs").write_text(SYSTEM_OF_FILES)
    env = dict(os.environ, CARGO_TARGET_DIR=str(fmutest.REPO_ROOT / "target" / "user-crates"))
    mechfmu = fmutest.REPO_ROOT / "target" / "release" / "mechfmu"
    build = [str(mechfmu), "build", "--manifest-path", str(crate / "Cargo.toml"), "--out", str(crate / "fmus"),
             "--platform", "x86_64-linux"]
    done = subprocess.run(build, cwd=crate, env=env, capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stderr[-3000:]
    assert not (crate / "fmus" / "Pair.fmu").exists()
    ssp = archive.read(crate / "fmus" / "Pair.ssp", tmp_path / "read")
    assert sorted(c.source for c in ssp.components) == ["resources/Oscillator.fmu", "resources/Oscillator.fmu",
                                                        "resources/SpringDamper.fmu"]
    assert len(ssp.connections) == 6 and ssp.sets["default"][("spring", "k")] == 2.0
    out = tmp_path / "rows.json"
    done = subprocess.run([str(mechfmu), "validate", str(crate / "fmus" / "Pair.ssp"), "--json", str(out)], cwd=crate,
                          capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    rows = {r["importer"]: r for r in json.loads(out.read_text())["rows"] if r["kind"] == "case"}
    assert rows["FMPy SSP"]["passed"] and rows["FMPy SSP"]["max_error"] > 0
    assert "extrapolated" in rows["plain Jacobi"]["notes"][0]  # no system FMU: the Jacobi solution

    (crate / "src" / "lib.rs").write_text(SYSTEM_OF_FILES.replace("spring.F_a => a.F", "spring.F_c => a.F"))
    done = subprocess.run(build, cwd=crate, env=env, capture_output=True, text=True, timeout=1800)
    assert done.returncode != 0 and "F_c" in done.stderr, done.stderr[-3000:]


def test_an_ssp_whose_component_would_extract_outside_its_folder_is_refused(tmp_path):
    """An importer extracts each component's FMU: one with an entry up the tree would write
    outside its folder, so the SSP is refused before any importer runs it."""
    original = ssp_path("TwoOscillators")
    hostile = tmp_path / "TwoOscillators.ssp"
    with zipfile.ZipFile(original) as src, zipfile.ZipFile(hostile, "w") as dst:
        for name in src.namelist():
            data = src.read(name)
            if name == "resources/SpringDamper.fmu":
                fmu = tmp_path / "SpringDamper.fmu"
                fmu.write_bytes(data)
                with zipfile.ZipFile(fmu, "a") as z:
                    z.writestr("resources/../../escaped.txt", "outside\n")
                data = fmu.read_bytes()
            dst.writestr(name, data)
    with pytest.raises(ValueError, match=r"resources/SpringDamper\.fmu has an entry outside the FMU's folder: "
                                         r"'resources/\.\./\.\./escaped\.txt'"):
        archive.read(hostile, tmp_path / "ssp")
    with pytest.raises(ValueError, match=r"the SSP has an entry outside its folder: '\.\./x'"):
        with zipfile.ZipFile(hostile, "a") as z:
            z.writestr("../x", "outside\n")
        archive.read(hostile, tmp_path / "ssp2")
