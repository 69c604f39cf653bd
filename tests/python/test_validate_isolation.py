"""`mechfmu validate` on FMUs that crash or hang their importer's process, that write to the
console, or that share a model name: each FMU's validation runs in a child process of its own
(python/mechfmu_validate/isolation.py).

A crash (a segmentation fault in fmi2DoStep) or a hang (an fmi2DoStep that never returns, past
--time-limit) is one FAIL row naming the signal or the time limit, the run and the FMI call;
the FMU beside it still passes; the table, the JSON and the JUnit file are written; nothing is
left in the temporary directory. What the FMU and the importers write to the console goes into
the row of the run that wrote it. Each FMU file is a JUnit suite of its own, named by its path
where two files are models of one name. The FMUs are FirstOrder's variants
(tests/python/data/foreign/FirstOrder.c: -DCRASH_AT, -DHANG_AT, -DTALK).
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
import types
import xml.etree.ElementTree as ET
from pathlib import Path

from mechfmu_validate import isolation, validation
from mechfmu_validate.importer import Selection
from mechfmu_validate.importers.fmi_crate import FMI_RUN_ENV
from mechfmu_validate.isolation import STOPPED, Job, validate_isolated
from test_validate_foreign import REPO, build, fmi_run, good, reference_rows, validate  # noqa: F401 (fixtures)

#: a job for the children below, which do not validate it
JOB = Job(Path("Fake.fmu"), "Fake", None, (), Selection(frozenset({"libcosim", "fmi-crate"}), False, False))
ROW = dict(kind="check", fmu="Fake", case="check: fake", importer="-", max_error=None, tolerance=None,
           passed=True, notes=[], problems=[])


def junit_suites(path) -> dict[str, ET.Element]:
    return {s.get("name"): s for s in ET.parse(path).getroot().findall("testsuite")}


def test_a_crashing_fmu_is_one_fail_row_and_the_other_still_runs(good, fmi_run, tmp_path):
    crashing = build(tmp_path / "crash", "-DCRASH_AT=1.0")
    junit = tmp_path / "validate.xml"
    proc, rows = validate(tmp_path, fmi_run, str(crashing), str(good), "--junit", str(junit))
    assert proc.returncode == 1
    [failed] = [r for r in rows if not r["passed"]]
    assert failed["case"] == STOPPED and failed["fmu"] == str(crashing), failed
    assert re.fullmatch(rf"{re.escape(str(crashing))}: the process validating it died of SIGSEGV \(signal 11\) in "
                        r"fmi2DoStep\(currentCommunicationPoint=1, communicationStepSize=0\.1\), while running "
                        r"FirstOrder: embedded_reference \(FMPy\)", failed["problems"][0]), failed["problems"]
    # the rows made before the crash are kept; the good FMU passes under every importer
    assert any(r["fmu"] == str(crashing) and r["case"] == "check: fmpy validate" and r["passed"] for r in rows)
    assert {"FMPy", "libcosim", "fmi crate"} <= set(reference_rows(rows, str(good)))
    assert all(r["passed"] for r in rows if r["fmu"] == str(good))
    assert re.search(r"^\d+ passed, 1 failed$", proc.stdout, re.M)
    suites = junit_suites(junit)
    assert set(suites) == {str(crashing), str(good)}
    assert suites[str(crashing)].get("failures") == "1" and suites[str(good)].get("failures") == "0"


def test_a_hanging_fmu_is_stopped_at_the_time_limit(good, fmi_run, tmp_path):
    hanging = build(tmp_path / "hang", "-DHANG_AT=1.0")
    proc, rows = validate(tmp_path, fmi_run, str(hanging), str(good), "--time-limit", "5")
    assert proc.returncode == 1
    [failed] = [r for r in rows if not r["passed"]]
    assert failed["case"] == STOPPED and failed["fmu"] == str(hanging)
    assert "made no progress for 5 s (the time limit, --time-limit): stopped in fmi2DoStep(" \
           "currentCommunicationPoint=1, communicationStepSize=0.1), while running FirstOrder: embedded_reference " \
           "(FMPy)" in failed["problems"][0], failed["problems"]
    assert all(r["passed"] for r in rows if r["fmu"] == str(good))


def test_what_an_fmu_writes_to_the_console_is_in_its_rows(fmi_run, tmp_path):
    """Written to the process's stderr by fmi2ExitInitializationMode: in the rows of the runs
    that called it (FMPy's; libcosim's, beside FMPy's run at libcosim's settings), in the JUnit
    file's <system-out>, not above the table."""
    talking = build(tmp_path / "talk", "-DTALK")
    junit = tmp_path / "validate.xml"
    proc, rows = validate(tmp_path, fmi_run, str(talking), "--junit", str(junit))
    assert proc.returncode == 0
    said = "FirstOrder on stderr: initialized with y0 = 1"
    refs = reference_rows(rows)
    assert refs["FMPy"]["output"].strip() == said and said in refs["libcosim"]["output"]
    assert said not in proc.stdout + proc.stderr
    assert "rows that pass captured the importers' console output" in proc.stdout
    outputs = [c.find("system-out").text for c in ET.parse(junit).getroot().iter("testcase")
               if c.find("system-out") is not None]
    assert len(outputs) == 2 and all(said in text for text in outputs)


