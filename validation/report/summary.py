"""The summary an engineer reads first: per chapter, one row per case with headers in words, numbers
to at most four significant digits, a colour scale on the PRBM error, a verdict, a one-sentence
result, and beneath the tables the findings with their evidence. A case's status and each method's are
verdicts (``validation.run.verdict``: the worst of their rows); the PRBM-vs-FEM cell is coloured by its
size and labelled by its own verdict (``no limit claimed`` unless an agreement claims one).

The numbers come from ``validation.run.outcome`` (``PrbmFemNumbers``: ``prbm_fem_errors``,
``fem_error_relative``) so the summary page and ``summary.csv`` say the same thing.
"""

from __future__ import annotations

import html
import math
import re
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from references import REFERENCES, citation
from validation.case.capabilities import QUANTITIES
from validation.case.loads import driving_load, load_name, load_unit
from validation.report.format import (
    SEED_KEYS,
    VERDICT_COLOURS,
    cite_keys,
    document_title,
    error_colour,
    percent,
    seconds,
    sig,
    verdict_html,
)
from validation.run.compare import verdict_by_method
from validation.run.runner import CaseResult
from validation.run.outcome import FEM_VALIDATION, PrbmFemNumbers, no_prbm_fem_reason
from validation.run.verdict import (
    MethodVerdict,
    Verdict,
    case_verdict_of,
    counts_sentence,
    method_verdicts,
    run_verdict,
)

METHOD_NAMES = {"fem": "FEM", "prbm": "PRBM", "elastica": "exact elastica", "bcm": "BCM", "opensees": "OpenSees"}


@dataclass(frozen=True)
class MethodState:
    """One method's verdict in one case, with its reason."""

    method: str
    verdict: Verdict
    reason: str


@dataclass
class CaseSummary:
    """One summary row."""

    group: str
    case: str
    title: str
    verdict: Verdict
    reason: str
    methods: list[MethodState]
    sentence: str
    prbm_fem_length: float  # fraction of the characteristic length
    prbm_fem_relative: float
    fem_estimate: float  # the largest reliable estimate, relative (``fem_error_relative``)
    checks: int
    checks_passed: int
    findings: int
    times: dict[str, float] = field(default_factory=dict)
    no_prbm_fem: str = ""
    readings_of: str = ""  # the base case of an experiment this case is one loading reading of
    fem_validation: bool = False  # case.purpose = 'fem-validation': a benchmark of the FEM itself
    fem_unreliable: int = 0  # FEM values whose error estimate is marked unreliable (left out of fem_estimate)
    prbm_fem_verdict: Verdict = Verdict.NO_LIMIT  # the verdict of the PRBM-vs-FEM number (``prbm_fem_verdict``)


def level_phrase(result: CaseResult, level: int) -> str:
    """'force at tip = 10 lbf' for a level, or 'level <label>' when the case has no load."""
    case = result.loaded.case
    index = driving_load(case)  # None: the case has no load
    if index is not None:
        load = case.loads[index]
        unit = load_unit(load, case)
        return f"{load_name(load, index, case)} = {sig(load.levels()[level])}{' ' + unit if unit else ''}"
    labels = case.level_labels or [str(i) for i in range(case.n_levels())]
    return f"level {labels[level]}"


LEVEL_COLUMNS = ["method", "quantity", "point", "level", "value", "scale"]


def prbm_fem_by_level(part: pd.DataFrame) -> pd.Series:
    """Largest |PRBM - FEM| of the length outputs at each level, over the characteristic length (the
    first value of each method, output and level; the first characteristic length given), indexed by the
    sorted levels with a difference."""
    worst = worst_by_level(part)
    if not worst:
        return pd.Series(dtype=float)
    return pd.Series(list(worst.values()), index=pd.Index(list(worst), name="level"), dtype=float)


