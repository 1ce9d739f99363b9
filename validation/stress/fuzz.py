"""Mutated case files: the shipped cases with one to three things broken, generated from a seed.

A mutant is a shipped case file (``SOURCES`` or every case) parsed to a dict, changed by a few
``Mutation`` records and written back with ``tomli_w``; a raw-byte mutation (bytes that are not
UTF-8, a file cut short) then acts on those bytes. Each mutation is plain data (kind, path, value),
so a mutant is rebuilt from its source and mutations alone, and shrinking drops mutations or
deletes fields one at a time (a deletion the shrinker adds is a mutation of kind ``shrink``).

Kinds (``KINDS``): a deleted field or table, a value of the wrong type, NaN, +-inf, 0, a negative,
1e+-300, a huge count (an integer or a list of thousands of entries), an unknown key, unicode text
(in a value or a key), a path-like id or name, a dangling node or member name, a zero-length beam,
bytes that are not UTF-8, and a truncated file. The path of a mutation is picked at random among
the nodes of the document that the kind applies to (numbers for NaN, names for dangling names, ...).
"""

from __future__ import annotations

import copy
import math
import random
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import tomli_w

from validation.case.loader import CASES_DIR, find_case_files

Where = tuple  # a path into the document: table keys (str) and list indices (int)

# small, fast cases of every kind (segments, mechanisms, chapter examples, seeds): the CI set
SOURCES = (
    "segments/slfp_alone.toml",
    "segments/curved_pinned_pinned.toml",
    "segments/fixed_guided_two_spring.toml",
    "segments/parallel_guided_mechanism.toml",
    "benchmarks/pure_moment_roll_up.toml",
    "benchmarks/follower_tip_load.toml",
    "benchmarks/lee_frame.toml",
    "chapter2/lyon_fixed_guided.toml",
    "chapter3/table3_1_load_combination.toml",
    "chapter6/example2.toml",
    "chapter6/example3.toml",
    "chapter7/example1_ma.toml",
    "chapter7/example3.toml",
    "chapter9/test1a_friction.toml",
    "chapter9/test2_partially_compliant_fourbar.toml",
    "chapter9/test3_specimen1_dof.toml",
    "seed003/circular_guided.toml",
    "seed004/strip_tip_force_prbm.toml",
)

DELETE = "<deleted>"  # the value of a deletion
# the document kinds
TREE_KINDS = (
    "delete_field",
    "delete_table",
    "wrong_type",
    "nan",
    "inf",
    "minus_inf",
    "zero",
    "negative",
    "tiny",
    "huge",
    "huge_count",
    "unknown_key",
    "unicode",
    "unicode_key",
    "path_id",
    "dangling_name",
    "zero_length",
)
RAW_KINDS = ("non_utf8", "truncate")
KINDS = TREE_KINDS + RAW_KINDS

# keys whose string value (or list of strings) names a node, member, body, method or output of the case
NAME_KEYS = frozenset(
    {
        "point",
        "node",
        "start",
        "end",
        "nodes",
        "members",
        "member",
        "body",
        "against",
        "method",
        "methods",
        "output",
        "compare",
        "input_moment_at",
        "points",
        "quantities",
        "quantity",
    }
)
ID_KEYS = frozenset({"id", "name"})
WRONG_TYPES: tuple[object, ...] = ("text", 7, 2.5, True, [], {}, [1.0, 2.0], {"x": 1}, "1.0", "")
UNICODE = ("ñandú", "🚀", "\u202eevil", "a\u0301", "\u200b", "中文", "\U0010ffff", "\x00", "\ud7ff", "Ω" * 40)
PATH_IDS = (
    "../../etc/passwd",
    "a/b",
    "/tmp/x",
    "C:\\temp\\x",
    ".",
    "..",
    "",
    " ",
    "con",
    "x" * 300,
    "a\x00b",
    "~",
    "$HOME",
    "*",
    "?[a]",
    "nul.toml",
    "-rf",
    "\n",
)
UNKNOWN_KEYS = ("lenght", "zzz", "Élan", "elements ", "_", "ids", "🚀")
NON_FINITE = {"nan": math.nan, "inf": math.inf, "minus_inf": -math.inf}
TINY = (1e-300, -1e-300, 5e-324)  # 1e-300 and the smallest subnormal
HUGE = (1e300, -1e300, sys.float_info.max)
HUGE_COUNTS = (10**6, 10**9, 2**63 - 1, 10**30)
LONG_LISTS = (5_000, 100_000)  # entries of a list made huge: over the default level limit of a case
BAD_BYTES = (b"\xff", b"\xfe\xff", b"\xc3\x28", b"\x80", b"\xe9", b"\xed\xa0\x80", b"\xf8\x88\x80\x80\x80")


