"""The chapter 5-8 case files (Bapat 2015): every file loads, ids are unique, every reference names
its source (a table or a section of the seed), and every level index is in range."""

from __future__ import annotations

from pathlib import Path

import pytest

from validation.case.loader import load_case

CASES = Path(__file__).resolve().parents[2] / "cases"
FOLDERS = ["chapter5", "chapter6", "chapter7", "chapter8"]
FILES = sorted(p for folder in FOLDERS for p in (CASES / folder).glob("*.toml"))
SEED = "000_0cc428dae4265b0a.txt"


def test_files_exist():
    assert len(FILES) >= 12, [p.name for p in FILES]


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_loads(path):
    loaded = load_case(path)
    assert loaded.case.case.group == f"chapter {path.parent.name.removeprefix('chapter')}"


def test_ids_unique():
    ids = [load_case(p).id for p in FILES]
    assert len(ids) == len(set(ids)), sorted(i for i in ids if ids.count(i) > 1)


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_references_have_source(path):
    case = load_case(path).case
    assert case.case.source is not None and case.case.source.file == SEED
    for ref in case.references:
        # the seed's columns, or an exact solution of the same geometry from the notes' extractions
        assert ref.source.file == SEED or (ref.label == "exact" and ref.source.file.startswith("notes/")), ref
        assert ref.source.table or ref.source.section, ref


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_levels_in_range(path):
    case = load_case(path).case
    n = case.n_levels()
    for ref in case.references:
        assert 0 <= ref.level < n
    for out in case.outputs:
        if out.levels != "all":
            assert all(0 <= lv < n for lv in out.levels)
    for load in case.loads:
        assert len(load.levels()) == n
    if case.level_labels is not None:
        assert len(case.level_labels) == n


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_absolute_paths(path):
    text = path.read_text(encoding="utf-8")
    assert "/work/" not in text and "/home/" not in text and "/tmp/" not in text
