"""The layout of issue 18, checked on the source: no import cycle between the project's modules
(imports inside functions counted), no import statement inside a function except of an optional
dependency, at most three functions over 80 lines, and the README's architecture section names
every package of the tree."""

import ast
import graphlib
from pathlib import Path

import pytest

from tests.source_trees import SOURCE_TREES, parsed

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("prbm", "fem", "elastica", "bcm", "argcheck", "planar", "validation")
# the optional extras of pyproject.toml (peer, dask, test, mutation), and pyvista, which needs the
# system's GL libraries to import (a report without them still runs): imported where used
OPTIONAL = {"openseespy", "dask", "distributed", "selenium", "hypothesis", "pytest", "mutmut", "pyvista"}
LONG_FUNCTION = 80
MAX_LONG_FUNCTIONS = 3


def modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            found[name] = path
    return found


def tree(path: Path) -> ast.Module:
    """A source file's syntax tree, parsed once for the three checks below and the other tests of the
    tree's syntax (tests/source_trees.py: they share one xdist group, so one worker parses the tree once)."""
    return parsed(path.read_text(encoding="utf-8"))


def imported_names(node: ast.AST, package: str) -> list[str]:
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if isinstance(node, ast.ImportFrom):
        base = package.rsplit(".", node.level - 1)[0] if node.level else ""
        module = ".".join(p for p in (base, node.module or "") if p)
        return [f"{module}.{alias.name}" for alias in node.names] + [module]
    return []


def import_graph() -> dict[str, set[str]]:
    """module -> the project modules (not package __init__s) it imports, anywhere in its body."""
    mods = modules()
    graph = {}
    for name, path in mods.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in ast.walk(tree(path)):
            for imported in imported_names(node, package):
                if imported in mods and mods[imported].name != "__init__.py" and imported != name:
                    targets.add(imported)
        graph[name] = targets
    return graph


@SOURCE_TREES
def test_no_import_cycle_between_modules():
    try:
        graphlib.TopologicalSorter(import_graph()).prepare()
    except graphlib.CycleError as error:
        pytest.fail(f"import cycle: {' -> '.join(error.args[1])}")


def functions(module: ast.AST):
    return [n for n in ast.walk(module) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]


@SOURCE_TREES
def test_imports_inside_functions_are_of_optional_dependencies_only():
    offenders = []
    for name, path in modules().items():
        for function in functions(tree(path)):
            for node in ast.walk(function):
                if isinstance(node, (ast.Import, ast.ImportFrom)) and not (
                    isinstance(node, ast.ImportFrom) and node.module == "__future__"
                ):
                    top = (node.names[0].name if isinstance(node, ast.Import) else node.module or "").split(".")[0]
                    if top not in OPTIONAL:
                        offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} in {function.name}()")
    assert not offenders, "imports inside functions:\n" + "\n".join(sorted(set(offenders)))


def logical_lines(function: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """A function's length as the lines on which its statements start, its docstring left out: what the
    code says, not how the formatter wraps a long call (ruff format puts each argument of a call too long
    for a line on its own line) nor how long its documentation is."""
    body = function.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:] if isinstance(body[0].value.value, str) else body
    return len({node.lineno for statement in body for node in ast.walk(statement) if isinstance(node, ast.stmt)})


@SOURCE_TREES
def test_at_most_three_functions_over_80_lines():
    long = []
    for name, path in modules().items():
        for function in functions(tree(path)):
            length = logical_lines(function)
            if length > LONG_FUNCTION:
                long.append(f"{path.relative_to(ROOT)}: {function.name} ({length} lines)")
    assert len(long) <= MAX_LONG_FUNCTIONS, "functions over 80 lines:\n" + "\n".join(long)


WRAPPED = '''
def f(a):
    """A docstring
    of two lines."""
    x = g(
        a,
        1,
    )
    if x:
        return x
    return -x
'''


def test_a_function_s_length_is_its_statements_not_its_wrapping():
    (function,) = ast.parse(WRAPPED).body
    assert logical_lines(function) == 4


def test_readme_architecture_names_every_package():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("## Architecture") :]
    section = section[: section.find("\n## ", 1)] if "\n## " in section[1:] else section
    packages = sorted(
        {str(p.parent.relative_to(ROOT)) for package in PACKAGES for p in (ROOT / package).rglob("__init__.py")}
    )
    missing = [p for p in packages if f"{p}/" not in section]
    assert not missing, f"README architecture section does not name {missing}"


@pytest.mark.xdist_group("layout-group-check")
def test_a_grouped_test_carries_its_group_on_the_workers(request):
    """``xdist_group`` works under pytest 9 (tests/conftest.py): a grouped test's node id ends in
    '@group' when the run distributes by group, so the tests sharing an expensive result share a worker."""
    if getattr(request.config.option, "loadgroup", False):
        assert request.node.nodeid.endswith("@layout-group-check")