@dataclass(frozen=True)
class Mutation:
    """One change: ``kind`` (``KINDS``), where (``path`` into the document; empty for raw bytes) and
    the new ``value`` (``DELETE`` for a deletion; for a raw-byte kind, its parameters: the position as a
    fraction of the file, and the bytes inserted)."""

    kind: str
    path: Where
    value: object

    def describe(self) -> str:
        where = ".".join(str(p) for p in self.path)
        if self.kind in RAW_KINDS:
            fraction, inserted = self.raw()
            return (
                f"truncate: the file cut at {fraction:.1%}"
                if self.kind == "truncate"
                else f"non_utf8: {inserted!r} at {fraction:.1%} of the file"
            )
        if self.value == DELETE:
            return f"{self.kind}: delete {where}"
        value = (
            self.value if not isinstance(self.value, list) or len(self.value) < 8 else f"[{len(self.value)} entries]"
        )
        text = repr(value)
        return f"{self.kind}: {where} = {text[:60] + '...' if len(text) > 60 else text}"

    def raw(self) -> tuple[float, bytes]:
        """A raw-byte kind's parameters: the position as a fraction of the file, the bytes inserted."""
        return cast(tuple[float, bytes], self.value)  # as ``random_mutation`` makes them


@dataclass(frozen=True)
class Mutant:
    """A source case file, the mutations applied to it in order (raw-byte ones act last, on the
    written file), and the verb it is run with (``solve`` or ``run``)."""

    source: Path
    mutations: tuple[Mutation, ...]
    verb: str = "solve"

    def describe(self) -> str:
        return "; ".join(m.describe() for m in self.mutations)

    def document(self) -> dict:
        """The source parsed, with the document mutations applied."""
        document = tomllib.loads(self.source.read_text(encoding="utf-8"))
        for mutation in self.mutations:
            if mutation.kind not in RAW_KINDS:
                apply(document, mutation)
        return document

    def bytes(self) -> bytes:
        """The mutated file: the source's own text when no mutation touches the document (so its
        comments stay), else the mutated document written by tomli_w; then the raw-byte mutations."""
        data = self.source.read_bytes()
        if any(m.kind not in RAW_KINDS for m in self.mutations):
            data = tomli_w.dumps(self.document()).encode("utf-8")
        for mutation in self.mutations:
            if mutation.kind in RAW_KINDS:
                data = apply_raw(data, mutation)
        return data


def source_files(long: bool) -> list[Path]:
    """The case files mutated: every shipped case (``long``), else the small fast set ``SOURCES``."""
    return find_case_files(None) if long else [CASES_DIR / name for name in SOURCES]


def apply(document: dict, mutation: Mutation) -> bool:
    """Set (or delete) the value at the mutation's path; False when the path no longer exists (an
    earlier mutation removed it) and nothing changed."""
    *parents, last = mutation.path
    node = document
    for key in parents:
        if (
            isinstance(node, dict)
            and key in node
            or isinstance(node, list)
            and isinstance(key, int)
            and key < len(node)
        ):
            node = node[key]
        else:
            return False
    if mutation.value == DELETE:
        if (
            isinstance(node, dict)
            and last in node
            or isinstance(node, list)
            and isinstance(last, int)
            and last < len(node)
        ):
            del node[last]
            return True
        return False
    if isinstance(node, dict) and isinstance(last, str):
        node[last] = copy.deepcopy(mutation.value)
        return True
    if isinstance(node, list) and isinstance(last, int) and last < len(node):
        node[last] = copy.deepcopy(mutation.value)
        return True
    return False


def apply_raw(data: bytes, mutation: Mutation) -> bytes:
    """A raw-byte mutation: ``truncate`` keeps the first fraction of the file; ``non_utf8`` inserts
    bytes that are not UTF-8 at a fraction of the file (or re-encodes the whole file as UTF-16)."""
    fraction, inserted = mutation.raw()
    at = int(fraction * len(data))
    if mutation.kind == "truncate":
        return data[:at]
    if inserted == b"utf-16":
        return data.decode("utf-8", errors="replace").encode("utf-16")
    return data[:at] + inserted + data[at:]


def nodes(document, path: Where = ()):
    """(path, value) of every node below the root, depth first."""
    items = (
        document.items() if isinstance(document, dict) else enumerate(document) if isinstance(document, list) else ()
    )
    for key, value in items:
        yield path + (key,), value
        yield from nodes(value, path + (key,))


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _name_key(path: Where) -> str:
    """The last key of a path that is not a list index (the field a list entry belongs to)."""
    return next((p for p in reversed(path) if isinstance(p, str)), "")


def _targets(kind: str, document: dict) -> list[tuple[Where, object]]:
    """The nodes a kind can act on."""
    every = list(nodes(document))
    if kind == "delete_field":
        return [(p, v) for p, v in every if not isinstance(v, (dict, list))]
    if kind == "delete_table":
        return [(p, v) for p, v in every if isinstance(v, (dict, list))]
    if kind in ("nan", "inf", "minus_inf", "zero", "negative", "tiny", "huge"):
        return [(p, v) for p, v in every if _is_number(v)]
    if kind == "huge_count":
        return [
            (p, v)
            for p, v in every
            if isinstance(v, int)
            and not isinstance(v, bool)
            or isinstance(v, list)
            and v
            and all(_is_number(x) for x in v)
        ]
    if kind in ("unknown_key", "unicode_key"):
        return [((), document)] + [(p, v) for p, v in every if isinstance(v, dict)]
    if kind == "unicode":
        return [(p, v) for p, v in every if isinstance(v, str)]
    if kind == "path_id":
        return [(p, v) for p, v in every if isinstance(v, str) and _name_key(p) in ID_KEYS]
    if kind == "dangling_name":
        return [(p, v) for p, v in every if isinstance(v, str) and _name_key(p) in NAME_KEYS]
    if kind == "zero_length":
        return _zero_length_targets(document)
    return every  # wrong_type


