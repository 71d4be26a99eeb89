"""The package's architecture rules, read from the source: one clamp of the damping, layering without circles."""

from __future__ import annotations

import ast
import re

from conftest import ROOT

SRC = ROOT / "src" / "uavdamp"
BOUNDS = re.compile(r"\b(c_min|c_max|damping_min|damping_max)\b")


def _clamps(tree: ast.AST, contract_clip: bool):
    """Calls of min, max or a clip whose arguments name a damper bound (but `uavdamp.contract.clip` itself when
    the module imports it, and the lower end of a log-spaced candidate grid, which cannot start at 0)."""
    grids = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "attr", "") == "geomspace"]
    inside_grid = {id(d) for g in grids for d in ast.walk(g)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and id(node) not in inside_grid:
            name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            if name == "clip" and isinstance(node.func, ast.Name) and contract_clip:
                continue
            if name in ("min", "max", "clip", "minimum", "maximum") and BOUNDS.search(ast.unparse(node)):
                yield node.lineno, ast.unparse(node)


def _imports_contract_clip(tree: ast.AST) -> bool:
    return any(
        isinstance(n, ast.ImportFrom) and n.module == "uavdamp.contract" and any(a.name == "clip" for a in n.names)
        for n in ast.walk(tree)
    )


def test_the_damping_is_clamped_in_one_place():
    """`uavdamp.contract.clip` is the only clamp of a damping demand to [c_min, c_max]: a plant, a law or a
    strategy that clamps on its own would let the bounds drift apart (the architecture issue)."""
    found = []
    for path in SRC.rglob("*.py"):
        tree = ast.parse(path.read_text())
        imported = _imports_contract_clip(tree)
        for function in (n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)):
            if path.name == "contract.py" and function.name == "clip":
                continue
            found += [f"{path.relative_to(SRC)}:{line}: {text}" for line, text in _clamps(function, imported)]
    assert sorted(set(found)) == [], "clamp the damping with uavdamp.contract.clip only"


def _imports(path) -> set[str]:
    tree = ast.parse(path.read_text())
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("uavdamp"):
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names |= {a.name for a in node.names if a.name.startswith("uavdamp")}
    return names


def test_the_packages_import_without_circles():
    """The import graph between uavdamp's packages and top-level modules is acyclic (module-level imports)."""

    def unit(module: str) -> str:
        parts = module.split(".")
        return ".".join(parts[:2]) if len(parts) > 1 else module

    graph: dict[str, set[str]] = {}
    for path in SRC.rglob("*.py"):
        module = "uavdamp." + ".".join(path.relative_to(SRC).with_suffix("").parts)
        graph.setdefault(unit(module), set()).update(unit(m) for m in _imports(path))
    for node in graph:
        graph[node].discard(node)
        graph[node].discard("uavdamp")
    state: dict[str, int] = {}

    def visit(node, trail):
        if state.get(node) == 1:
            raise AssertionError(f"import circle: {' -> '.join([*trail, node])}")
        if state.get(node) == 2:
            return
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            visit(nxt, [*trail, node])
        state[node] = 2

    for node in sorted(graph):
        visit(node, [])