def worst_by_level(part: pd.DataFrame) -> dict[int, float]:
    """``prbm_fem_by_level`` as a dict, level -> largest difference, in the order of the levels; read in
    one pass over the rows (cheaper than a pandas pivot on tables this small)."""
    values: dict[str, dict[tuple, float]] = {"prbm": {}, "fem": {}}
    scale = math.nan
    any_length = False
    for method, quantity, point, level, value, row_scale in zip(*(part[c].tolist() for c in LEVEL_COLUMNS)):
        if not (isinstance(quantity, str) and QUANTITIES[quantity].dimension == "length"):
            continue
        any_length = True
        if math.isnan(scale) and not pd.isna(row_scale):
            scale = float(row_scale)
        if method in values:
            values[method].setdefault((quantity, point, level), value)
    prbm, fem = values["prbm"], values["fem"]
    if not any_length or not _has_number(prbm) or not _has_number(fem):
        return {}
    worst: dict[int, float] = {}
    for key in prbm.keys() & fem.keys():
        diff = abs(prbm[key] - fem[key]) / scale
        if not math.isnan(diff):
            worst[key[2]] = max(worst.get(key[2], -math.inf), diff)
    return {level: worst[level] for level in sorted(worst)}


def _has_number(values: dict) -> bool:
    return any(not pd.isna(v) for v in values.values())


def case_sentence(result: CaseResult, part: pd.DataFrame) -> str:
    """The case's answer in one sentence."""
    by_level = worst_by_level(part)  # no NaN
    clauses = []
    if by_level:
        last, worst = int(max(by_level)), int(max(by_level, key=by_level.__getitem__))  # the first largest
        clauses.append(
            f"PRBM within {percent(max(by_level.values()))} of L of the FEM up to {level_phrase(result, last)}"
            + (f" (largest at {level_phrase(result, worst)})" if worst != last else "")
        )
        without_value = (part["method"] == "prbm") & part["level"].notna() & part["value"].isna()
        if without_value.any():
            missing = part[without_value]
            first = int(missing["level"].min())
            why = str(missing.sort_values("level")["message"].iloc[0] or "")
            clauses.append(f"no PRBM answer from {level_phrase(result, first)}" + (f" ({_short(why)})" if why else ""))
    else:
        claimed, good = claimed_limits(part)
        if claimed:
            clauses.append(
                f"{good} of {claimed} claimed limits met (printed numbers, findings, "
                f"limits between methods, FEM against the exact elastica)"
            )
        reason = getattr(result.loaded.case.case, "no_prbm_fem", None)
        if reason:
            clauses.append(f"no PRBM-vs-FEM comparison: {reason}")
    expected = result.loaded.case.case.expected_failure
    for method, run in result.runs.items():
        verdict, why = run_verdict(run, expected.get(method))
        if verdict is not None:
            clauses.append(f"{METHOD_NAMES.get(method, method)} {verdict.value}: {_short(why)}")
    findings = part["finding"].dropna().unique()
    if len(findings) or result.loaded.case.case.findings:
        clauses.append(f"{len(findings) + len(result.loaded.case.case.findings)} finding(s) below")
    if not clauses:
        return "Every method ran; no printed number to compare with."
    sentence = round_numbers("; ".join(clauses))
    return sentence[0].upper() + sentence[1:] + "."


def claimed_limits(part: pd.DataFrame) -> tuple[int, int]:
    """How many rows claim a limit (``within_tolerance`` set), and how many of them meet it."""
    within = part["within_tolerance"]
    return int(within.notna().sum()), int((within == True).sum())  # noqa: E712


DECIMAL = re.compile(r"(?<![\w.])-?\d+\.\d+(?:[eE][+-]?\d+)?(?![\w.])")


def round_numbers(text: str, digits: int = 4) -> str:
    """Every decimal number in a message to at most ``digits`` significant digits."""
    return DECIMAL.sub(lambda m: f"{float(m.group()):.{digits}g}", text)


def _short(text: str, limit: int = 140) -> str:
    """A message for a table cell: one line, numbers to four significant digits, at most ``limit`` long."""
    text = round_numbers(re.sub(r"\s+", " ", text).strip())
    return text if len(text) <= limit else text[: limit - 1].rstrip() + "…"