def test_fmus_of_one_model_name_are_named_by_their_paths(good, fmi_run, tmp_path):
    """Two FirstOrder files: two JUnit suites, two FMU names in the table and two plots in the
    report, never merged; the platforms row names FMI 2.0's folders."""
    other = build(tmp_path / "other")
    junit, report = tmp_path / "validate.xml", tmp_path / "report"
    proc, rows = validate(tmp_path, fmi_run, str(good), str(other), "--junit", str(junit), "--report", str(report))
    assert proc.returncode == 0
    assert len({p.parent for p in report.glob("*/embedded_reference.png")}) == 2  # a plot each, inside DIR
    assert {r["fmu"] for r in rows} == {str(good), str(other)}
    suites = junit_suites(junit)
    assert set(suites) == {str(good), str(other)}
    for name, suite in suites.items():
        tests = [c.get("name") for c in suite.findall("testcase")]
        assert len(tests) == len(set(tests)) == len([r for r in rows if r["fmu"] == name]) == int(suite.get("tests"))
        assert {c.get("classname") for c in suite.findall("testcase")} == {name}
    [platforms] = [r for r in rows if r["fmu"] == str(good) and r["case"] == "(platforms, FMI 2.0)"]
    others = "no binary for win64, aarch64-linux, darwin64, aarch64-darwin"
    assert platforms["importer"] == "linux64" and platforms["notes"][1] == others
    assert f"{good} (FMI 2.0): binaries for linux64; run: linux64; {others}" in proc.stdout


