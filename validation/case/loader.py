"""Load case files: TOML -> validated ``Case``, with every error of a file listed, one line each,
naming the file, the field and what is wrong.

A case is checked completely before any solve: the schema (``validation/case/schema.py``, with the options
of each method, ``validation/case/method_options.py``) and, for a mechanism or a segment, whether it is
held against rigid-body motion (``validation/case/mobility.py``). Case files can live anywhere: ids, files, folders
and globs are all accepted, and unknown names get the nearest valid ones, as do misspelled fields
("segment.lenght: unknown field; did you mean 'length'?", ``unknown_field``).
"""

from __future__ import annotations

import difflib
import fnmatch
import glob
import os
import re
import tomllib
import typing
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel, ValidationError

from validation.case import mobility
from validation.case.names import nearest
from validation.case.schema import Case
from validation.case.strict import field_path

CASES_DIR = Path(__file__).resolve().parents[2] / "cases"
SKIPPED = {"node_modules", "__pycache__", "venv", "site-packages", "reports"}  # never case folders
# the project's data folders kept with the cases: design specifications and sweep studies, not cases
DATA_FOLDERS = (CASES_DIR / "specs", CASES_DIR / "sweeps", CASES_DIR / "atlas")


class CaseError(Exception):
    """A case file that cannot be used; ``str()`` has one line per problem (file: field: problem),
    the first problem first. ``field`` and ``problem`` are the first; ``problems`` has them all."""

    def __init__(self, path: Path | str, field: str, problem: str, more: list[tuple[str, str]] | None = None):
        self.path, self.field, self.problem = str(path), field, problem
        self.problems: list[tuple[str, str]] = [(field, problem), *(more or [])]
        super().__init__("\n".join(self._line(f, p) for f, p in self.problems))

    def _line(self, field: str, problem: str) -> str:
        return f"{self.path}: {field}: {problem}" if field else f"{self.path}: {problem}"


class SpecError(CaseError):
    """A sweep spec or a design specification that cannot be used (same lines as ``CaseError``)."""


@dataclass(frozen=True)
class LoadedCase:
    path: Path
    text: str
    case: Case

    @property
    def id(self) -> str:
        return self.case.case.id


def _field_path(location: tuple) -> str:
    """Dotted field path of a pydantic error location, without validator and union-member tags."""
    return field_path(location) or "(top level)"


_FIELD_PREFIX = re.compile(r"^([A-Za-z_][\w.]*): (.+)$")


