"""``mechfmu validate --junit FILE``: the table as JUnit XML, for CI systems that show test
results. One ``<testsuite>`` per FMU, one ``<testcase>`` per row (``classname`` the FMU,
``name`` the case and the importer); a FAIL row has a ``<failure>`` (its first problem as the
message, every problem in the text), a SKIP row ``<skipped>``; a LIMIT row passes, its note
in ``<system-out>``.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from .report import result_text

__all__ = ["write_junit"]


def _testcase(row: dict[str, Any]) -> ET.Element:
    case = ET.Element("testcase", classname=row["fmu"], name=f"{row['case']} ({row['importer']})",
                      time=f"{row.get('seconds') or 0.0:.3f}")
    result = result_text(row)
    problems = [str(p) for p in row.get("problems", [])]
    if result == "FAIL":
        failure = ET.SubElement(case, "failure", message=problems[0] if problems else "failed")
        failure.text = "\n".join(problems + [f"({n})" for n in row.get("notes", [])])
    elif result == "SKIP":
        ET.SubElement(case, "skipped", message="; ".join(problems) or "skipped")
    elif result == "LIMIT":
        ET.SubElement(case, "system-out").text = "LIMIT (the importer's solver; reported, not failed): " + \
            "; ".join(str(n) for n in row.get("notes", []))
    return case


def write_junit(path: Path, rows: list[dict[str, Any]]) -> None:
    by_fmu: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        by_fmu.setdefault(row["fmu"], []).append(row)
    root = ET.Element("testsuites", name="mechfmu validate")
    totals = dict(tests=0, failures=0, skipped=0)
    for fmu, fmu_rows in by_fmu.items():
        results = [result_text(r) for r in fmu_rows]
        counts = dict(tests=len(fmu_rows), failures=results.count("FAIL"), skipped=results.count("SKIP"))
        suite = ET.SubElement(root, "testsuite", name=fmu, errors="0", **{k: str(v) for k, v in counts.items()})
        suite.extend(_testcase(r) for r in fmu_rows)
        totals = {k: totals[k] + counts[k] for k in totals}
    root.attrib.update(errors="0", **{k: str(v) for k, v in totals.items()})
    path.parent.mkdir(parents=True, exist_ok=True)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
