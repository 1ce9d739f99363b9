"""The adapters receive their method's validated options model and read its fields: no adapter reads the
options as a dict, each default is written once (in ``validation/case/method_options.py``), and a value the
case gives reaches the solver."""

import re
import tomllib
from pathlib import Path

import pytest

from validation.case.method_options import OPTIONS, FemOptions, PrbmOptions, options_of
from validation.case.schema import Case
from validation.methods import fem as fem_adapter
from validation.methods import prbm as prbm_adapter
from validation.methods.base import Request
from validation.run.compare import axial_strain_bound
from validation.run.runner import requests_for, run_method

ROOT = Path(__file__).resolve().parents[2]
ADAPTERS = sorted((ROOT / "validation" / "methods").glob("*.py")) + [ROOT / "validation" / "run" / "compare.py"]
OPTIONS_FILE = ROOT / "validation" / "case" / "method_options.py"
# the options read as a dict: options.get("x"...), options["x"], "x" in options, (options...).get("x", default)
DICT_READS = re.compile(r"""\boptions\.get\(|\boptions\[|\bin\s+options\b(?!\.)|\(options[^)]*\)\s*\.get\(""")
# a default restated: .get("<option>", <default>) for an option whose model gives a default
DEFAULTED = sorted(
    {
        name
        for model in OPTIONS.values()
        for name, field in model.model_fields.items()
        if field.default is not None and not field.is_required()
    }
)
RESTATED = re.compile(r"""\.get\(\s*["'](%s)["']\s*,""" % "|".join(DEFAULTED))

CASE = """\
[case]
id = "typed_options_toy"
title = "toy cantilever"
group = "tests"
units = "dimensionless"

[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0 }

[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [2.0]

[[outputs]]
quantity = "dx"
point = "tip"

[methods.fem]
elements = 5
error_estimate = false
[methods.prbm]
family = "howell"
"""


def _case(text: str = CASE) -> Case:
    return Case.model_validate(tomllib.loads(text))


@pytest.mark.parametrize("path", ADAPTERS, ids=lambda p: p.name)
def test_no_adapter_reads_its_options_as_a_dict(path):
    source = path.read_text()
    reads = [m.group(0) for m in DICT_READS.finditer(source)] + [m.group(0) for m in RESTATED.finditer(source)]
    assert not reads, f"{path.name} reads options as a dict: {reads}"


def test_each_default_is_written_once_in_the_options_models():
    assert FemOptions().inextensible_ratio == 1e6 and PrbmOptions().family == "pauly-midha"
    assert re.search(r"inextensible_ratio: Ratio = Field\(default=1e6", OPTIONS_FILE.read_text())
    for path in [*ADAPTERS, *(ROOT / "validation" / "case").glob("*.py")]:
        if path == OPTIONS_FILE:
            continue
        code = "\n".join(line.split("#")[0] for line in path.read_text().splitlines())
        assert not re.search(r"(inextensible_ratio|rigid_ratio)\W[^\n]{0,40}\b1e6\b", code), path.name
        assert not re.search(r"""(family\W[^\n]{0,20}|[,=]\s*)["']pauly-midha["']\s*\)""", code), path.name
        assert not re.search(r"""\b(family|default)\s*=\s*["']pauly-midha["']""", code), path.name


def test_the_runner_hands_the_adapter_the_model_with_the_case_values():
    run = run_method(_case(), "fem")
    assert run.ok, run.message
    assert run.extras["elements"] == 5 and not run.error_estimate  # elements = 5, error_estimate = false


def test_a_non_default_fem_value_reaches_the_solver():
    case = _case()
    requests = requests_for(case, "fem")
    coarse = fem_adapter.run(case, requests, FemOptions(elements=5, error_estimate=False))
    default = fem_adapter.run(case, requests, FemOptions(error_estimate=False))
    assert coarse.extras["elements"] == 5 and default.extras["elements"] == FemOptions().elements
    # a section without an area: EA = inextensible_ratio EI / L^2, so a ratio of 10 lets the beam stretch
    stiff = fem_adapter.run(case, requests, FemOptions(elements=5, error_estimate=False))
    soft = fem_adapter.run(case, requests, FemOptions(elements=5, error_estimate=False, inextensible_ratio=10.0))
    req = Request("dx", "tip", 0)
    assert abs(soft.values[req] - stiff.values[req]) > 1e-2


def test_compare_reads_the_fem_ratio_from_the_model():
    case = _case()
    assert axial_strain_bound(case, 0) == pytest.approx(2.0 / 1e6)  # the model's default ratio
    ratio = _case(CASE.replace("elements = 5", "elements = 5\ninextensible_ratio = 100.0"))
    assert axial_strain_bound(ratio, 0) == pytest.approx(2.0 / 100.0)


def test_a_non_default_prbm_family_reaches_the_model():
    case = _case()
    requests = [Request("dx", "tip", 0)]
    howell = prbm_adapter.run(case, requests, options_of("prbm", case.methods["prbm"]))
    pauly = prbm_adapter.run(case, requests, PrbmOptions())
    assert howell.values[requests[0]] != pytest.approx(pauly.values[requests[0]], rel=1e-6)
