"""The repository's Python sources parsed once per test process, for the tests that read their syntax:
tests/project/test_layout.py (import graph, imports inside functions, long functions),
tests/project/test_no_history.py (docstrings) and tests/validation/test_cache_import_scan.py (every import).

``parsed(text)`` is ``ast.parse(text)``, kept for the process (a parse of the whole tree is about a
CPU-second); ``SOURCE_TREES`` puts those tests in one xdist group, so that one worker parses each file
once for all of them. The trees are shared: a test reads them and never changes them.
"""

from __future__ import annotations

import ast
import functools

import pytest

SOURCE_TREES = pytest.mark.xdist_group("source-trees")


@functools.lru_cache(maxsize=None)
def parsed(text: str) -> ast.Module:
    """``ast.parse(text)``, once per text in this process."""
    return ast.parse(text)
