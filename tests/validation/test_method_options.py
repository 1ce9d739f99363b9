"""Strict method options (validation/case/method_options.py) and a cache key that cannot go stale."""

import re
import shutil
from pathlib import Path

import pytest

from validation.run import cache
from validation.cli.main import main
from validation.case.loader import CaseError, load_case
from validation.case.method_options import OPTIONS

ROOT = Path(__file__).resolve().parents[2]
CASE = """\
[case]
id = "options_toy"
title = "toy cantilever"
group = "tests"
units = "dimensionless"

[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0, A = 1.0e6 }

[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [1.0]

[[outputs]]
quantity = "y"

[methods.fem]
elements = 4
[methods.prbm]
family = "howell"
"""


@pytest.mark.parametrize(
    "replace, field, words",
    [
        ("elements = 4", "methods.fem.elemnts", "unknown option"),
        ('family = "howell"', "methods.prbm.familly", "unknown option"),
        ("elements = 4", "methods.fem.elements", "valid integer"),
        ('family = "howell"', "methods.prbm.family", "'pauly-midha', 'howell' or 'constant'"),
    ],
)
def test_a_bad_option_is_one_error_naming_file_and_field(tmp_path, replace, field, words):
    option = field.rsplit(".", 1)[1]
    value = {
        "elemnts": "elemnts = 8",
        "familly": 'familly = "howell"',
        "elements": 'elements = "eight"',
        "family": 'family = "hwell"',
    }[option]
    path = tmp_path / "bad.toml"
    path.write_text(CASE.replace(replace, value))
    with pytest.raises(CaseError) as info:
        load_case(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {field}: ") and words in message and "\n" not in message


def test_a_bad_option_exits_2_and_the_good_case_loads(tmp_path, capsys):
    good = tmp_path / "good.toml"
    good.write_text(CASE)
    assert load_case(good).case.methods["fem"] == {"elements": 4}  # the file's dict (the cache key)
    bad = tmp_path / "bad.toml"
    bad.write_text(CASE.replace("elements = 4", "elemnts = 8"))
    assert main(["run", str(bad), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    assert "methods.fem.elemnts: unknown option" in capsys.readouterr().err


def test_every_option_an_adapter_reads_is_declared():
    pattern = re.compile(r"""\boptions\.(?!model_)(\w+)\b(?!\()""")  # the fields read off the method's options model
    for method, model in OPTIONS.items():
        folder = ROOT / "validation" / "methods"  # the adapter and its parts (prbm_fourbar.py, ...)
        source = "\n".join(p.read_text() for p in [folder / f"{method}.py", *sorted(folder.glob(f"{method}_*.py"))])
        read = set(pattern.findall(source))
        assert read, method
        assert read <= set(model.model_fields), f"{method}: undeclared {sorted(read - set(model.model_fields))}"


def test_the_cache_key_covers_schema_contract_options_adapter_and_library():
    names = {p.relative_to(cache.ROOT).as_posix() for p in cache.source_files("prbm")}
    assert {
        "validation/case/schema.py",
        "validation/case/quantities.py",
        "validation/case/method_options.py",
        "validation/methods/prbm.py",
        "validation/methods/base.py",
        "prbm/segments.py",
    } <= names
    assert "fem/solver.py" not in names  # another method's library does not invalidate this one


@pytest.mark.parametrize(
    "edited",
    ["validation/case/schema.py", "validation/case/quantities.py", "fem/newton.py", "validation/methods/fem.py"],
)
def test_an_edit_invalidates_the_cache(tmp_path, monkeypatch, edited):
    copy = tmp_path / "repo"
    for package in cache.PACKAGES:
        if (ROOT / package).is_dir():
            shutil.copytree(ROOT / package, copy / package, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(cache, "ROOT", copy)
    cache.code_hash.cache_clear()
    before = cache.run_key(CASE, "fem", {"elements": 4})
    with (copy / edited).open("a") as handle:
        handle.write("\n# an edit\n")
    cache.code_hash.cache_clear()
    after = cache.run_key(CASE, "fem", {"elements": 4})
    cache.code_hash.cache_clear()
    assert before != after
