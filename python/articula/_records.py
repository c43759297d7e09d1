"""Records: what the host library reports (`articula predict --json`, `run --json`, `quantize
--json`, simulation events), with the same field names as the command line's JSON, read as
attributes (``rec.steps``) or as a dict (``rec["steps"]``, ``rec.to_dict()``)."""

from __future__ import annotations

from typing import Any, Iterator


class Record:
    """A JSON object of the host library with attribute access. Nested objects and lists of
    objects are Records too."""

    __slots__ = ("_fields",)

    def __init__(self, fields: dict[str, Any]):
        object.__setattr__(self, "_fields", {k: _wrap(v) for k, v in fields.items()})

    def __getattr__(self, name: str) -> Any:
        try:
            return self._fields[name]
        except KeyError:
            raise AttributeError(f"no field '{name}' (fields: {', '.join(self._fields)})") from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("records are read-only")

    def __getitem__(self, name: str) -> Any:
        return self._fields[name]

    def __contains__(self, name: str) -> bool:
        return name in self._fields

    def __iter__(self) -> Iterator[str]:
        return iter(self._fields)

    def __dir__(self) -> list[str]:
        return list(self._fields)

    def get(self, name: str, default: Any = None) -> Any:
        return self._fields.get(name, default)

    def keys(self):
        return self._fields.keys()

    def to_dict(self) -> dict[str, Any]:
        """The plain JSON value, as the command line prints it."""
        return {k: _unwrap(v) for k, v in self._fields.items()}

    def column(self, field: str, records: str = "records"):
        """One field of every record as a numpy array: ``prediction.column("steps")`` is an
        (N, motors) array, ``prediction.column("error_mm")`` an (N,) one."""
        import numpy as np

        return np.array([r[field] for r in self._fields[records]], dtype=float)

    def __repr__(self) -> str:
        head = ", ".join(f"{k}={_short(v)}" for k, v in list(self._fields.items())[:6])
        more = ", ..." if len(self._fields) > 6 else ""
        return f"Record({head}{more})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Record) and self.to_dict() == other.to_dict()


def _wrap(v: Any) -> Any:
    if isinstance(v, dict):
        return Record(v)
    if isinstance(v, list) and v and isinstance(v[0], dict):
        return [_wrap(e) for e in v]
    return v


def _unwrap(v: Any) -> Any:
    if isinstance(v, Record):
        return v.to_dict()
    if isinstance(v, list):
        return [_unwrap(e) for e in v]
    return v


def _short(v: Any) -> str:
    if isinstance(v, list):
        return f"[{len(v)} items]" if len(v) > 4 else repr(v)
    if isinstance(v, Record):
        return "Record(...)"
    return repr(v)
