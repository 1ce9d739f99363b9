"""Finding a case file by its [case].id (``find_case_files``, ``case_by_id``): only the files with a
line ``id = "<the id>"`` are parsed, so the lookup must still be exact where that shortcut could
mislead: an id that another file only mentions, one that another file gives to a key ``id`` of
another table, and an id written with a TOML escape."""

from __future__ import annotations

from pathlib import Path

import pytest

from validation.case import loader
from validation.case.loader import CaseError, case_by_id, find_case_files

CANTILEVER = (Path(__file__).resolve().parents[2] / "cases" / "benchmarks" / "cantilever_tip_load.toml").read_text()


def _case(folder: Path, name: str, case_id: str, extra: str = "") -> Path:
    text = CANTILEVER.replace('id = "cantilever_tip_load"', f'id = "{case_id}"', 1)
    assert text != CANTILEVER
    path = folder / name
    path.write_text(text.replace("[case]\n", "[case]\n" + extra, 1))
    return path


def test_the_file_with_the_id_is_found_not_one_that_mentions_it(tmp_path):
    mentions = _case(tmp_path, "a.toml", "other", extra='notes = "compare with mine_1"\n')
    mine = _case(tmp_path, "b.toml", "mine_1")
    assert find_case_files(["mine_1"], root=tmp_path) == [mine.resolve()]
    assert case_by_id("mine_1", root=tmp_path).case.case.id == "mine_1"
    assert mentions.is_file()


def test_a_file_that_only_mentions_the_id_is_not_parsed(tmp_path, monkeypatch):
    _case(tmp_path, "a.toml", "other", extra='readings_of = "mine_5"\n')
    mine = _case(tmp_path, "b.toml", "mine_5")
    mine.write_text(mine.read_text().replace('id = "mine_5"', "id   =\t'mine_5'  # literal string"))
    parsed = []
    real_loads = loader.tomllib.loads
    monkeypatch.setattr(loader.tomllib, "loads", lambda text: parsed.append(text) or real_loads(text))
    assert find_case_files(["mine_5"], root=tmp_path) == [mine.resolve()]
    assert parsed == [mine.read_text()]


def test_an_id_key_of_another_table_does_not_stand_for_the_case_id(tmp_path):
    other = _case(tmp_path, "a.toml", "other", extra="")
    other.write_text(other.read_text() + '\n[meta]\nid = "mine_6"\n')
    mine = _case(tmp_path, "b.toml", "mine_6")
    assert find_case_files(["mine_6"], root=tmp_path) == [mine.resolve()]


def test_an_id_written_with_an_escape_is_still_found(tmp_path):
    escaped = _case(tmp_path, "c.toml", "mine\\u005f2")  # TOML reads "mine_2"
    assert "mine_2" not in escaped.read_text()
    assert find_case_files(["mine_2"], root=tmp_path) == [escaped.resolve()]
    assert case_by_id("mine_2", root=tmp_path).case.case.id == "mine_2"


def test_an_unknown_id_names_the_nearest_ids(tmp_path):
    _case(tmp_path, "d.toml", "mine_3")
    with pytest.raises(CaseError, match="nearest: mine_3"):
        case_by_id("mine_4", root=tmp_path)
