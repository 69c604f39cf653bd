"""``mechfmu validate --junit FILE``: the table as JUnit XML, for CI systems that show test
results. One ``<testsuite>`` per FMU file given (its rows' ``file``; named like the table's
FMU column: the model, or the file's path where two files are models of one name), one
``<testcase>`` per row (``classname`` the suite, ``name`` the case and the importer, unique in
its suite); a FAIL row has a ``<failure>`` (its first problem as the message, every problem
in the text), a SKIP row ``<skipped>``; a LIMIT row passes, its note in ``<system-out>``, where
the console output the row's run wrote is too (the importers', the FMU's).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

from .report import result_text
from .rows import Row

__all__ = ["write_junit"]

#: the characters XML 1.0 cannot hold (terminal escapes in a console output, say)
NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _testcase(row: Row, suite: str, name: str) -> ET.Element:
    case = ET.Element("testcase", classname=suite, name=name, time=f"{row.get('seconds') or 0.0:.3f}")
    result = result_text(row)
    problems = [NOT_XML.sub("", str(p)) for p in row.get("problems", [])]
    if result == "FAIL":
        failure = ET.SubElement(case, "failure", message=problems[0] if problems else "failed")
        failure.text = "\n".join(problems + [f"({NOT_XML.sub('', str(n))})" for n in row.get("notes", [])])
    elif result == "SKIP":
        ET.SubElement(case, "skipped", message="; ".join(problems) or "skipped")
    said = []
    if result == "LIMIT":
        said.append("LIMIT (the importer's solver; reported, not failed): " +
                    "; ".join(NOT_XML.sub("", str(n)) for n in row.get("notes", [])))
    if (row.get("output") or "").strip():
        said.append(NOT_XML.sub("", row["output"].rstrip()))
    if said:
        ET.SubElement(case, "system-out").text = "\n".join(said)
    return case


def _unique(names: list[str]) -> list[str]:
    """The test names, the second and later of a repeated one numbered (``... #2``)."""
    seen: dict[str, int] = {}
    out = []
    for name in names:
        seen[name] = seen.get(name, 0) + 1
        out.append(name if seen[name] == 1 else f"{name} #{seen[name]}")
    return out


def write_junit(path: Path, rows: list[Row]) -> None:
    by_file: dict[str, list[Row]] = {}
    for row in rows:
        by_file.setdefault(row.get("file") or row["fmu"], []).append(row)
    root = ET.Element("testsuites", name="mechfmu validate")
    totals = dict(tests=0, failures=0, skipped=0)
    for file, file_rows in by_file.items():
        suite_name = file_rows[0]["fmu"]
        results = [result_text(r) for r in file_rows]
        counts = dict(tests=len(file_rows), failures=results.count("FAIL"), skipped=results.count("SKIP"))
        suite = ET.SubElement(root, "testsuite", name=suite_name, errors="0", file=file,
                              **{k: str(v) for k, v in counts.items()})
        names = _unique([f"{r['case']} ({r['importer']})" for r in file_rows])
        suite.extend(_testcase(r, suite_name, n) for r, n in zip(file_rows, names))
        totals = {k: totals[k] + counts[k] for k in totals}
    root.attrib.update(errors="0", **{k: str(v) for k, v in totals.items()})
    path.parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
