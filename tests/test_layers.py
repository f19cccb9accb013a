"""The layers of docs/architecture.md hold: every import points down, and no modules import each
other in a circle (imports inside functions included)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"

#: layer of each top-level part of the package, bottom first (docs/architecture.md)
LAYERS = [
    {"errors", "labels", "_version", "_lazy"},
    {"core"},
    {"descriptors", "samples", "rejection", "scope"},
    {"classifier", "io"},
    {"datasets"},
    {"plots", "replica"},
    {"online"},
    {"library", "benchmark", "view"},
    {"robot"},
    {"commands", "cli"},
]
RANK = {part: k for k, parts in enumerate(LAYERS) for part in parts}


def _modules() -> dict[str, Path]:
    out = {}
    for path in (SRC / "framefree").rglob("*.py"):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(name: str, path: Path, known: set[str]) -> set[str]:
    """framefree modules that ``name`` imports (resolved to the deepest known module)."""
    is_pkg = path.name == "__init__.py"
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        targets = []
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_pkg else name.split(".")[:-1]
                base = base[: len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            targets = [f"{mod}.{a.name}" if f"{mod}.{a.name}" in known else mod for a in node.names]
        elif isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        for t in targets:
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t.startswith("framefree") and t != name:
                found.add(t)
    return found


def _part(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


MODULES = _modules()
GRAPH = {m: _imports(m, p, set(MODULES)) for m, p in MODULES.items()}


def test_every_part_has_a_layer():
    parts = {_part(m) for m in MODULES} - {""}
    assert parts <= set(RANK), f"parts without a layer in docs/architecture.md: {parts - set(RANK)}"


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m != "framefree"))
def test_imports_point_down(module: str):
    here = _part(module)
    for target in GRAPH[module]:
        there = _part(target)
        if target == "framefree":
            pytest.fail(f"{module} imports the package facade framefree/__init__.py")
        if there == here:
            continue
        assert RANK[there] < RANK[here], f"{module} imports {target}: an upward or sideways import"
    if module.startswith("framefree.online.") and not module.startswith("framefree.online.paper"):
        paper = [t for t in GRAPH[module] if t.startswith("framefree.online.paper")]
        assert not paper, f"the default recognizer's {module} imports the paper's {paper}"


def test_no_import_circles():
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    assert not circles, f"modules that import each other: {circles}"


def _code_lines(node: ast.FunctionDef) -> int:
    """Lines of a function from its first statement after the docstring to its end."""
    body = node.body
    first = body[0]
    docstring = isinstance(first, ast.Expr) and isinstance(getattr(first, "value", None), ast.Constant) \
        and isinstance(first.value.value, str)
    start = (body[1].lineno if len(body) > 1 else first.end_lineno) if docstring else first.lineno
    return node.end_lineno - start + 1


def test_functions_are_short_or_say_why():
    """No function has more than 60 lines of code (docstring aside) unless a comment right above
    it says why it is kept whole."""
    long = []
    for name, path in MODULES.items():
        lines = path.read_text().splitlines()
        for node in ast.walk(ast.parse("\n".join(lines))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and _code_lines(node) > 60:
                above = node.decorator_list[0].lineno if node.decorator_list else node.lineno
                if not lines[above - 2].lstrip().startswith("#"):
                    long.append(f"{name}.{node.name} ({_code_lines(node)} lines)")
    assert not long, f"functions over 60 lines without a reason next to them: {long}"
