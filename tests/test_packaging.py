"""Dependencies as used: every required dependency is imported by the package, and every optional
extra that the package imports has a one-line install hint where it is imported."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SRC = REPO / "src" / "framefree"
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text())

#: distribution name -> import name, where they differ
IMPORT_NAMES = {"pyzmq": "zmq", "scikit-learn": "sklearn", "dask[distributed]": "dask"}


def _name(requirement: str) -> str:
    return re.split(r"[<>=!~ ;]", requirement, maxsplit=1)[0]


def _sources() -> str:
    return "\n".join(p.read_text() for p in SRC.rglob("*.py"))


def _imports(module: str, text: str) -> bool:
    return re.search(rf"^\s*(import|from)\s+{re.escape(module)}\b", text, re.MULTILINE) is not None


def test_every_required_dependency_is_imported_by_the_package():
    text = _sources()
    for req in PYPROJECT["project"]["dependencies"]:
        name = _name(req)
        module = IMPORT_NAMES.get(name, name)
        assert _imports(module, text), f"{name} is a dependency but src/ never imports {module}"


def test_optional_extras_have_an_install_hint_where_imported():
    extras = PYPROJECT["project"]["optional-dependencies"]
    hints = {"robot": "mujoco", "dask": "dask", "ray": "ray"}
    text = _sources()
    for extra, module in hints.items():
        assert extra in extras
        assert _imports(module, text), f"src/ never imports {module} (extra {extra!r})"
        assert f"pip install 'framefree[{extra}]'" in text, f"no install hint for [{extra}]"
    # scikit-learn is needed only by scikit-learn's own tools (which then call the estimator)
    assert any(_name(r) == "scikit-learn" for r in extras["sklearn"])
    assert any(_name(r) == "scikit-learn" for r in extras["dev"])
