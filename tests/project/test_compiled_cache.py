"""No numba-cached function calls a compiled function of another module.

numba keys a function's on-disk cache on its own source file only ("Notes on caching" in numba's
documentation): a ``cache=True`` function that calls a compiled function defined in another file
keeps running the machine code of the old callee after that file is edited, silently. So every
compiled function a cached function calls must live in the cached function's own module
(`fem.kernel`, `fem.numbering`, `elastica.integrator` each hold everything they compile).
The detector is checked on a planted pair of modules that breaks the rule.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("prbm", "fem", "elastica", "bcm", "argcheck", "planar", "validation")


def _decorator_is_compiled(node: ast.expr) -> tuple[bool, bool]:
    """(compiled, cached) of one decorator: njit/jit, bare or called, with cache=True or not."""
    call = node if isinstance(node, ast.Call) else None
    target = call.func if call else node
    name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
    if name not in ("njit", "jit"):
        return False, False
    cached = bool(call) and any(
        k.arg == "cache" and isinstance(k.value, ast.Constant) and k.value.value is True for k in call.keywords
    )
    return True, cached


def _resolve(module: str, level: int, name: str | None) -> str:
    """Absolute module name of ``from <level dots><name> import ...`` inside ``module``."""
    if level == 0:
        return name or ""
    base = module.split(".")[:-level]
    return ".".join(base + ([name] if name else []))


def cross_module_calls(sources: dict[str, str]) -> list[str]:
    """Every place a cached compiled function uses a compiled function of another module.
    ``sources``: module name (``pkg.mod``) -> source text. Only the modules whose text says "jit" can
    define or call a compiled function, so only they are parsed; every name still counts as a module."""
    trees = {m: ast.parse(s) for m, s in sources.items() if "jit" in s}
    compiled = {
        m: {
            f.name
            for f in ast.walk(t)
            if isinstance(f, ast.FunctionDef) and any(_decorator_is_compiled(d)[0] for d in f.decorator_list)
        }
        for m, t in trees.items()
    }
    problems = []
    for module, tree in trees.items():
        names: dict[str, tuple[str, str]] = {}  # local name -> (module, function)
        modules: dict[str, str] = {}  # local name -> module
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                source = _resolve(module, node.level, node.module)
                for alias in node.names:
                    local = alias.asname or alias.name
                    if f"{source}.{alias.name}" in sources:
                        modules[local] = f"{source}.{alias.name}"
                    else:
                        names[local] = (source, alias.name)
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    modules[alias.asname or alias.name.split(".")[0]] = alias.name
        for function in (f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef)):
            if not any(_decorator_is_compiled(d)[1] for d in function.decorator_list):
                continue
            for node in ast.walk(function):
                if isinstance(node, ast.Name) and node.id in names:
                    source, target = names[node.id]
                    if source != module and target in compiled.get(source, ()):
                        problems.append(f"{module}.{function.name} calls {source}.{target}")
                elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in modules:
                    source = modules[node.value.id]
                    if source != module and node.attr in compiled.get(source, ()):
                        problems.append(f"{module}.{function.name} calls {source}.{node.attr}")
    return problems


def project_sources() -> dict[str, str]:
    out = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = path.read_text()
    return out


def test_no_cached_compiled_function_calls_into_another_module():
    assert cross_module_calls(project_sources()) == []


def test_the_detector_finds_a_cached_function_calling_another_files_kernel():
    callee = "from numba import njit\n\n@njit(cache=True)\ndef element(x):\n    return 2.0 * x\n"
    by_name = (
        "from numba import njit\nfrom .kernel import element\n\n"
        "@njit(cache=True)\ndef newton(x):\n    return element(x) + 1.0\n"
    )
    by_module = (
        "from numba import njit\nfrom . import kernel as k\n\n"
        "@njit(cache=True)\ndef newton(x):\n    return k.element(x) + 1.0\n"
    )
    assert cross_module_calls({"pkg.kernel": callee, "pkg.newton": by_name}) == [
        "pkg.newton.newton calls pkg.kernel.element"
    ]
    assert cross_module_calls({"pkg.kernel": callee, "pkg.newton": by_module}) == [
        "pkg.newton.newton calls pkg.kernel.element"
    ]
    uncached = by_name.replace("@njit(cache=True)", "@njit")
    assert cross_module_calls({"pkg.kernel": callee, "pkg.newton": uncached}) == []
