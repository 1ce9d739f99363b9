"""Every string of a case file is text in the report, in every HTML context: element text, attribute
values, and the JSON of the charts inside <script> (where '<', '>' and '&' are JSON escapes, so that
'</script>' or '<!--' cannot end or bend the script element, and plotly.js labels are HTML-escaped, so
that its few tags are never read from a case file).

A case whose title, group, description, source, assumptions, findings, level labels, load label,
reference source and note carry script (ids are refused at load: ``test_input_ranges``) is built into a
report; both its pages are parsed with ``html.parser`` and no element, attribute or script of them may
come from those strings."""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest
import tomli_w

from validation.report.build import build_report

PAYLOADS = {
    1: "<img src=x onerror=alert(1)> title",
    2: "<script>alert(2)</script> group",
    3: "</script><script>alert(3)</script> description <!--",
    4: "<img src=x onerror=alert(4)>",
    5: "' onmouseover='alert(5)",
    6: "<b onclick=alert(6)>assumption</b>",
    7: "<img src=x onerror=alert(7)> finding",
    8: "</script><img src=x onerror=alert(8)> load & <!--",
    9: "<img src=x onerror=alert(9)>",
    10: '"><svg onload=alert(10)>',
    11: "<img src=x onerror=alert(11)>",
    12: "' onerror='alert(12)",
    13: "<img src=x onerror=alert(13)> note",
}
CASE = {
    "level_labels": [PAYLOADS[9], PAYLOADS[10]],
    "case": {
        "id": "hostile_strings",
        "title": PAYLOADS[1],
        "group": PAYLOADS[2],
        "units": "dimensionless",
        "description": PAYLOADS[3],
        "source": {"file": PAYLOADS[4], "section": PAYLOADS[5], "note": "<!-- note"},
        "assumptions": [PAYLOADS[6]],
        "findings": [PAYLOADS[7]],
    },
    "segment": {"boundary": "fixed-free", "length": 1.0, "E": 1.0, "section": {"kind": "inertia", "I": 1.0, "A": 1e6}},
    "loads": [{"kind": "force", "point": "tip", "direction": [0.0, 1.0], "values": [0.5, 1.0], "label": PAYLOADS[8]}],
    "outputs": [{"quantity": "y"}, {"quantity": "rotation"}],
    "methods": {"prbm": {}},
    # printed 999 against ~0.3: a comparison outside its tolerance, listed on the index with its level label
    "references": [
        {
            "quantity": "y",
            "level": 1,
            "value": 999.0,
            "label": "published",
            "compare": "prbm",
            "tolerance": {"rel": 0.01},
            "note": PAYLOADS[13],
            "source": {"file": PAYLOADS[11], "table": "</script>", "row": "<!--", "column": PAYLOADS[12]},
        }
    ],
}


class Page(HTMLParser):
    """Every start tag with its attributes, the text of every <script> and the rest of the text."""

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, dict]] = []
        self.scripts: list[str] = []
        self.text: list[str] = []
        self._script: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag == "script":
            self._script = []

    def handle_endtag(self, tag):
        if tag == "script" and self._script is not None:
            self.scripts.append("".join(self._script))
            self._script = None

    def handle_data(self, data):
        (self._script if self._script is not None else self.text).append(data)


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("hostile")
    path = folder / "hostile.toml"
    path.write_text(tomli_w.dumps(CASE))
    build_report(folder / "report", use_cache=False, jobs=1, cases=[str(path)])
    return folder / "report"


def test_no_markup_of_the_report_comes_from_the_case_file(report):
    for page, expected in (("index.html", {7, 10}), ("cases/hostile_strings.html", {1, 3, 4, 5, 6, 7})):
        parsed = Page((report / page).read_text())
        assert not [(tag, attrs) for tag, attrs in parsed.tags if any(name.startswith("on") for name in attrs)], page
        assert not [tag for tag, _ in parsed.tags if tag in ("svg", "iframe", "object", "embed")], page
        images = [attrs.get("src", "") for tag, attrs in parsed.tags if tag == "img"]
        assert images and all(re.fullmatch(r"[\w./-]+\.png", src) for src in images), (page, images)
        assert not [s for s in parsed.scripts if "alert(" in s and "Plotly.newPlot" not in s], page
        text = "".join(parsed.text)
        # shown as text: on the index the finding and the list of comparisons outside their tolerance with
        # the level's label; on the case page its title, description, source, assumption and finding
        assert expected <= {k for k in PAYLOADS if f"alert({k})" in text}, page
    assert "Comparisons outside the claimed limit" in (report / "index.html").read_text()


def test_the_charts_json_cannot_end_its_script_and_gives_the_strings_back(report):
    parsed = Page((report / "cases" / "hostile_strings.html").read_text())
    charts = [s for s in parsed.scripts if "Plotly.newPlot" in s]
    assert charts
    labels = []
    for script in charts:
        spec = re.search(r"const f=(.*?);Plotly\.newPlot\(", script, flags=re.S).group(1)
        assert not set("<>&") & set(spec), "'<', '>' and '&' only as JSON escapes"
        figure = json.loads(spec)
        labels += [
            axis["title"]["text"] for key, axis in figure["layout"].items() if key.startswith(("xaxis", "yaxis"))
        ]
    # the load's label is the outputs chart's x title: as written, HTML-escaped for plotly.js's text
    assert any("&lt;/script&gt;&lt;img src=x onerror=alert(8)&gt; load &amp; &lt;!--" in label for label in labels)
