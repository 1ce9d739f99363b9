"""Nearest valid names for a misspelled one, for error messages ("did you mean")."""

from __future__ import annotations

import difflib
from typing import Iterable


def nearest(name: str, valid: Iterable[str], n: int = 3) -> str:
    """'; nearest: a, b' for a misspelled name, or '; valid: ...' (up to 12) when none is close."""
    names = sorted(set(valid))
    close = difflib.get_close_matches(name, names, n=n, cutoff=0.5)
    if close:
        return f"; nearest: {', '.join(close)}"
    return f"; valid: {', '.join(names[:12])}{', ...' if len(names) > 12 else ''}" if names else ""
