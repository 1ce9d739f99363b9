"""The libraries stay independent: prbm/, fem/, elastica/ and bcm/ import none of each other,
nor validation/ (only validation/ and synthesis/ may tie them together)."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LIBRARIES = ["prbm", "fem", "elastica", "bcm"]


def imported_top_levels(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


@pytest.mark.parametrize("library", LIBRARIES)
def test_library_imports_no_other_library(library):
    forbidden = (set(LIBRARIES) - {library}) | {"validation", "synthesis"}
    offenders = {
        str(p.relative_to(ROOT)): sorted(imported_top_levels(p) & forbidden) for p in (ROOT / library).rglob("*.py")
    }
    offenders = {k: v for k, v in offenders.items() if v}
    assert not offenders, f"{library}/ imports {offenders}"


def test_planar_is_a_leaf():
    """``planar`` (the mechanism vocabulary every library may import) imports nothing of the project."""
    project = set(LIBRARIES) | {"validation", "argcheck", "references", "tests", "cases"}
    found = {
        str(p.relative_to(ROOT)): sorted(imported_top_levels(p) & project) for p in (ROOT / "planar").rglob("*.py")
    }
    assert not {k: v for k, v in found.items() if v}, found