def summarise(
    result: CaseResult,
    part: pd.DataFrame,
    sentence: str | None = None,
    verdicts: dict[str, MethodVerdict] | None = None,
    numbers: PrbmFemNumbers | None = None,
) -> CaseSummary:
    """The case's row of the index; ``sentence``: its `case_sentence` of ``part``, ``verdicts``: its
    `method_verdicts` of ``part``, and ``numbers``: its ``PrbmFemNumbers``, when the caller has them (the
    case page works the first two out, the page writer the numbers for ``summary.csv`` too)."""
    case = result.loaded.case
    claimed, passed = claimed_limits(part)
    findings = part["finding"].dropna().unique()
    n_findings = len(findings) + len(case.case.findings)
    if verdicts is None:
        problems = verdict_by_method(case, result.runs, part) if len(part) else {}
        verdicts = method_verdicts(case, result.runs, part, problems)
    methods = [MethodState(m, v.verdict, v.reason) for m, v in verdicts.items()]
    verdict = case_verdict_of(verdicts.values())
    reason = "; ".join(f"{s.method}: {_short(s.reason)}" for s in methods if s.verdict is verdict and s.reason)
    numbers = numbers or PrbmFemNumbers.of(part)
    return CaseSummary(
        group=case.case.group,
        case=case.case.id,
        title=case.case.title,
        verdict=verdict,
        reason=reason,
        methods=methods,
        sentence=case_sentence(result, part) if sentence is None else sentence,
        prbm_fem_length=numbers.length,
        prbm_fem_relative=numbers.relative,
        fem_estimate=numbers.fem_estimate,
        checks=claimed,
        checks_passed=passed,
        findings=n_findings,
        times={m: r.wall_time for m, r in result.runs.items()},
        no_prbm_fem=no_prbm_fem_reason(result)
        if case.case.purpose == "fem-validation"
        else case.case.no_prbm_fem or "",
        readings_of=case.case.readings_of or "",
        fem_validation=case.case.purpose == "fem-validation",
        fem_unreliable=numbers.fem_unreliable,
        prbm_fem_verdict=numbers.verdict,
    )


def group_order(group: str) -> tuple:
    """Chapters in number order, then the other source documents' groups, then the classic
    benchmarks."""
    match = re.match(r"chapter\s+(\d+)", group)
    if match:
        return (0, int(match.group(1)), group)
    return (1 if group.startswith("seed") else 2, 0, group)


# The index's columns: one line a case, the result sentence clipped to its column (whole on hover, and
# on a click); the relative error and the PRBM and exact times are in the hover text of their neighbours
# (all of them are in summary.csv and on the case page).
HEADERS = [
    "Case",
    "Verdict",
    "Methods",
    "Result",
    "PRBM vs FEM, max % of L",
    "FEM error estimate",
    "Printed\u00a0numbers reproduced",
    "Findings",
    "FEM time",
]
SHORT_METHOD_NAMES = {**METHOD_NAMES, "elastica": "elastica"}


def readable(text: str) -> str:
    """A case file's or a run's text as the index shows it: sources by their key (`cite_keys`), field
    names of the case file in words."""
    return cite_keys(text).replace("case.findings", "the case's findings")


