"""The report's HTML page: its style sheet, the sortable-table script, and the small writers every page
uses (numbers, tables, pictures, links), each text escaped for HTML."""

from __future__ import annotations

import html
import math

import numpy as np
import pandas as pd

CSS = """body{font-family:system-ui,sans-serif;margin:1.5em 2em;max-width:1400px;color:#222}
table{border-collapse:collapse;margin:0.6em 0;font-size:13px}th,td{border:1px solid #ccc;padding:3px 6px;
text-align:right;vertical-align:top}th{background:#eee;cursor:pointer;user-select:none}
th.asc::after{content:" \\25B2"}th.desc::after{content:" \\25BC"}
td:first-child,th:first-child{text-align:left}td.sentence{text-align:left;max-width:34em}
td.absent{color:#777;font-size:12px;text-align:left;max-width:14em}
.bad{background:#fdd}.good{background:#dfd}.finding{background:#ffd}img{max-width:100%;border:1px solid #ddd}
.badge{color:#fff;border-radius:3px;padding:1px 6px;font-size:12px;white-space:nowrap}
.cellverdict{display:block;font-size:11px;color:#333}
.method{border:2px solid;border-radius:3px;padding:0 4px;margin:1px;font-size:12px;white-space:nowrap;
display:inline-block}.lead{font-size:1.15em;margin:0.4em 0 0.8em}ul.evidence{font-size:12px;color:#444}
details{margin:0.6em 0}summary{cursor:pointer;font-weight:600}.caption{font-size:12px;color:#444;max-width:60em}
code{background:#f4f4f4;padding:1px 3px}
table.summary{font-size:12px}table.summary td{white-space:nowrap;padding:1px 5px;line-height:1.3}table.summary th{font-size:11px;padding:2px 5px}h3.group{margin:0.9em 0 0.1em;font-size:1.05em}
table.summary td.sentence{width:100%;max-width:0;overflow:hidden;text-overflow:ellipsis;cursor:pointer}
table.summary td.sentence.open{white-space:normal}table.summary td.absent{white-space:normal;min-width:8em;font-size:11px}
table.summary td.methods{text-align:left}table.summary td.relative{color:#777;font-size:11px}table.summary .method{margin:0 1px;padding:0 3px;font-size:11px;border-width:1px;line-height:1.2}
dl.key{display:grid;grid-template-columns:max-content 1fr max-content 1fr;gap:1px 1em;font-size:12px;margin:0.4em 0}
dl.key dt{font-weight:600}p.caption.vocabulary{max-width:none}dl.key dd{margin:0}
details.casefindings,details.fold{margin:0.1em 0}details.casefindings{font-size:13px}
details.casefindings>summary,details.fold>summary{white-space:nowrap;overflow:hidden;text-overflow:ellipsis;
font-weight:normal}details.casefindings[open]>summary,details.fold[open]>summary{white-space:normal}"""
SORT_JS = """document.querySelectorAll('table.sortable th').forEach(th=>th.addEventListener('click',()=>{
const i=th.cellIndex,body=th.closest('table').tBodies[0],asc=!th.classList.contains('asc');
th.closest('tr').querySelectorAll('th').forEach(h=>h.classList.remove('asc','desc'));
th.classList.add(asc?'asc':'desc');
const key=r=>{const c=r.children[i],v=c.dataset.value!==undefined?c.dataset.value:c.innerText;
const n=parseFloat(v);return v!==''&&!isNaN(n)?n:v.toLowerCase()};
[...body.rows].sort((x,y)=>{const a=key(x),b=key(y);if(a===b)return 0;
if(a===''||b==='')return a===''?1:-1;
return (typeof a==typeof b?(a<b?-1:1):(typeof a=='number'?-1:1))*(asc?1:-1)})
.forEach(r=>body.appendChild(r))}));
document.querySelectorAll('table.summary td.sentence').forEach(c=>c.addEventListener('click',()=>c.classList.toggle('open')));"""


def _fmt(value, digits: int = 6) -> str:
    if type(value) is str:  # the most common cell first: text, as it is
        return value
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return f"{value:.{digits}g}"
    return str(value)


def _html_table(frame: pd.DataFrame, row_class=None, digits: int = 4) -> str:
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
    body = []
    columns = list(frame.columns)
    for values in frame.values:  # the rows as iterrows gives them (its Series are built on these), no Series
        cls = row_class(dict(zip(columns, values))) if row_class else ""
        cells = "".join(f"<td>{html.escape(_fmt(v, digits))}</td>" for v in values)
        body.append(f"<tr class='{cls}'>{cells}</tr>")
    return f"<table class='sortable'><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _md_table(frame: pd.DataFrame) -> str:
    if frame.empty:
        return "_none_\n"
    lines = ["| " + " | ".join(map(str, frame.columns)) + " |", "|" + "---|" * len(frame.columns)]
    for values in frame.values:  # as in _html_table
        lines.append("| " + " | ".join(_fmt(v).replace("|", "/") for v in values) + " |")
    return "\n".join(lines) + "\n"


def _image(src: str, alt: str) -> str:
    """A picture of the report, its file name escaped for the attribute."""
    return f"<p><img src='{html.escape(src, quote=True)}' alt='{html.escape(alt, quote=True)}'></p>"


def _link(href: str, text: str) -> str:
    return f"<a href='{html.escape(href, quote=True)}'>{html.escape(text)}</a>"


def _page(title: str, body: str, head: str = "") -> str:
    return (
        f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
        f"<style>{CSS}</style>{head}</head><body>{body}<script>{SORT_JS}</script></body></html>"
    )
