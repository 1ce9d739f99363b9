"""The documents the code cites, each once, by a key: ``REFERENCES[key]`` is its full citation.

Docstrings and comments cite a source by its key in brackets, with the place in it after a comma:
``[bapat2015, eq 47]``, ``[bapat2015, eqs 41-49]``, ``[bapat2015, §2.3]``, ``[bapat2015, ch. 4]``,
``[bapat2015, Table 3.2]``, ``[bapat2015, Fig. 4.6]``, ``[chen2021, §4.1]``; ``[bapat2015]`` alone
cites the whole document.  Equation, section, table and figure numbers are the document's own; the
lecture has none, so a place in it is the transcript's slide time ("Refer Slide Time"), e.g.
``[ananthasuresh_l18, 07:13-12:05]`` for its fixed-guided beam.  A key is the first author's surname
and the year (``bapat2015``, ``chen2021``); the lecture transcript prints no year, so its key names
the lecture instead (``ananthasuresh_l18``).  ``tests/project/test_no_history.py`` checks that every key cited
in a docstring or comment is one of ``REFERENCES``.

The documents themselves (the project's "seed" documents) are kept beside the repository, not in it,
as plain text under the file names of ``Reference.seed_file``; the case files' ``source`` fields name
those files (data the harness reads and prints as it is).

A leaf package: it imports nothing of the project, so every package may import it (no mathematics and
no angles here).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Reference:
    """One cited document: its key, full citation, first author's surname and seed file name."""

    key: str
    citation: str
    surname: str
    seed_file: str


REFERENCES: dict[str, Reference] = {
    ref.key: ref
    for ref in (
        Reference(
            "bapat2015",
            'S. G. Bapat, "On the design and analysis of compliant mechanisms using the pseudo-rigid-body '
            'model concept", Ph.D. dissertation (advisor A. Midha), Department of Mechanical and Aerospace '
            "Engineering, Missouri University of Science and Technology, 2015. Doctoral Dissertations 2376, "
            "https://scholarsmine.mst.edu/doctoral_dissertations/2376",
            "bapat",
            "000_0cc428dae4265b0a.txt",
        ),
        Reference(
            "chen2021",
            'G. Chen, F. Ma, R. Bai, W. Zhu, S. P. Magleby and L. L. Howell, "An energy-based framework for '
            'nonlinear kinetostatic modeling of compliant mechanisms utilizing beam flexures", Journal of '
            "Computing and Information Science in Engineering 21(6), 064501, 2021 (the beam constraint "
            "model's strain energy and complementary energy, Castigliano's first theorem and the "
            "Crotti-Engesser theorem)",
            "chen",
            "003_2353723c375451e7.txt",
        ),
        Reference(
            "ananthasuresh_l18",
            'G. K. Ananthasuresh, "Pseudo rigid-body (PRB) modeling", Lecture 18 of the course "Compliant '
            'Mechanisms: Principles and Design" (NPTEL), Department of Mechanical Engineering, Indian '
            "Institute of Science, Bangalore; lecture transcript (no year printed). Its PRB models and n-fits "
            "are those of L. L. Howell, Compliant Mechanisms, Wiley, 2001, and L. L. Howell and A. Midha, "
            "J. Mech. Des. 117(1), 156-165, 1995",
            "ananthasuresh",
            "004_f476baa17c1f7da6.txt",
        ),
    )
}


def citation(key: str) -> str:
    """The full citation of ``key``; a ValueError naming the known keys for any other."""
    if key not in REFERENCES:
        raise ValueError(f"unknown reference key {key!r}; known: {', '.join(sorted(REFERENCES))}")
    return REFERENCES[key].citation


def key_of_seed_file(name: str) -> str:
    """The key of the document kept as seed file ``name`` (a case file's ``source`` names it)."""
    for ref in REFERENCES.values():
        if ref.seed_file == name:
            return ref.key
    raise ValueError(
        f"no reference is kept as {name!r}; known: {', '.join(sorted(r.seed_file for r in REFERENCES.values()))}"
    )