def _error_cell(row: CaseSummary) -> str:
    """The PRBM-vs-FEM cell: % of L on the colour scale, its verdict above it where a limit is claimed;
    else the relative error of the other outputs; else the reason there is none."""
    length_pct = 100 * row.prbm_fem_length
    relative = percent(row.prbm_fem_relative)
    if math.isnan(length_pct) and not math.isnan(row.prbm_fem_relative):
        return (
            "<td class='relative' data-value='-1' title='the PRBM and the FEM share no position output: the "
            f"largest relative error of their other outputs ({html.escape(row.prbm_fem_verdict.value)})'>"
            f"relative {relative}</td>"
        )
    if math.isnan(length_pct):
        why = readable(row.no_prbm_fem or _why_not_compared(row))
        return f"<td class='absent' title='{html.escape(why, quote=True)}'>{html.escape(_short(why, 60))}</td>"
    label = (
        ""
        if row.prbm_fem_verdict is Verdict.NO_LIMIT
        else f"<span class='cellverdict'>{html.escape(row.prbm_fem_verdict.value)}</span> "
    )
    title = f"{row.prbm_fem_verdict.value}: {row.prbm_fem_verdict.meaning}; largest relative error {relative}"
    return (
        f"<td data-value='{length_pct:.6g}' style='background:{error_colour(length_pct)}' "
        f"title='{html.escape(title, quote=True)}'>{label}{sig(length_pct, 3)} %</td>"
    )


def _row_html(row: CaseSummary, link: str) -> str:
    methods = " ".join(
        f"<span class='method' style='border-color:{VERDICT_COLOURS[s.verdict]}' title='"
        f"{html.escape(readable(s.verdict.value + (': ' + s.reason if s.reason else '')), quote=True)}'>"
        f"{html.escape(SHORT_METHOD_NAMES.get(s.method, s.method))}</span>"
        for s in sorted(row.methods, key=_method_order)
    )
    sentence = html.escape(readable(row.sentence), quote=True)
    others = "; ".join(
        f"{METHOD_NAMES[m]} {seconds(row.times[m])}"
        for m in ("prbm", "elastica", "bcm", "opensees")
        if not math.isnan(row.times.get(m, math.nan))
    )
    cells = [
        f"<td class='case'><a href='{html.escape(link, quote=True)}' title='{html.escape(row.title, quote=True)}'>"
        f"{html.escape(row.case)}</a></td>",
        f"<td data-value='{row.verdict.rank}'>{verdict_html(row.verdict, readable(row.reason))}</td>",
        f"<td class='methods'>{methods}</td>",
        f"<td class='sentence' title='{sentence} (click to unfold)'>{sentence}</td>",
        _error_cell(row),
        _estimate_cell(row),
        f"<td data-value='{row.checks_passed}'>{row.checks_passed} of {row.checks}</td>"
        if row.checks
        else "<td data-value='-1'></td>",
        f"<td>{row.findings or ''}</td>",
        f"<td data-value='{_raw(row.times.get('fem', math.nan))}' title='{html.escape(others, quote=True)}'>"
        f"{seconds(row.times.get('fem', math.nan))}</td>",
    ]
    return "<tr>" + "".join(cells) + "</tr>"


def _method_order(state: MethodState) -> tuple[int, str]:
    """Methods in one order on every row: FEM, PRBM, the exact elastica, BCM, OpenSees, then others."""
    order = ["fem", "prbm", "elastica", "bcm", "opensees"]
    return (order.index(state.method) if state.method in order else len(order), state.method)


def group_heading(group: str) -> str:
    """A group's heading: 'Chapter 2', or a source document's group (named by its seed file's three
    digits) as its key and title ('[chen2021] An energy-based framework ...')."""
    match = re.fullmatch(r"seed (\d{3})", group)
    if match and match.group(1) in SEED_KEYS:
        key = SEED_KEYS[match.group(1)]
        return f"[{key}] {document_title(key)}"
    return group.capitalize()


def estimate_text(row: CaseSummary) -> str:
    """The 'FEM error estimate' cell: the largest reliable estimate, and how many estimates are marked
    unreliable (no bound: the FEM's meshes were not in the asymptotic range), which it leaves out."""
    if not row.fem_unreliable:
        return percent(row.fem_estimate)
    mark = f"{row.fem_unreliable} unreliable"
    return f"{percent(row.fem_estimate)} ({mark})" if not math.isnan(row.fem_estimate) else mark


