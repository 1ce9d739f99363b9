"""Which reading of an experiment's loading puts the FEM nearest the measured points, and whether the
ranking the experiment records still holds.

An experiment whose loading the source leaves open is run as one case per reading
(`validation.case.readings`). Reading k is ranked by its FEM's rms distance to the measured points,

    D_k = sqrt( mean_l |r_k,l - m_l|^2 ),

over the measured load levels l that ``readings_groups`` keeps (flagged rows and the unloaded state left
out), in the case's length unit and as 100 D_k / L in % of the characteristic length L. The FEM's
Richardson estimate bounds how far the computed D_k lies from the exact one by E_k = sqrt(mean_l e_l^2)
(``readings_groups``' ``rms_estimate``). The nearest reading is *separated* from the second when

    D_2 - D_1 > E_1 + E_2,

so that no discretisation error the FEM admits can swap them; without an estimate (none, or marked
unreliable) the order is not separated.

The ranking an experiment records is a case finding of its base case that starts ``Readings ranking
(FEM): nearest <case id>, then <case id>`` followed by its physical reason; `check` holds it against the
computed ranking: it holds when the recorded nearest and second are the computed first two, in that
order, and separated. The measured points are the references labelled ``measured`` of [bapat2015,
Tables 9.1-9.4].
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from enum import Enum

import pandas as pd

from validation.case.readings import readings_groups

METHOD = "fem"
RECORD = re.compile(r"Readings ranking \(FEM\): nearest ([A-Za-z0-9_-]+), then ([A-Za-z0-9_-]+)")
EXPERIMENT = re.compile(r"^(.*?) load reading:")


@dataclass(frozen=True)
class Reading:
    """One reading's FEM against the measured points."""

    case: str
    name: str  # the case id after the experiment's ('base' for the experiment's own case)
    levels: int
    rms: float  # D_k, in ``unit``
    rms_pct_L: float  # 100 D_k / L
    estimate: float  # E_k, the bound on |D_k - exact D_k| (NaN: none)
    unit: str


@dataclass(frozen=True)
class Recorded:
    """The ranking the base case records: the nearest and the second reading's case ids."""

    nearest: str
    second: str


class Status(Enum):
    HOLDS = "holds"  # recorded first two = computed, in order, separated
    DIFFERS = "differs"  # another reading is nearer, or the second changed
    NOT_SEPARATED = "not separated"  # the order is the recorded one, but within the FEM's error bound
    UNRECORDED = "unrecorded"  # the base case records no ranking


@dataclass(frozen=True)
class Ranking:
    """One experiment's readings, nearest first, and its recorded ranking."""

    experiment: str  # the base case id
    label: str  # e.g. 'Test 1(a)', from the readings' titles
    readings: tuple[Reading, ...]
    recorded: Recorded | None

    @property
    def nearest(self) -> Reading:
        return self.readings[0]

    @property
    def margin(self) -> float:
        """D_2 - D_1 (NaN with one reading)."""
        return self.readings[1].rms - self.readings[0].rms if len(self.readings) > 1 else math.nan

    @property
    def bound(self) -> float:
        """E_1 + E_2: the margin the FEM's own error could take away (NaN: no estimate)."""
        return self.readings[0].estimate + self.readings[1].estimate if len(self.readings) > 1 else math.nan

    @property
    def separated(self) -> bool:
        """The first two stay in this order under any error within the FEM's estimate."""
        return bool(self.margin > self.bound)  # False when either is NaN

    @property
    def status(self) -> Status:
        if self.recorded is None:
            return Status.UNRECORDED
        order = tuple(r.case for r in self.readings[:2])
        if order != (self.recorded.nearest, self.recorded.second):
            return Status.DIFFERS
        return Status.HOLDS if self.separated else Status.NOT_SEPARATED

    def line(self) -> str:
        """'Test 1(a): nearest reading: self weight (RMS 0.125 in, 1.25 % of L); then base (...), ...'."""

        def one(r: Reading) -> str:
            return f"{r.name} (RMS {r.rms:.3g} {r.unit}, {r.rms_pct_L:.3g} % of L)"

        first, *rest = self.readings
        text = f"{self.label}: nearest reading: {one(first)}"
        if rest:
            text += "; then " + ", ".join(one(r) for r in rest)
            text += (
                f". Margin to the second {self.margin:.3g} {first.unit} against the FEM's error bound "
                f"{self.bound:.2g} {first.unit}"
            )
        recorded = {
            Status.UNRECORDED: "no ranking recorded",
            Status.HOLDS: "the recorded ranking holds",
            Status.NOT_SEPARATED: "the recorded ranking holds but within the FEM's error bound",
            Status.DIFFERS: (
                f"the recorded ranking (nearest {self.recorded.nearest}, then {self.recorded.second}) no longer holds"
                if self.recorded
                else ""
            ),
        }
        return f"{text}; {recorded[self.status]}."


def recorded_ranking(findings: list[str]) -> Recorded | None:
    """The ranking a base case's findings record (the first finding of the form), or None."""
    for text in findings:
        match = RECORD.search(text)
        if match:
            return Recorded(*match.groups())
    return None


def _label(experiment: str, titles: list[str]) -> str:
    for title in titles:
        match = EXPERIMENT.match(title)
        if match:
            return match.group(1)
    return experiment


def _name(case: str, experiment: str) -> str:
    return "base" if case == experiment else case.removeprefix(experiment + "_").replace("_", " ")


def rank_readings(results, table: pd.DataFrame) -> list[Ranking]:
    """Per experiment (base case with readings), its readings ranked by the FEM's rms distance to the
    measured points. ``results``: the runner's case results (``loaded.case``); ``table``: its rows."""
    cases = {r.loaded.id: r.loaded.case for r in results}
    rankings = []
    for group in readings_groups(results, table):
        fem = group.table[group.table["method"] == METHOD].sort_values("rms", kind="stable")
        if fem.empty:
            continue
        readings = tuple(
            Reading(
                case=str(r["case"]),
                name=_name(str(r["case"]), group.experiment),
                levels=int(r["levels"]),
                rms=float(r["rms"]),
                rms_pct_L=float(r["rms_pct_L"]),
                estimate=float(r["rms_estimate"]),
                unit=str(r["unit"]),
            )
            for _, r in fem.iterrows()
        )
        base = cases[group.experiment].case
        rankings.append(
            Ranking(
                group.experiment,
                _label(group.experiment, list(group.table["title"])),
                readings,
                recorded_ranking(base.findings),
            )
        )
    return rankings
