"""What a run builds only for the report (shapes, the FEM's ParaView field series) is built when first
read, and a cached or pickled run holds the plain objects."""

import pickle

import numpy as np

from validation.case.loader import case_by_id
from validation.methods.base import DeferredList
from validation.run.runner import run_method


def test_deferred_list_builds_once_when_first_read_and_pickles_as_the_list():
    calls = []

    def build():
        calls.append(1)
        return [np.arange(3.0), np.ones(2)]

    shapes = DeferredList(build)
    assert calls == []  # nothing built by creating it
    assert len(shapes) == 2 and bool(shapes) and calls == [1]
    np.testing.assert_array_equal(shapes[0], np.arange(3.0))
    assert [len(s) for s in shapes] == [3, 2] and calls == [1]  # built once
    back = pickle.loads(pickle.dumps(shapes))
    assert type(back) is list and len(back) == 2
    assert not DeferredList(list)  # an empty build is falsy, as no shapes at all


def test_fem_run_shapes_and_fields_read_and_pickled_equal_the_results_own():
    run = run_method(case_by_id("cantilever_tip_load").case, "fem")
    shapes, fields = run.extras["shapes"], run.extras["fields"]
    back = pickle.loads(pickle.dumps(run))
    assert type(back.extras["shapes"]) is list and type(back.extras["fields"]).__name__ == "FieldSeries"
    assert (
        len(shapes)
        == len(back.extras["shapes"])
        == len(fields.nodal)
        == run_method(case_by_id("cantilever_tip_load").case, "fem").extras["fields"].positions.shape[0]
    )
    for level, polylines in enumerate(shapes):
        for a, b in zip(polylines, back.extras["shapes"][level]):
            np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(fields.nodal[level].displacement, back.extras["fields"].nodal[level].displacement)
    # the tip of the last level's shape is the tip position the run reports
    tip = shapes[-1][-1][-1]
    x = [v for r, v in run.values.items() if r.quantity == "x" and r.level == len(shapes) - 1]
    assert x and tip[0] == x[0]