def _descendants(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (spawn's children; not its resource tracker)."""
    found = []
    for entry in Path("/proc").iterdir():
        try:
            stat = (entry / "stat").read_text()
            cmdline = (entry / "cmdline").read_bytes()
        except (OSError, ValueError):
            continue
        if int(stat.rsplit(")", 1)[1].split()[1]) == pid and b"spawn_main" in cmdline:
            found.append(int(entry.name))
    return found


def _gone(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] in ("Z", "X")
    except OSError:
        return True


def _hung_validation(tmp_path: Path, fmi_run: Path) -> tuple[subprocess.Popen, int, Path]:
    """`python -m mechfmu_validate` on an FMU hanging in fmi2DoStep, once its child runs:
    (the parent, the child's pid, the temporary directory)."""
    hanging = build(tmp_path / "hang", "-DHANG_AT=1.0")
    tmp = tmp_path / "tmpdir"
    tmp.mkdir()
    env = dict(os.environ, TMPDIR=str(tmp), **{FMI_RUN_ENV: str(fmi_run)})
    parent = subprocess.Popen([sys.executable, "-m", "mechfmu_validate", str(hanging), "--time-limit", "60"],
                              cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not _descendants(parent.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    [child] = _descendants(parent.pid)
    time.sleep(2)  # into the FMU's run
    return parent, child, tmp


def _wait_gone(pid: int, seconds: float = 10) -> bool:
    deadline = time.monotonic() + seconds
    while not _gone(pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    return _gone(pid)


def test_sigterm_to_the_parent_ends_the_child_and_removes_its_files(fmi_run, tmp_path):
    parent, child, tmp = _hung_validation(tmp_path, fmi_run)
    parent.send_signal(signal.SIGTERM)
    _, stderr = parent.communicate(timeout=20)
    assert parent.returncode == 128 + signal.SIGTERM and "Traceback" not in stderr, stderr
    assert _wait_gone(child), f"the child {child} outlived its parent"
    assert not list(tmp.iterdir()), [p.name for p in tmp.iterdir()]


def test_a_parent_killed_outright_takes_its_child_with_it(fmi_run, tmp_path):
    parent, child, _ = _hung_validation(tmp_path, fmi_run)
    parent.kill()
    parent.communicate(timeout=20)
    assert _wait_gone(child), f"the child {child} outlived its parent"


# Children standing in for the validation (``validate_isolated(child=...)``), run by spawn
# from this module


def child_dying_at_once(*_):
    """Ends before it writes anything (a start-up that fails, a process killed for memory)."""
    os._exit(3)


def child_hanging_at_its_exit(conn, *_):
    """Sends its result, then never ends (a static destructor, a thread that does not stop)."""
    conn.send(("done", [ROW], [], []))
    time.sleep(3600)


def child_sending_what_the_parent_cannot_read(conn, *_):
    """A row, then a result holding an object of a module the parent does not have (a
    cases.py loaded only in the child)."""
    module = types.ModuleType("only_in_the_child")
    thing = type("Thing", (), {"__module__": "only_in_the_child"})
    module.Thing = thing
    sys.modules["only_in_the_child"] = module
    conn.send(("row", ROW, 0))
    conn.send(("done", [ROW], [], [thing()]))
    time.sleep(3600)


def child_validating_a_talking_batch(*args):
    """The real child around a validation whose three runs (as the platforms' runs of one case,
    made by one generator) each write to the console, as wine or an FMU does, while made."""
    def validate_fmu(path, cases_file, only, selection, rows, *_, **__):
        def made():
            for name in ("win64", "aarch64-linux", "x86_64-windows"):
                os.write(2, f"the {name} run speaks\n".encode())
                yield dict(ROW, case=name)
        validation._append(rows, {}, made())

    isolation.validate_fmu = validate_fmu
    isolation._child(*args)


def test_each_row_of_a_batch_has_what_its_own_run_wrote():
    rows, _, _ = validate_isolated(JOB, 30, child=child_validating_a_talking_batch)
    assert [(r["case"], r.get("output")) for r in rows] == [
        (name, f"the {name} run speaks\n") for name in ("win64", "aarch64-linux", "x86_64-windows")]


def test_a_child_that_dies_before_it_writes_anything_is_one_fail_row():
    rows, plots, details = validate_isolated(JOB, 30, child=child_dying_at_once)
    assert plots == details == []
    [row] = rows
    assert row["case"] == STOPPED and not row["passed"] and "output" not in row
    assert row["problems"] == ["Fake.fmu: the process validating it ended (exit status 3) with its validation "
                               "unfinished before any FMI call, while running its opening"], row["problems"]


def test_a_child_hanging_at_its_exit_is_ended_and_its_result_kept(monkeypatch):
    monkeypatch.setattr(isolation, "SHUTDOWN_GRACE", 0.5)
    got = []
    runner = threading.Thread(target=lambda: got.append(validate_isolated(JOB, 30, child=child_hanging_at_its_exit)),
                              daemon=True)
    runner.start()
    runner.join(20)
    assert not runner.is_alive(), "the parent waited for a child that does not end"
    assert got == [([ROW], [], [])]


def test_a_result_the_parent_cannot_read_keeps_the_rows_and_is_one_fail_row():
    rows, plots, details = validate_isolated(JOB, 30, child=child_sending_what_the_parent_cannot_read)
    assert rows[0] == ROW and plots == details == []
    [stopped] = rows[1:]
    assert stopped["case"] == STOPPED and not stopped["passed"]
    assert "sent a result that cannot be read (ModuleNotFoundError" in stopped["problems"][0], stopped


def test_sigterm_to_the_mechfmu_command_reaches_the_validation(fmi_run, tmp_path):
    """`mechfmu validate` (the Rust command) passes SIGTERM on to the Python side it runs and
    waits for it: the validation's child ends and its files are removed before the command
    ends; killed outright, the command takes the validation with it."""
    hanging = build(tmp_path / "hang", "-DHANG_AT=1.0")
    for how in ("terminate", "kill"):
        tmp = tmp_path / f"tmpdir-{how}"
        tmp.mkdir()
        env = dict(os.environ, TMPDIR=str(tmp), **{FMI_RUN_ENV: str(fmi_run)})
        command = subprocess.Popen([str(REPO / "target/release/mechfmu"), "validate", str(hanging), "--no-fmi-crate",
                                    "--time-limit", "60"], cwd=REPO, env=env, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 120
        python = []
        while not python and time.monotonic() < deadline and command.poll() is None:
            time.sleep(0.2)
            python = [p for p in _children_of(command.pid) if _descendants(p)]
        assert python, "the validation never started its child"
        [validation] = python
        [child] = _descendants(validation)
        time.sleep(2)  # into the FMU's run
        getattr(command, how)()
        command.wait(timeout=60)
        if how == "terminate":
            assert command.returncode == 128 + signal.SIGTERM, command.returncode
            assert _gone(validation) and _gone(child), "the command ended before the validation"
            assert not list(tmp.iterdir()), [p.name for p in tmp.iterdir()]
        assert _wait_gone(validation) and _wait_gone(child), f"the validation outlived the command ({how})"


def _children_of(pid: int) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        try:
            if int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1]) == pid:
                found.append(int(entry.name))
        except (OSError, ValueError):
            continue
    return found
