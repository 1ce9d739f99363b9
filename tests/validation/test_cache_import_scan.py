"""The run cache's import scan (`validation.run.cache.import_statements`): it reads only the places an
import can begin instead of parsing whole files, and must find every import a full parse finds."""

from __future__ import annotations

import ast
import textwrap
from functools import lru_cache

from validation.run import cache
from validation.run.cache import ROOT, import_statements

from tests.source_trees import SOURCE_TREES, parsed


def _walk(body):
    """Every import statement of a parsed body, as a full syntax-tree walk finds them."""
    for node in ast.walk(ast.Module(body=body, type_ignores=[])):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node


def _dumps(nodes) -> set[str]:
    return {ast.dump(node) for node in nodes}


# (an import inside a block read past its end does not parse: the block's indentation ends it)
TRICKY = textwrap.dedent('''\
    """A docstring that mentions the word import and from, and a (bracket."""
    import a.b, c as d
    from .e import (f,  # a comment inside the brackets, (with one of its own
                    g as h)
    from ..i import \\
        j
    x = 1; import k; s = "("
    try: import l
    except ImportError: from m import n
    if x: from o import p
    else:
        import q


    class R:
        def s(self):
            from t import u
            x = 1; import k2; s = "("
            from .e2 import (f2,  # a comment inside the brackets, (with one of its own
                             g2)
            with open("v") as w:
                import y
            match x:
                case 1:
                    import z
            return [important for important in ()]
    ''')


def test_the_scan_finds_what_a_full_parse_finds_in_every_form_of_import():
    expected = _dumps(_walk(ast.parse(TRICKY).body))
    assert len(expected) == 13
    assert _dumps(import_statements(TRICKY)) == expected


@lru_cache(maxsize=None)
def _repository_sources():
    return sorted(p for package in cache.PACKAGES for p in (ROOT / package).rglob("*.py"))


@SOURCE_TREES  # the full parse of each file is shared with the other tests of the tree's syntax
def test_the_scan_loses_no_import_of_any_repository_source():
    # a string that reads as an import may add one (a dependency too many invalidates, never goes stale)
    for path in _repository_sources():
        source = path.read_text(encoding="utf-8")
        assert _dumps(_walk(parsed(source).body)) <= _dumps(import_statements(source)), path


def test_prose_that_does_not_parse_as_an_import_adds_nothing():
    source = 'def f():\n    """\n    from the start, import what is needed (a list\n    """\n    return 1\n'
    assert import_statements(source) == []


def test_every_package_of_the_repository_keys_the_cache():
    """A run's key hashes the sources it imports from these packages: one left out (planar's loads, the
    bibliography's seed keys) would let a change to it reuse results computed before it."""
    packages = {p.parent.name for p in ROOT.glob("*/__init__.py")} - {"tests"}
    assert packages <= set(cache.PACKAGES), sorted(packages - set(cache.PACKAGES))


def test_a_run_of_the_mechanism_elastica_is_keyed_on_planar():
    assert any(p.parts[-2] == "planar" for p in cache.source_files("elastica"))
