"""The Python packages under python/ are layered: no circle among their modules, no module
importing another's private name, and no module passing on what it imports (a module imports
what it uses, at its top; only a package's ``__init__`` presents other modules' names), and
no function is longer than 150 lines.

A module uses another when it imports it or a name from it: ``from .x import ...``,
``from pkg.x import ...``, ``import pkg.x``, at the top or inside a function. A package's
``__init__`` naming its own children is how it presents them, and does not count. Only the
source is read (``ast``): no package is imported, no FMU is needed.
"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path
from typing import NamedTuple

ROOT = Path(__file__).resolve().parents[2]
PYTHON = ROOT / "python"

Module = tuple[str, ...]  # a dotted name, split: ("mechfmu_sweep", "runner")


@cache
def modules() -> dict[Module, Path]:
    """Every module of the packages under python/ (a package by its folder's name)."""
    found = {}
    for init in sorted(PYTHON.glob("*/__init__.py")):
        for path in sorted(init.parent.rglob("*.py")):
            parts = path.relative_to(PYTHON).with_suffix("").parts
            found[parts[:-1] if parts[-1] == "__init__" else parts] = path
    return found


@cache
def tree(module: Module) -> ast.Module:
    path = modules()[module]
    return ast.parse(path.read_text(), filename=str(path))


def dotted(module: Module) -> str:
    return ".".join(module)


def where(module: Module, node: ast.expr | ast.stmt) -> str:
    return f"{modules()[module].relative_to(ROOT)}:{node.lineno}"


def is_package(module: Module) -> bool:
    return modules()[module].name == "__init__.py"


def is_private(name: str) -> bool:
    return name.startswith("_") and not name.endswith("__")


def owner(name: Module) -> Module | None:
    """The module a dotted name is in: its longest prefix that is a module."""
    while name and name not in modules():
        name = name[:-1]
    return name or None


class Import(NamedTuple):
    node: ast.Import | ast.ImportFrom
    target: Module  # the module imported, or the one the name is imported from
    name: str | None  # the name imported from ``target``; None: a module is imported
    local: str  # what the import binds in the importing module
    bound: Module | None  # the module ``local`` is (None: a name of ``target``)


def imports(module: Module) -> list[Import]:
    """The module's imports of the packages' modules and of their names."""
    package = module if is_package(module) else module[:-1]
    found = []
    for node in ast.walk(tree(module)):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else ()
            source = base + tuple(node.module.split(".") if node.module else ())
            for alias in node.names:
                local = alias.asname or alias.name
                child = source + (alias.name,)
                if child in modules():
                    found.append(Import(node, child, None, local, child))
                elif (target := owner(source)) is not None:
                    found.append(Import(node, target, alias.name, local, None))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                name = tuple(alias.name.split("."))
                if (target := owner(name)) is not None:
                    # `import pkg.x` binds `pkg`; `import pkg.x as y` binds the module
                    local, bound = (alias.asname, target) if alias.asname else (name[0], name[:1])
                    found.append(Import(node, target, None, local, bound))
    return found


def arrows() -> dict[tuple[Module, Module], str]:
    """{(module, a module it uses): the first place that draws the arrow}."""
    found = {}
    for module in modules():
        for imp in imports(module):
            if imp.target == module or (is_package(module) and imp.target[:len(module)] == module):
                continue
            found.setdefault((module, imp.target), where(module, imp.node))
    return found


def circles(edges) -> list[list[Module]]:
    """The strongly connected components of more than one module (Tarjan)."""
    graph: dict[Module, set[Module]] = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    index: dict[Module, int] = {}
    low: dict[Module, int] = {}
    stack: list[Module] = []
    out = []

    def visit(v: Module) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = [stack.pop()]
            while component[-1] != v:
                component.append(stack.pop())
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_both_packages_are_read():
    assert {"mechfmu_validate", "mechfmu_sweep"} <= {m[0] for m in modules()}


def test_no_circle_among_modules():
    edges = arrows()
    problems = []
    for component in circles(edges):
        problems.append(" <-> ".join(map(dotted, component)))
        problems += [f"    {dotted(a)} -> {dotted(b)}   {at}" for (a, b), at in sorted(edges.items())
                     if a in component and b in component]
    assert not problems, "circles among the modules under python/:\n" + "\n".join(problems)


def private_uses(module: Module) -> list[str]:
    """Where the module imports or reads a private name of another module: ``from .x import
    _name``, ``x._name``, ``pkg.x._name``."""
    found = []
    bound = {}
    for imp in imports(module):
        if imp.name is not None and is_private(imp.name) and imp.target != module:
            found.append(f"{where(module, imp.node)}: from {dotted(imp.target)} import {imp.name}")
        if imp.bound is not None:
            bound[imp.local] = imp.bound
    for node in ast.walk(tree(module)):
        chain = []
        while isinstance(node, ast.Attribute):
            chain.append(node.attr)
            node = node.value
        if not (chain and isinstance(node, ast.Name) and node.id in bound):
            continue
        target = bound[node.id]
        for attr in reversed(chain):
            if target + (attr,) not in modules():
                if is_private(attr) and target != module:
                    found.append(f"{where(module, node)}: {dotted(target)}.{attr}")
                break
            target += (attr,)
    return found


def test_no_private_name_crosses_modules():
    problems = sorted({p for module in modules() for p in private_uses(module)})
    assert not problems, ("private names used outside their module (make the name public where it is "
                          "defined, or move it where it is used):\n" + "\n".join(problems))


def test_imports_are_at_the_top():
    """An import below a module's code passes names on to an old path, or hides a circle."""
    problems = []
    for module in modules():
        code_seen = False
        for statement in tree(module).body:
            if isinstance(statement, (ast.Import, ast.ImportFrom)):
                if code_seen:
                    problems.append(where(module, statement))
            elif not (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant)):
                code_seen = True  # anything but the docstring
    assert not problems, "imports below a module's code:\n" + "\n".join(problems)


def listed(module: Module) -> set[str]:
    """The names in the module's ``__all__``."""
    for statement in tree(module).body:
        if isinstance(statement, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in statement.targets):
            return {e.value for e in ast.walk(statement.value) if isinstance(e, ast.Constant)}
    return set()


def test_no_module_passes_on_what_it_imports():
    """A name imported from the packages is used where it is imported; its users import it
    from the module that defines it (a package's ``__init__`` presenting its API excepted)."""
    problems = []
    for module in modules():
        if is_package(module):
            continue
        used = {n.id for n in ast.walk(tree(module)) if isinstance(n, ast.Name)}
        for imp in imports(module):
            origin = f"{imp.local} (from {dotted(imp.target)})"
            if imp.local in listed(module):
                problems.append(f"{where(module, imp.node)}: {origin} is in __all__")
            elif imp.local not in used:
                problems.append(f"{where(module, imp.node)}: {origin} is not used here")
    assert not problems, "names passed on (import them from their module instead):\n" + "\n".join(problems)


#: the longest a function of the packages may be: past it, it almost always holds two ideas
LONGEST_FUNCTION = 150


def test_no_function_is_longer_than_the_limit():
    long = [
        f"{where(module, node)} {node.name}: {node.end_lineno - node.lineno + 1} lines"
        for module in modules()
        for node in ast.walk(tree(module))
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
        and node.end_lineno - node.lineno + 1 > LONGEST_FUNCTION
    ]
    assert not long, f"functions over {LONGEST_FUNCTION} lines (split them by idea):\n" + "\n".join(long)
