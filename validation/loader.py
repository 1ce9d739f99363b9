"""Load case files: TOML -> validated ``Case``, with one-line errors naming file, field and problem."""
from __future__ import annotations

import fnmatch
import glob
import tomllib
from dataclasses import dataclass
from pathlib import Path

from pydantic import ValidationError

from validation.schema import Case

CASES_DIR = Path(__file__).resolve().parent.parent / "cases"


class CaseError(Exception):
    """A case file that cannot be used; ``str()`` is the one-line message for the user."""

    def __init__(self, path: Path | str, field: str, problem: str):
        self.path, self.field, self.problem = str(path), field, problem
        super().__init__(f"{self.path}: {field}: {problem}" if field else f"{self.path}: {problem}")


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
    def is_tag(part) -> bool:
        return isinstance(part, str) and (part.startswith("function-") or "[" in part
                                          or part in ("str", "int", "float", "bool"))
    return ".".join(str(p) for p in location if not is_tag(p)) or "(top level)"


def read_toml_model(path: Path | str, model, error=CaseError):
    """(text, validated model) of a TOML file; any problem raises ``error(path, field, problem)``,
    whose ``str()`` is one line naming the file, the field path and what is wrong."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise error(path, "", f"cannot read file ({exc.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(path, "", f"not valid TOML: {exc}") from None
    try:
        return text, model.model_validate(data)
    except ValidationError as exc:
        field, message = describe(exc)
        raise error(path, field, message) from None


def load_case(path: Path | str) -> LoadedCase:
    """Read and validate one case file; raise ``CaseError`` with a one-line message on any problem."""
    text, case = read_toml_model(path, Case)
    return LoadedCase(path=Path(path), text=text, case=case)


def describe(exc: ValidationError) -> tuple[str, str]:
    """(field path, message) of the first error of a pydantic ValidationError, for one-line reports."""
    err = exc.errors()[0]
    more = f" (and {exc.error_count() - 1} more)" if exc.error_count() > 1 else ""
    path = _field_path(err["loc"])
    below = (err.get("ctx") or {}).get("field")  # a method option's path below 'methods'
    return (f"{path}.{below}" if below else path), err["msg"].removeprefix("Value error, ") + more


def find_case_files(patterns: list[str] | None = None, root: Path = CASES_DIR) -> list[Path]:
    """Case files matching ids, paths or globs (relative to cwd or to ``cases/``); all if none given."""
    if not patterns:
        return sorted(root.rglob("*.toml"))
    found: list[Path] = []
    for pattern in patterns:
        matches = [Path(p) for p in glob.glob(pattern, recursive=True)]
        matches += [Path(p) for p in glob.glob(str(root / "**" / pattern), recursive=True)]
        matches += [Path(p) for p in glob.glob(str(root / "**" / f"{pattern}.toml"), recursive=True)]
        matches = [m for m in matches if m.suffix == ".toml" and m.is_file()]
        if not matches:
            matches = [path for case_id, path in _id_index(root).items() if fnmatch.fnmatchcase(case_id, pattern)]
        if not matches:
            raise CaseError(pattern, "", "no case file matches this name or pattern")
        found.extend(sorted(set(m.resolve() for m in matches)))
    unique = list(dict.fromkeys(found))
    return unique


def _id_index(root: Path) -> dict[str, Path]:
    """[case].id of every readable case file under root (files that do not parse are skipped here;
    loading them reports their error)."""
    index = {}
    for path in sorted(root.rglob("*.toml")):
        try:
            case_id = tomllib.loads(path.read_text(encoding="utf-8"))["case"]["id"]
        except (OSError, tomllib.TOMLDecodeError, KeyError, TypeError):
            continue
        index.setdefault(str(case_id), path)
    return index


def case_by_id(case_id: str, root: Path = CASES_DIR) -> LoadedCase:
    """The case whose [case].id is ``case_id`` (for tests)."""
    for path in find_case_files(None, root):
        loaded = load_case(path)
        if loaded.id == case_id:
            return loaded
    raise CaseError(case_id, "case.id", "no case file has this id")
