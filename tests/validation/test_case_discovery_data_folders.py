"""Case names never resolve into the data folders (cases/specs, cases/sweeps).

cases/specs/bapat2015_ch7_ex5.toml is a design specification sharing its file name with the id of
the chapter-7 case; a name lookup must give the case file only, while a path written out in full
still reaches the file it names.
"""

from pathlib import Path

from validation.case.loader import CASES_DIR, find_case_files


def test_a_case_id_that_is_also_a_spec_file_name_finds_the_case_only():
    found = find_case_files(["bapat2015_ch7_ex5"])
    assert found == [(CASES_DIR / "chapter7" / "example5.toml").resolve()]


def test_a_glob_of_names_skips_the_data_folders():
    found = find_case_files(["bapat2015_ch7_ex*"])
    assert len(found) == 12 and all(p.parent.name == "chapter7" for p in found)


def test_a_path_written_out_still_reaches_a_file_in_a_data_folder():
    spec = CASES_DIR / "specs" / "bapat2015_ch7_ex5.toml"
    assert find_case_files([str(spec)]) == [spec.resolve()]
    assert Path(spec).is_file()
