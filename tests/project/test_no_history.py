"""No history in the production code, and every citation by a key the bibliography has.

Production code is every ``.py`` file of prbm/, fem/, elastica/, bcm/, argcheck/, planar/, references/ and
validation/ (not tests/, not cases/).  What the code says is what it does and why (the mathematics,
the reference); where it came from (a tracker's item, a session, a day's timing) belongs in the commit
message or a benchmark's output.

1. No tracker reference anywhere in a production file's text (docstrings, comments and strings): none
   of ``HISTORY_PATTERNS`` matches (case-insensitive):
   ``issue 14``, ``issues 14``, ``issue #14``, ``issue#14``; ``item 3 of issue``; ``session 19``;
   ``ticket 7`` / ``ticket #7``, ``bug #7``, ``PR #7``, ``pull request 7``; a date ``2026-01-31``;
   ``re-timed at``, ``on this machine``, ``today``.
2. Every citation in a docstring or comment names a key of ``references.REFERENCES``: a bracket
   opening on a key-shaped word, ``[word`` followed by ``,``, ``]``, a space or a line end, where the
   word is author+year shaped (letters then four digits, ``bapat2015``) or begins with the surname of
   a reference (``ananthasuresh_l18``), must be a known key.
3. Docstrings and comments cite a source document by its key, never by its seed number
   (``seed 000``, ``Seed 004``); strings the code prints (model names, messages) are output and may.
4. ``references`` is a leaf: it imports nothing of the project, so every package may import it; and
   every seed file a case file names as its source has a key.
"""

import ast
import io
import re
import tokenize
import tomllib
from functools import lru_cache
from pathlib import Path

import pytest

from references import REFERENCES, key_of_seed_file
from tests.source_trees import SOURCE_TREES, parsed

ROOT = Path(__file__).resolve().parents[2]
PRODUCTION = ("prbm", "fem", "elastica", "bcm", "argcheck", "planar", "references", "validation")
PROJECT = set(PRODUCTION) | {"tests", "cases"}

HISTORY_PATTERNS = {
    "issue number": r"\bissues?\s*#?\s*\d+",
    "item of an issue": r"\bitem\s+\d+\s+of\s+(?:the\s+)?issue",
    "session number": r"\bsession\s+#?\d+",
    "ticket, bug or PR number": r"\b(?:ticket|bug|PR|pull\s+request)\s*#\s*\d+|\b(?:ticket|pull\s+request)\s+\d+",
    "date": r"\b20\d\d-[01]\d-[0-3]\d\b",
    "re-timing": r"\bre-?timed\s+at\b",
    "this machine": r"\bon\s+this\s+machine\b",
    "today": r"\btoday\b",
}
HISTORY = re.compile("|".join(f"(?P<p{i}>{p})" for i, p in enumerate(HISTORY_PATTERNS.values())), re.IGNORECASE)

CITATION = re.compile(r"\[(?P<key>[a-z][a-z0-9_]*)(?=[,\]\s]|$)", re.MULTILINE)
YEAR_KEY = re.compile(r"[a-z]+\d{4}[a-z]?")
SURNAMES = {ref.surname for ref in REFERENCES.values()}
SEED_ID = re.compile(r"\bseed\s?0\d\d(?![\w-])", re.IGNORECASE)
SEED_FILE = re.compile(r"\d{3}_[0-9a-f]{16}\.txt")


def production_files() -> list[Path]:
    return sorted(p for package in PRODUCTION for p in (ROOT / package).rglob("*.py"))


def history_hits(text: str) -> list[str]:
    """'line: matched text' for every history pattern in ``text``."""
    return [f"{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)!r}" for m in HISTORY.finditer(text)]


@lru_cache(maxsize=None)
def prose(text: str) -> list[tuple[int, str]]:
    """(line, text) of every docstring (module, class, function, and bare string statements) and every
    comment of a source file (read once per text: the two prose checks below share one worker with the
    other tests of the tree's syntax, tests/source_trees.py, and so one parse of the tree)."""
    found = []
    for node in ast.walk(parsed(text)):
        body = getattr(node, "body", None)
        for statement in body if isinstance(body, list) else []:
            if (
                isinstance(statement, ast.Expr)
                and isinstance(statement.value, ast.Constant)
                and isinstance(statement.value.value, str)
            ):
                found.append((statement.lineno, statement.value.value))
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type == tokenize.COMMENT:
            found.append((token.start[0], token.string))
    return found