def _models_in(annotation) -> list[type[BaseModel]]:
    """The pydantic models an annotation holds (``X``, ``X | None``, ``list[X]``, ``dict[str, X]``,
    ``Annotated[X, ...]``, unions of them)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for arg in typing.get_args(annotation) for m in _models_in(arg)]


def field_names(model: type[BaseModel], location: tuple) -> list[str]:
    """The field names (as a file writes them: aliases) of the model(s) that a pydantic error
    ``location`` leads to from ``model``; list indices, dict keys and union tags are stepped over."""
    models = [model]
    for part in location:
        below = [
            m
            for current in models
            if isinstance(part, str) and part in current.model_fields
            for m in _models_in(current.model_fields[part].annotation)
        ]
        models = below or models
    return sorted({field.alias or name for m in models for name, field in m.model_fields.items()})


def unknown_field(name: str, known: list[str]) -> str:
    """ "unknown field; did you mean 'length'?" (the nearest names, ``difflib``), or the valid names
    when none is close."""
    close = difflib.get_close_matches(name, known, n=2, cutoff=0.6)
    if close:
        return f"unknown field; did you mean {' or '.join(repr(c) for c in close)}?"
    return f"unknown field{nearest(name, known)}"


def describe_all(exc: ValidationError, model: type[BaseModel] | None = None) -> list[tuple[str, str]]:
    """(field path, message) of every error of a pydantic ValidationError, in pydantic's order; with
    the ``model`` validated, an unknown field comes with the nearest valid names (``unknown_field``).

    A model-level check that found several problems reports them one per line, each as
    ``field: message``; those lines become separate errors with their own field."""
    problems = []
    for err in exc.errors():
        field = _field_path(err["loc"])
        below = (err.get("ctx") or {}).get("field")  # a method option's path below 'methods'
        field = f"{field}.{below}" if below else field
        if err["type"] == "extra_forbidden" and model is not None and err["loc"]:
            problems.append((field, unknown_field(str(err["loc"][-1]), field_names(model, err["loc"][:-1]))))
            continue
        for part in err["msg"].removeprefix("Value error, ").split("\n"):
            match = _FIELD_PREFIX.match(part)
            if match and field == "(top level)":
                problems.append((match.group(1), match.group(2)))
            else:
                problems.append((field, part))
    return _without_explained_missing(problems)


def _without_explained_missing(problems: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """``problems`` less each required field reported missing that a misspelled field beside it is
    the nearest name of ('segment.lenght: ... did you mean 'length'?' explains 'segment.length: Field
    required')."""
    meant = {
        f"{field.rpartition('.')[0]}.{name}".lstrip(".")
        for field, problem in problems
        if problem.startswith("unknown field; did you mean")
        for name in re.findall(r"'([^']+)'", problem.partition("did you mean")[2])
    }
    return [(f, p) for f, p in problems if not (p == "Field required" and f in meant)] or problems


def describe(exc: ValidationError) -> tuple[str, str]:
    """(field path, message) of the first error of a pydantic ValidationError."""
    return describe_all(exc)[0]


def read_toml_model(path: Path | str, model, error=None):
    """(text, validated model) of a TOML file; any problem raises ``error(path, field, problem)``
    (``CaseError`` by default), whose ``str()`` names the file, the field path and what is wrong,
    one line per problem."""
    error = error or CaseError
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise error(path, "", f"cannot read file ({exc.strerror})") from None
    except UnicodeDecodeError as exc:  # TOML is UTF-8 text
        raise error(
            path,
            "",
            f"not UTF-8 text: byte 0x{exc.object[exc.start]:02x} at offset {exc.start} (save the file as UTF-8)",
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(path, "", f"not valid TOML: {exc}") from None
    try:
        return text, model.model_validate(data)
    except ValidationError as exc:
        problems = describe_all(exc, model if isinstance(model, type) else None)
        (field, message), more = problems[0], problems[1:]
        if isinstance(error, type) and issubclass(error, CaseError):
            raise error(path, field, message, more) from None
        raise error(path, field, "; ".join([message] + [f"{f}: {m}" for f, m in more])) from None


def check_case(case: Case) -> list[tuple[str, str]]:
    """(field, problem) of everything wrong with a schema-valid case (the schema checks the method
    options) that would otherwise only show in a solve: a mechanism, or a segment under its boundary and
    loads (a pinned-pinned one loaded across its chord), that can move as a rigid body."""
    return mobility.check(case)


def load_case(path: Path | str) -> LoadedCase:
    """Read and validate one case file; raise ``CaseError`` listing every problem, one per line."""
    text, case = read_toml_model(path, Case)
    problems = check_case(case)
    if problems:
        (field, message), more = problems[0], problems[1:]
        raise CaseError(path, field, message, more)
    return LoadedCase(path=Path(path), text=text, case=case)


def search_roots(patterns: list[str], root: Path = CASES_DIR) -> list[Path]:
    """Where ids are looked up: ``root``, the current folder, and every folder (or folder of a
    file) named alongside."""
    roots = [root, Path.cwd()]
    for pattern in patterns:
        p = Path(pattern)
        if p.is_dir():
            roots.append(p)
        elif p.is_file():
            roots.append(p.parent)
    return list(dict.fromkeys(r.resolve() for r in roots))


def find_case_files(
    patterns: list[str] | None = None, root: Path = CASES_DIR, roots: list[Path] | None = None
) -> list[Path]:
    """Case files matching ids, files, folders (every ``*.toml`` below) or globs; all of ``root``
    if none given. Ids are looked up in ``roots`` (default: ``root`` and the folders named
    alongside). An unknown name raises ``CaseError`` with the nearest valid ids."""
    if not patterns:
        return _toml_files(root)
    roots = roots or search_roots(patterns, root)
    found: list[Path] = []
    for pattern in patterns:
        if Path(pattern).is_dir():
            matches = _toml_files(Path(pattern))
            if not matches:
                raise CaseError(pattern, "", "the folder holds no case file (*.toml)")
            found.extend(m.resolve() for m in matches)
            continue
        matches = [Path(p) for p in glob.glob(pattern, recursive=True)]  # a path as given
        below = glob.glob(str(root / "**" / pattern), recursive=True)  # a name found below root
        below += glob.glob(str(root / "**" / f"{pattern}.toml"), recursive=True)
        matches += [Path(p) for p in below if not _in_data_folder(Path(p))]
        matches = [m for m in matches if m.suffix == ".toml" and m.is_file()]
        if not matches:
            index = _ids_in(roots, pattern)
            matches = [path for case_id, path in index.items() if fnmatch.fnmatchcase(case_id, pattern)]
            if not matches:
                raise CaseError(pattern, "", "no case file matches this id, file or pattern" + nearest(pattern, index))
        found.extend(sorted(set(m.resolve() for m in matches)))
    return list(dict.fromkeys(found))


def _in_data_folder(path: Path) -> bool:
    """The file lies in one of the project's data folders (design specifications, sweeps, the atlas's claims)."""
    resolved = path.resolve()
    return any(folder.resolve() in resolved.parents for folder in DATA_FOLDERS)


def _toml_files(root: Path) -> list[Path]:
    """Every ``*.toml`` under root, not looking inside hidden folders, virtual environments or the
    project's data folders (``cases/specs``, ``cases/sweeps``, ``cases/atlas``) unless root is one of them."""
    found: list[Path] = []
    root = Path(root).resolve()
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = sorted(
            d
            for d in subfolders
            if not d.startswith(".") and d not in SKIPPED and (Path(folder) / d).resolve() not in DATA_FOLDERS
        )
        found.extend(Path(folder) / f for f in sorted(files) if f.endswith(".toml"))
    return found


def _ids_in(roots: list[Path], pattern: str) -> dict[str, Path]:
    """The ids of the case files under ``roots`` that can match ``pattern``: for a plain id (no glob
    characters) only the files with a line ``id = "<pattern>"`` are parsed; when none of those has it
    as its id (an id written with escapes or as a dotted or inline key, a misspelling), every file
    is, for the error's nearest ids."""
    if not any(c in pattern for c in "*?["):
        index = {k: v for r in roots for k, v in _id_index(r, pattern).items()}
        if pattern in index:
            return index
    return {k: v for r in roots for k, v in _id_index(r).items()}


def _id_index(root: Path, containing: str | None = None) -> dict[str, Path]:
    """[case].id of every readable case file under root (files that do not parse are skipped here;
    loading them reports their error); with ``containing``, only of the files with a line giving some
    key ``id`` that quoted value (reading a file is cheap, parsing it is not: a case's id is also
    named in other files' references)."""
    index: dict[str, Path] = {}
    id_line = (
        None
        if containing is None
        else re.compile(r"^[ \t]*id[ \t]*=[ \t]*([\"'])" + re.escape(containing) + r"\1", re.MULTILINE)
    )
    for path in _toml_files(root):
        try:
            text = path.read_text(encoding="utf-8")
            if containing is not None and id_line is not None and (containing not in text or not id_line.search(text)):
                continue
            case_id = tomllib.loads(text)["case"]["id"]
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, KeyError, TypeError):
            continue
        index.setdefault(str(case_id), path)
    return index


def case_by_id(case_id: str, root: Path = CASES_DIR) -> LoadedCase:
    """The case whose [case].id is ``case_id``; ``CaseError`` with the nearest ids otherwise."""
    index = _ids_in([root], case_id)
    if case_id in index:
        return load_case(index[case_id])
    raise CaseError(case_id, "case.id", "no case file has this id" + nearest(case_id, index))