def _estimate_cell(row: CaseSummary) -> str:
    why = (
        "estimates marked unreliable (the FEM's meshes were not in the asymptotic range) are left out: no "
        "bound, and no FEM-against-elastica check is made with them"
    )
    title = f" title='{html.escape(why, quote=True)}'" if row.fem_unreliable else ""
    return f"<td data-value='{_raw(row.fem_estimate)}'{title}>{html.escape(estimate_text(row))}</td>"


def _why_not_compared(row: CaseSummary) -> str:
    """Why a case has no PRBM-vs-FEM number, in a few words."""
    state = {s.method: s.verdict for s in row.methods}
    missing = [METHOD_NAMES[m] for m in ("prbm", "fem") if m not in state]
    if missing:
        return f"no {' or '.join(missing)} in this case"
    refused = [
        METHOD_NAMES[m]
        for m in ("prbm", "fem")
        if state[m] in (Verdict.REFUSED, Verdict.NOT_CONVERGED, Verdict.FAILED, Verdict.EXPECTED)
    ]
    if refused:
        return f"{' and '.join(refused)} gave no answer"
    if not math.isnan(row.prbm_fem_relative):
        return "no position that both give; other outputs: see the relative error"
    return "no output that both give"


def _raw(value: float) -> str:
    return "" if value is None or math.isnan(value) else f"{value:.6g}"