def cited_like_a_key(key: str) -> bool:
    """Whether ``[key`` reads as a citation: author+year shaped, or opening with a reference's surname."""
    return bool(YEAR_KEY.fullmatch(key)) or re.match(r"[a-z]+", key).group(0) in SURNAMES


def unknown_citations(text: str) -> list[str]:
    return [
        f"{line + words.count(chr(10), 0, m.start())}: [{m.group('key')}"
        for line, words in prose(text)
        for m in CITATION.finditer(words)
        if cited_like_a_key(m.group("key")) and m.group("key") not in REFERENCES
    ]


def seed_numbers(text: str) -> list[str]:
    return [
        f"{line + words.count(chr(10), 0, m.start())}: {m.group(0)!r}"
        for line, words in prose(text)
        for m in SEED_ID.finditer(words)
    ]


def _offenders(check) -> dict[str, list[str]]:
    found = {str(p.relative_to(ROOT)): check(p.read_text(encoding="utf-8")) for p in production_files()}
    return {path: hits for path, hits in found.items() if hits}


def test_production_code_has_no_tracker_references_or_dated_timings():
    offenders = _offenders(history_hits)
    assert not offenders, "history in production code (say what the code does and why):\n" + "\n".join(
        f"{path}:{hit}" for path, hits in offenders.items() for hit in hits
    )


@SOURCE_TREES
def test_every_citation_names_a_key_of_the_bibliography():
    offenders = _offenders(unknown_citations)
    assert not offenders, (
        f"citations of keys not in references.REFERENCES ({', '.join(sorted(REFERENCES))}):\n"
        + "\n".join(f"{path}:{hit}" for path, hits in offenders.items() for hit in hits)
    )


@SOURCE_TREES
def test_docstrings_and_comments_cite_by_key_not_by_seed_number():
    offenders = _offenders(seed_numbers)
    assert not offenders, "cite by key ([bapat2015, eq 47]), not by seed number:\n" + "\n".join(
        f"{path}:{hit}" for path, hits in offenders.items() for hit in hits
    )


@pytest.mark.parametrize(
    "text, caught",
    [
        ('"""Model applicability (issue 12)."""', True),
        ("# issue #12 item 3", True),
        ("x = 1  # item 3 of issue twelve", True),
        ('"""Found in session 19."""', True),
        ('"""1.45 ms for a run re-timed at 0.88."""', True),
        ('"""A FitRangeWarning is issued and the nearest branch is evaluated."""', False),
        ('"""The tissue 12 mm thick."""', False),
    ],
)
def test_the_history_patterns_catch_a_planted_reference(text, caught):
    assert bool(history_hits(text)) is caught


@pytest.mark.parametrize(
    "text, unknown",
    [
        ('"""The fits [bapat2015, eqs 41-49]."""', []),
        ('"""The fits [bapat2016, eqs 41-49]."""', ["1: [bapat2016"]),
        ('"""End moment [ananthasuresh_l18, 16:59-21:58]."""', []),
        ('"""End moment [ananthasuresh_lecture18]."""', ["1: [ananthasuresh_lecture18"]),
        ("x = 1  # [smith1999] says so", ["1: [smith1999"]),
        ('"""Units [m], a list [str, int], an index [i]."""', []),
    ],
)
def test_the_citation_check_knows_a_key_from_other_brackets(text, unknown):
    assert unknown_citations(text) == unknown


def test_references_is_a_leaf():
    imported = set()
    for path in (ROOT / "references").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                imported |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                imported.add(node.module.split(".")[0])
    assert not (imported & (PROJECT - {"references"})), sorted(imported & PROJECT)


def test_every_seed_file_a_case_cites_has_a_key():
    files = set()

    def walk(value):
        if isinstance(value, dict):
            source = value.get("source")
            if isinstance(source, dict) and isinstance(source.get("file"), str):
                files.add(Path(source["file"]).name)
            for item in value.values():
                walk(item)
        elif isinstance(value, list):
            for item in value:
                walk(item)

    for path in (ROOT / "cases").rglob("*.toml"):
        walk(tomllib.loads(path.read_text(encoding="utf-8")))
    seeds = sorted(name for name in files if SEED_FILE.fullmatch(name))
    assert seeds, "no case file names a seed file"
    assert {name: key_of_seed_file(name) for name in seeds}
