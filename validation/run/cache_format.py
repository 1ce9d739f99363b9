"""A method run (`MethodRun`) as the bytes of a run-cache entry, and back: plain data only, so that
reading an entry cannot run code, and checked, so that a changed byte is found before any value is served.

An entry is three parts, one after the other:

- the line ``MAGIC`` (``prbm-validate method run``);
- a header line, JSON: ``{"schema": SCHEMA_VERSION, "structure": n, "data": m, "sha256": hex}``;
- the payload: ``n`` bytes of UTF-8 JSON, ``{"key": key, "run": ...}``, then ``m`` bytes of array data
  (each array's bytes at an offset that is a multiple of ``ALIGN``).

``sha256`` is the SHA-256 of the payload. Reading checks, in this order, the magic line, the schema
version, the payload's length against the header's sizes (a truncated entry), the digest (a changed
byte), and after decoding the key (an entry copied under another key's name holds another case's
run); a failed check raises `EntryError` with the reason, and nothing of the entry is used.

Why this format: a run is mostly a few hundred floats and strings keyed by requests, plus, for the
FEM, a few dozen arrays (the deformed mesh and its element forces, up to a few MB). JSON says the
structure; raw bytes hold the arrays exactly and read back with one copy (JSON lists of floats would
be several times larger and slower to read; a ``.npz`` archive costs a zip entry and a parsed array
header per member, several times this format's reading time on the shipped cases).

The structure is JSON with a tag ``"$"`` for what JSON cannot say; a JSON object without ``"$"`` is a
dict with those string keys:

- ``None``, ``bool``, ``int``, ``str``, ``list``: themselves; a finite ``float`` a JSON number (its
  ``repr``, which reads back to the same double); a NaN or an infinity ``{"$": "float", "bits": hex}``,
  its 8 bytes, so every float comes back bit for bit;
- ``tuple``: ``{"$": "tuple", "items": [...]}``; a dict keyed by instances of one named tuple of
  ``CLASSES`` (a run's values, keyed by `Request`): ``{"$": "keyed", "class": tag, "keys": [[...], ...],
  "values": [...]}``; any other dict with a key that is not a string, or a key ``"$"``:
  ``{"$": "dict", "items": [[key, value], ...]}``;
- a NumPy scalar: ``{"$": "scalar", "dtype": ..., "bits": hex}``; an array (numeric or boolean dtype):
  ``{"$": "array", "dtype": ..., "shape": [...], "at": offset}`` with ``"order": "F"`` for one kept in
  Fortran order (its transpose's bytes); the same array object twice is stored once and reads back as
  two views of the same bytes;
- an instance of a class of ``CLASSES``, by its tag: a named tuple ``{"$": tag, "v": [...]}``, an enum
  member ``{"$": tag, "v": value}``, a dataclass ``{"$": tag, "ref": r, "f": {field: value}}`` (its
  fields, not its cached properties), and the same instance again ``{"$": "ref", "ref": r}`` (the
  FEM's elements share their `fem.Section`, and `fem.result._ElementForces.section_groups` groups
  them by identity);
- a lazy value that pickles as another object (`validation.methods.base.DeferredList` as its list, the
  FEM adapter's deferred field series as its `fem.result.FieldSeries`): that object.

Reading builds only the classes of ``CLASSES`` (a dataclass without calling its ``__init__``, as
pickle restores one: the stored fields are the state), and only when the stored fields are exactly
the class's fields. The classes are named by module and name and imported when an entry holds one,
as reading a FEM run needs ``fem``; the run cache itself stays light to import. Anything else a run
holds is refused when it is written (``TypeError``), so a run is cached exactly or not at all.

The checksum finds corruption (a changed, lost or added byte), not forgery: whoever can write the
cache folder can write a valid entry, as they could edit the source files.
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib
import json
import math
import struct
from enum import Enum
from functools import lru_cache
from typing import Any

import numpy as np

from validation.methods.base import MethodRun

MAGIC = b"prbm-validate method run\n"
SCHEMA_VERSION = 1

# tag -> (module, class name, kind): every class an entry may hold besides the builtins and NumPy's
CLASSES: dict[str, tuple[str, str, str]] = {
    "MethodRun": ("validation.methods.base", "MethodRun", "dataclass"),
    "Request": ("validation.methods.base", "Request", "namedtuple"),
    "RunStatus": ("validation.methods.base", "RunStatus", "enum"),
    "Applicability": ("validation.methods.base", "Applicability", "enum"),
    "FieldSeries": ("fem.result", "FieldSeries", "dataclass"),
    "ElementForces": ("fem.result", "_ElementForces", "dataclass"),
    "Section": ("fem.section", "Section", "dataclass"),
}
_TAG_OF = {(module, name): tag for tag, (module, name, _) in CLASSES.items()}
ARRAY_KINDS = "biufc"  # bool, signed and unsigned integer, float, complex: no object, no record
ALIGN = 16  # bytes: every array's offset in the data, so that each is aligned as NumPy's own


class EntryError(ValueError):
    """An entry that cannot be used (corrupt, truncated, foreign, of another schema version, or of a
    run whose classes have changed since); the message says why."""


def encode(run: MethodRun, key: str) -> bytes:
    """The entry's bytes for ``run`` stored under ``key``. Raises ``TypeError`` for a run holding an
    object the format cannot write exactly."""
    writer = _Writer()
    structure = json.dumps({"key": key, "run": writer.value(run)}, allow_nan=False, separators=(",", ":")).encode()
    data = writer.data()
    payload = structure + data
    header = {
        "schema": SCHEMA_VERSION,
        "structure": len(structure),
        "data": len(data),
        "sha256": hashlib.sha256(payload).hexdigest(),
    }
    return MAGIC + json.dumps(header, separators=(",", ":")).encode() + b"\n" + payload


def decode(entry: bytes, key: str) -> MethodRun:
    """The run an entry's bytes hold, after every check of the module docstring; ``EntryError`` says
    why an entry cannot be used."""
    if not entry.startswith(MAGIC):
        truncated = MAGIC.startswith(entry)
        raise EntryError(f"truncated to {len(entry)} bytes" if truncated else "not an entry of this format")
    end = entry.find(b"\n", len(MAGIC))
    if end < 0:
        raise EntryError(f"truncated to {len(entry)} bytes, within its header")
    try:
        header = json.loads(entry[len(MAGIC) : end])
        schema, sizes, digest = header["schema"], (header["structure"], header["data"]), header["sha256"]
    except (ValueError, KeyError, TypeError):
        raise EntryError("not an entry of this format (no header)") from None
    if schema != SCHEMA_VERSION:
        raise EntryError(f"schema version {schema!r}, this code reads {SCHEMA_VERSION}")
    if not all(type(n) is int and n >= 0 for n in sizes) or type(digest) is not str:
        raise EntryError("a header without the payload's sizes and checksum")
    payload = memoryview(entry)[end + 1 :]
    if len(payload) != sum(sizes):
        raise EntryError(f"truncated or extended: a payload of {len(payload)} bytes, its header says {sum(sizes)}")
    if hashlib.sha256(payload).hexdigest() != digest:
        raise EntryError("its checksum does not match its payload")
    structure = payload[: sizes[0]]
    packed = np.frombuffer(payload, dtype=np.uint8, offset=sizes[0]).copy()  # aligned and writable
    try:
        document = json.loads(bytes(structure), object_hook=_Reader(packed).tagged)
    except EntryError:
        raise
    except Exception as exc:  # whatever the structure's text makes the decoder raise: unusable
        raise EntryError(f"undecodable ({_reason(exc)})") from None
    if type(document) is not dict or type(document.get("run")) is not MethodRun:
        raise EntryError("does not hold a method run")
    if document.get("key") != key:
        raise EntryError(f"holds the run of another key, {document.get('key')!r}")
    return document["run"]


def _reason(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}".replace("\n", " ")[:200]


def _float_bits(value: float) -> str:
    return struct.pack("<d", value).hex()


class _Writer:
    """The JSON tree of a value; the bytes of the arrays it refers to, each at an offset aligned to
    ``ALIGN`` bytes, in ``data()``."""

    def __init__(self) -> None:
        self._chunks: list[bytes] = []
        self._size = 0
        self._arrays: dict[int, dict] = {}
        self._refs: dict[int, int] = {}
        self._keep: list[Any] = []  # what ``id`` keys refer to stays alive while writing

    def data(self) -> bytes:
        return b"".join(self._chunks)

    def value(self, obj: Any) -> Any:
        kind = type(obj)
        if obj is None or kind is str or kind is int or kind is bool:
            return obj
        if kind is float:
            return obj if math.isfinite(obj) else {"$": "float", "bits": _float_bits(obj)}
        if kind is list:
            return [self.value(item) for item in obj]
        if kind is dict:
            if all(type(k) is str for k in obj) and "$" not in obj:
                return {k: self.value(v) for k, v in obj.items()}
            tag = _keyed_by(obj)
            if tag is not None:
                return {
                    "$": "keyed",
                    "class": tag,
                    "keys": [[self.value(item) for item in k] for k in obj],
                    "values": [self.value(v) for v in obj.values()],
                }
            return {"$": "dict", "items": [[self.value(k), self.value(v)] for k, v in obj.items()]}
        if kind is tuple:
            return {"$": "tuple", "items": [self.value(item) for item in obj]}
        if kind is np.ndarray:
            return self._array(obj)
        if isinstance(obj, np.generic) and obj.dtype.kind in ARRAY_KINDS:
            return {"$": "scalar", "dtype": obj.dtype.str, "bits": obj.tobytes().hex()}
        tag = _TAG_OF.get((kind.__module__, kind.__qualname__))
        if tag is not None:
            return self._instance(tag, obj)
        if kind.__reduce__ is not object.__reduce__:  # a lazy value: what it pickles as
            reduced = obj.__reduce__()
            if isinstance(reduced, tuple) and callable(reduced[0]):
                value = reduced[0](*reduced[1])
                if type(value) is not kind:
                    return self.value(value)
        raise TypeError(
            f"a {kind.__module__}.{kind.__qualname__} cannot be written to the run cache "
            "(validation.run.cache_format.CLASSES lists what can)"
        )

    def _array(self, array: np.ndarray) -> dict:
        """The array's reference: dtype, shape, offset of its bytes (C order, or of its transpose for
        an array stored in Fortran order, ``"order": "F"``); the same array again, the same reference."""
        described = self._arrays.get(id(array))
        if described is not None:
            return described
        if array.dtype.kind not in ARRAY_KINDS:
            raise TypeError(f"an array of dtype {array.dtype} cannot be written to the run cache")
        fortran = array.ndim > 1 and array.flags.f_contiguous and not array.flags.c_contiguous
        padding = -self._size % ALIGN
        described = {"$": "array", "dtype": array.dtype.str, "shape": list(array.shape), "at": self._size + padding}
        if fortran:
            described["order"] = "F"
        raw = (array.T if fortran else array).tobytes()
        self._chunks += [bytes(padding), raw]
        self._size += padding + len(raw)
        self._arrays[id(array)] = described
        self._keep.append(array)
        return described

    def _instance(self, tag: str, obj: Any) -> dict:
        kind = CLASSES[tag][2]
        if kind == "enum":
            return {"$": tag, "v": self.value(obj.value)}
        if kind == "namedtuple":
            return {"$": tag, "v": [self.value(item) for item in obj]}
        ref = self._refs.get(id(obj))
        if ref is not None:
            return {"$": "ref", "ref": ref}
        ref = self._refs[id(obj)] = len(self._refs)
        self._keep.append(obj)
        return {"$": tag, "ref": ref, "f": {f.name: self.value(getattr(obj, f.name)) for f in dataclasses.fields(obj)}}


class _Reader:
    """``json.loads``'s object hook: a tagged object to its value (the JSON objects close inner
    first, in document order, so a dataclass is built before any reference to it)."""

    def __init__(self, packed: np.ndarray) -> None:
        self.packed = packed
        self.refs: dict[int, Any] = {}

    def tagged(self, obj: dict) -> Any:
        tag = obj.get("$")
        if tag is None:
            return obj
        if tag == "float":
            return struct.unpack("<d", bytes.fromhex(obj["bits"]))[0]
        if tag == "tuple":
            return tuple(obj["items"])
        if tag == "dict":
            return {_hashable(k): v for k, v in obj["items"]}
        if tag == "keyed":
            cls, keys, values = _class(_of(obj["class"], str), "namedtuple"), obj["keys"], obj["values"]
            if len(_of(keys, list)) != len(_of(values, list)):
                raise EntryError("a dict of more keys than values")
            return dict(zip(map(cls._make, keys), values))
        if tag == "array":
            return self._array(obj)
        if tag == "scalar":
            return np.frombuffer(bytes.fromhex(obj["bits"]), dtype=_dtype(obj["dtype"]))[0]
        if tag == "ref":
            return self.refs[_index(obj["ref"])]
        cls, kind = _class(tag), CLASSES[tag][2]
        if kind == "enum":
            return cls(obj["v"])
        if kind == "namedtuple":
            return cls._make(obj["v"])
        fields = obj["f"]
        names = [f.name for f in dataclasses.fields(cls)]
        if type(fields) is not dict or sorted(fields) != sorted(names):
            raise EntryError(f"a {tag} with other fields than this code's")
        instance = cls.__new__(cls)
        for name in names:
            object.__setattr__(instance, name, fields[name])
        self.refs[_index(obj["ref"])] = instance
        return instance

    def _array(self, described: dict) -> np.ndarray:
        """A view of the packed bytes (arrays that were one object share their bytes again)."""
        dtype, shape, at = _dtype(described["dtype"]), described["shape"], described["at"]
        if type(shape) is not list or not all(type(n) is int and n >= 0 for n in shape):
            raise EntryError(f"an array of shape {shape!r}")
        size = math.prod(shape) * dtype.itemsize
        if type(at) is not int or at < 0 or at % ALIGN or at + size > self.packed.size:
            raise EntryError("an array outside the entry's data")
        flat = self.packed[at : at + size].view(dtype)
        if described.get("order") == "F":
            return flat.reshape(shape[::-1]).T
        return flat.reshape(shape)


def _of(value: Any, kind: type) -> Any:
    if type(value) is not kind:
        raise EntryError(f"a {type(value).__name__} where the format has a {kind.__name__}")
    return value


def _index(value: Any) -> int:
    if type(value) is not int or value < 0:
        raise EntryError("a reference that is not an index")
    return value


def _hashable(key: Any) -> Any:
    if isinstance(key, (list, dict)):
        raise EntryError("a dict key that cannot be one")
    return key


def _keyed_by(mapping: dict) -> str | None:
    """The tag of the named tuple class all of a dict's keys are instances of (a run's values are
    keyed by `Request`), or None."""
    kind = type(next(iter(mapping), None))
    tag = _TAG_OF.get((kind.__module__, kind.__qualname__))
    if tag is None or CLASSES[tag][2] != "namedtuple" or not all(type(k) is kind for k in mapping):
        return None
    return tag


@lru_cache(maxsize=None)
def _dtype(name: Any) -> np.dtype:
    """The dtype a stored name says, if the format writes it (a bool, integer, float or complex)."""
    dtype = np.dtype(_of(name, str))
    if dtype.kind not in ARRAY_KINDS:
        raise EntryError(f"data of dtype {dtype}")
    return dtype


@lru_cache(maxsize=None)
def _class(tag: Any, kind: str | None = None) -> Any:
    """The class of ``CLASSES[tag]`` (of that ``kind`` when given), imported at first use (typed Any: an
    enum, a namedtuple or a dataclass, which kind checked here at run time)."""
    if tag not in CLASSES or kind not in (None, CLASSES[tag][2]):
        raise EntryError(f"an object of tag {tag!r}" + (f" where a {kind} belongs" if kind else ""))
    module, name, kind = CLASSES[tag]
    cls = getattr(importlib.import_module(module), name)
    expected = {
        "enum": lambda c: issubclass(c, Enum),
        "namedtuple": lambda c: issubclass(c, tuple),
        "dataclass": dataclasses.is_dataclass,
    }[kind]
    if not isinstance(cls, type) or not expected(cls):
        raise TypeError(f"{module}.{name} is not a {kind}")
    return cls