def _zero_length_targets(document: dict) -> list[tuple[Where, object]]:
    """A beam whose end is its start (a mechanism), or a segment's length (set to 0 below)."""
    found: list[tuple[Where, object]] = []
    mechanism = document.get("mechanism")
    if isinstance(mechanism, dict) and isinstance(mechanism.get("beams"), list):
        for i, beam in enumerate(mechanism["beams"]):
            if isinstance(beam, dict) and "start" in beam:
                found.append((("mechanism", "beams", i, "end"), beam["start"]))
    segment = document.get("segment")
    if isinstance(segment, dict) and "length" in segment:
        found.append((("segment", "length"), 0.0))
    return found


def _new_value(kind: str, current, rng: random.Random):
    """The value a kind puts at a node holding ``current``."""
    if kind in ("delete_field", "delete_table"):
        return DELETE
    if kind == "wrong_type":
        return rng.choice([v for v in WRONG_TYPES if type(v) is not type(current)])
    if kind in NON_FINITE:
        return NON_FINITE[kind]
    if kind == "zero":
        return 0 if isinstance(current, int) else 0.0
    if kind == "tiny":
        return rng.choice(TINY)
    if kind == "huge":
        return rng.choice(HUGE)
    if kind == "negative":
        return -abs(current) if current else -1
    if kind == "huge_count":
        if isinstance(current, list):
            return (current * (rng.choice(LONG_LISTS) // len(current) + 1))[: rng.choice(LONG_LISTS)]
        return rng.choice(HUGE_COUNTS)
    if kind == "unicode":
        return rng.choice((rng.choice(UNICODE), current + rng.choice(UNICODE)))
    if kind == "path_id":
        return rng.choice(PATH_IDS)
    if kind == "dangling_name":
        return rng.choice(
            ("nowhere", current.lower() if current != current.lower() else current.upper(), current + "2", current[:-1])
        )
    if kind == "zero_length":
        return current
    return rng.choice(WRONG_TYPES)


def random_mutation(document: dict, rng: random.Random, kind: str | None = None) -> Mutation | None:
    """One mutation of a kind (random if not given) at a random node it applies to; None when the
    document has no such node."""
    kind = kind or rng.choice(KINDS)
    if kind in RAW_KINDS:
        inserted = rng.choice(BAD_BYTES + (b"utf-16",)) if kind == "non_utf8" else b""
        return Mutation(kind, (), (round(rng.random(), 4), inserted))
    targets = _targets(kind, document)
    if not targets:
        return None
    path, current = rng.choice(targets)
    if kind in ("unknown_key", "unicode_key") and isinstance(current, dict):  # a table (``_targets``)
        return _key_mutation(kind, path, current, rng)
    return Mutation(kind, path, _new_value(kind, current, rng))


def _key_mutation(kind: str, path: Where, table: dict, rng: random.Random) -> Mutation:
    """An unknown key added to a table, or (``unicode_key``) a key of the table spelt with a unicode
    look-alike letter (Cyrillic 'е' for 'e', ...), its value kept."""
    if kind == "unknown_key" or not table:
        return Mutation(kind, path + (rng.choice(UNKNOWN_KEYS),), rng.choice(WRONG_TYPES))
    key = rng.choice(sorted(table))
    lookalike = key.translate(str.maketrans("aeopcx", "аеорсх")) if set(key) & set("aeopcx") else key + "\u0301"
    return Mutation(kind, path + (lookalike,), copy.deepcopy(table[key]))


def generate(sources: list[Path], count: int, seed: int) -> list[Mutant]:
    """``count`` mutants, each of a source picked at random, with one mutation (60 %), two (25 %)
    or three (15 %); the i-th mutant depends on (seed, i) alone."""
    documents = {path: tomllib.loads(path.read_text(encoding="utf-8")) for path in sources}
    mutants = []
    for index in range(count):
        rng = random.Random(f"{seed}:{index}")
        source = rng.choice(sources)
        document = copy.deepcopy(documents[source])
        mutations: list[Mutation] = []
        wanted = rng.choices((1, 2, 3), weights=(60, 25, 15))[0]
        for _ in range(20 * wanted):
            if len(mutations) == wanted:
                break
            mutation = random_mutation(document, rng)
            if mutation is None or mutation.kind in RAW_KINDS and any(m.kind in RAW_KINDS for m in mutations):
                continue
            if mutation.kind not in RAW_KINDS:
                apply(document, mutation)
            mutations.append(mutation)
        mutations.sort(key=lambda m: m.kind in RAW_KINDS)  # raw bytes last: they act on the written file
        mutants.append(Mutant(source, tuple(mutations)))
    return mutants