def summary_tables_html(rows: list[CaseSummary], links: dict[str, str]) -> str:
    """Per group, a sortable table (click a header) of the case rows."""
    out = []
    groups = sorted({r.group for r in rows}, key=group_order)
    for group in groups:
        part = [r for r in rows if r.group == group]
        head = "".join(f"<th>{h}</th>" for h in HEADERS)
        body = "".join(_row_html(r, links.get(r.case, "#")) for r in part)
        out.append(
            f"<h3 class='group'>{html.escape(group_heading(group))}</h3>"
            f"<table class='summary sortable'><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        )
    missing = without_prbm_fem(rows)
    items = "".join(
        f"<li><a href='{html.escape(links.get(r.case, '#'), quote=True)}'>{html.escape(r.case)}</a>: "
        f"{html.escape(readable(missing_reason(r)))}</li>"
        for r in missing
    )
    line = f"<span class='caption' id='without-prbm-fem'>{html.escape(without_prbm_fem_line(rows))}</span>"
    out.append(
        f"<details class='fold'><summary>{line}</summary><ul>{items}</ul></details>" if items else f"<p>{line}</p>"
    )
    return "".join(out)


def without_prbm_fem(rows: list[CaseSummary]) -> list[CaseSummary]:
    """The cases with neither a PRBM-vs-FEM length error nor a relative error, other cases first, then the
    FEM-validation benchmarks, the stress-contract regressions and the loading readings."""
    order = [kind for kind, _, _ in KINDS]
    missing = [r for r in rows if math.isnan(r.prbm_fem_length) and math.isnan(r.prbm_fem_relative)]
    return sorted(missing, key=lambda r: order.index(_kind(r)))


def missing_reason(row: CaseSummary) -> str:
    """The one-line reason a case has no PRBM-vs-FEM number: the case's own, else what the runs say."""
    if row.no_prbm_fem:
        return row.no_prbm_fem
    if row.readings_of:
        return (
            f"a loading reading of {row.readings_of} (FEM only): the PRBM-vs-FEM number is in the row of "
            f"{row.readings_of}"
        )
    if row.group == REGRESSIONS:
        return f"a stress-contract regression: {_why_not_compared(row)} (see its findings)"
    return _why_not_compared(row)


REGRESSIONS = "stress regressions"
KINDS = (
    ("case", "other case", "other cases"),
    (FEM_VALIDATION, "FEM-validation benchmark", "FEM-validation benchmarks"),
    ("regression", "stress-contract regression", "stress-contract regressions"),
    (
        "loading reading",
        "loading reading of an experiment (its base case carries the number)",
        "loading readings of an experiment (their base case carries the number)",
    ),
)


def _kind(row: CaseSummary) -> str:
    if row.fem_validation:
        return FEM_VALIDATION
    if row.readings_of:
        return "loading reading"
    return "regression" if row.group == REGRESSIONS else "case"


def without_prbm_fem_line(rows: list[CaseSummary]) -> str:
    """The closing count: how many cases have no PRBM-vs-FEM number, by kind (each listed with its reason)."""
    missing = without_prbm_fem(rows)
    if not missing:
        return f"0 of {len(rows)} cases have no PRBM-vs-FEM number."
    counts = {kind: sum(_kind(r) == kind for r in missing) for kind, _, _ in KINDS}
    parts = [f"{counts[kind]} {one if counts[kind] == 1 else many}" for kind, one, many in KINDS if counts[kind]]
    return f"{len(missing)} of {len(rows)} cases have no PRBM-vs-FEM number ({', '.join(parts)}), each with its reason:"


def summary_markdown(rows: list[CaseSummary]) -> str:
    lines = []
    for group in sorted({r.group for r in rows}, key=group_order):
        lines += [
            f"\n### {group_heading(group)}\n",
            "| Case | Verdict | Result | PRBM vs FEM, max % of L | FEM error estimate | Printed numbers reproduced |",
            "|---|---|---|---|---|---|",
        ]
        for r in (r for r in rows if r.group == group):
            pct = _markdown_error(r)
            lines.append(
                f"| {r.case} | {r.verdict.value} | {r.sentence.replace('|', '/')} | {pct} | "
                f"{estimate_text(r)} | {f'{r.checks_passed} of {r.checks}' if r.checks else ''} |"
            )
    lines += ["", without_prbm_fem_line(rows)]
    lines += [f"- {r.case}: {missing_reason(r)}" for r in without_prbm_fem(rows)]
    return "\n".join(lines) + "\n"


def _markdown_error(row: CaseSummary) -> str:
    """The PRBM-vs-FEM cell: % of L, else the relative error, else the reason there is none."""
    if not math.isnan(row.prbm_fem_length):
        return f"{sig(100 * row.prbm_fem_length, 3)} % ({row.prbm_fem_verdict.value})"
    if not math.isnan(row.prbm_fem_relative):
        return f"relative {percent(row.prbm_fem_relative)} ({row.prbm_fem_verdict.value})"
    return f"none: {_short(missing_reason(row), 100)}".replace("|", "/")


@dataclass
class Finding:
    """One finding of one case, with the evidence of every row that carries it."""

    case: str
    text: str
    evidence: list[str]


def findings(results: list[CaseResult], table: pd.DataFrame) -> list[Finding]:
    """Case-level findings and reference findings, each once, with the printed and computed numbers."""
    out = []
    evidence = _evidence(table)
    for result in sorted(results, key=lambda r: (group_order(r.loaded.case.case.group), r.loaded.id)):
        cid = result.loaded.id
        out += [Finding(cid, text, []) for text in result.loaded.case.case.findings]
        out += [Finding(cid, str(text), lines) for text, lines in evidence.get(cid, {}).items()]
    return out


EVIDENCE_COLUMNS = ["case", "finding", "method", "quantity", "point", "level", "reference_label"]
EVIDENCE_NUMBERS = ["level_label", "value", "reference_value", "rel_error"]


def _evidence(table: pd.DataFrame) -> dict[str, dict[str, list[str]]]:
    """Per case and per finding (in the order they first appear in ``table``), a line for each row that
    carries the finding, one for each method, output, level and printed column (the first such row)."""
    noted = table["finding"].notna().to_numpy()
    if not noted.any():
        return {}
    columns = [table[c].to_numpy()[noted].tolist() for c in EVIDENCE_COLUMNS + EVIDENCE_NUMBERS]
    out: dict[str, dict[str, list[str]]] = {}
    seen = set()
    for row in zip(*columns):
        key = tuple(None if pd.isna(v) else v for v in row[: len(EVIDENCE_COLUMNS)])  # NaN matches NaN
        if key in seen:
            continue
        seen.add(key)
        case, text, method, quantity, point, _, label, level_label, value, printed, rel_error = row
        out.setdefault(str(case), {}).setdefault(text, []).append(
            f"{quantity}{'@' + point if point else ''} at {level_label}: "
            f"{METHOD_NAMES.get(method, method)} {sig(value)} against printed {label} {sig(printed)}"
            + (f" ({percent(rel_error)} apart)" if not np.isnan(rel_error) else "")
        )
    return out


def _finding_html(item: Finding, shown: int) -> str:
    """One finding with its evidence: the first ``shown`` rows, the others folded."""
    evidence = ""
    if item.evidence:
        first = "".join(f"<li>{html.escape(readable(e))}</li>" for e in item.evidence[:shown])
        rest = item.evidence[shown:]
        more = (
            (
                f"<details><summary>{len(rest)} more row(s)</summary><ul class='evidence'>"
                + "".join(f"<li>{html.escape(readable(e))}</li>" for e in rest)
                + "</ul></details>"
            )
            if rest
            else ""
        )
        evidence = f"<ul class='evidence'>{first}</ul>{more}"
    return f"<li>{html.escape(readable(item.text))}{evidence}</li>"


def findings_html(items: list[Finding], links: dict[str, str], shown: int = 3) -> str:
    """The findings folded per case: one line each (the case, how many, the first finding's start), the
    findings and their evidence behind a click."""
    if not items:
        return "<p>none</p>"
    cases: dict[str, list[Finding]] = {}
    for item in items:
        cases.setdefault(item.case, []).append(item)
    parts = []
    for case, mine in cases.items():
        count = f"{len(mine)} finding{'s' if len(mine) != 1 else ''}"
        parts.append(
            f"<details class='casefindings'><summary><a href='{html.escape(links.get(case, '#'), quote=True)}'>"
            f"{html.escape(case)}</a> <b>{count}</b>: {html.escape(readable(mine[0].text))}</summary>"
            f"<ul class='findings'>{''.join(_finding_html(item, shown) for item in mine)}</ul></details>"
        )
    return "".join(parts)


def _source_line(key: str) -> str:
    """'S. G. Bapat, 2015: On the design and analysis of ...': a cited document's first author, year and
    title (its full citation: ``references.citation``)."""
    authors = citation(key).split(', "')[0]
    first = re.split(r",| and ", authors)[0]
    year = re.search(r"\d{4}$", key)  # a key is the surname and the year, or names an undated lecture
    return (
        f"{first}{' et al.' if first != authors else ''}, {year.group() if year else 'lecture, no year printed'}: "
        f"{document_title(key)}"
    )


def key_terms() -> list[tuple[str, str]]:
    """The index's key: each term of its tables and texts an engineer may not know, with its meaning."""
    return [(f"[{key}]", _source_line(key)) for key in REFERENCES] + [
        (
            "eq 47, §2.3, ch. 4, Fig. 4.13",
            "equation, section, chapter, figure (and table) numbers of the document cited just before",
        ),
        ("L", "the characteristic length: the segment's length, or the mechanism's extent; errors in % of L"),
        (
            "P, -nP (n > 0 compressive)",
            "the end force of a segment in [bapat2015]'s notation: P across the "
            "undeformed segment, -nP along it, n = -F_x/F_y",
        ),
        (
            "Θ, γ, K_Θ",
            "the PRB angle, the characteristic radius factor and the stiffness coefficient of the "
            "pseudo-rigid-body model [bapat2015 ch. 2]",
        ),
        ("FEM error estimate", "the FEM's discretisation error, estimated from its meshes (relative)"),
        ("finding", "a printed number known not to be reproduced, with the explanation that reproduces it"),
    ]


def verdict_counts_line(rows: list[CaseSummary]) -> str:
    """The cases counted per verdict ('N cases: a within the claimed limit, ...'); the counts add up to N."""
    return counts_sentence([r.verdict for r in rows])
