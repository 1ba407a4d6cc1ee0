"""JSON values: conversion from numpy, reading, and JSON Schema validation with one-line errors."""

from __future__ import annotations

import json
import math
import sys
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from jsonschema import Draft202012Validator
from jsonschema.exceptions import relevance

from ..errors import DgpcError
from .bounded_read import read_regular

_JSON_TYPES = {dict: "object", list: "array", str: "string", bool: "boolean",
               int: "integer", float: "number", type(None): "null"}


def to_jsonable(obj: Any) -> Any:
    """Plain JSON value of ``obj``: numpy scalars/arrays → Python numbers/lists, tuples → lists,
    paths → POSIX strings, non-finite floats → ``None``. Dict keys become strings."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return to_jsonable(obj.item())
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Path):
        return obj.as_posix()
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    raise TypeError(f"not JSON serializable: {type(obj).__name__}")


#: Deepest nesting of arrays and objects a JSON file read here may have (an artifact needs
#: fewer than 10); deeper is refused before anything walks it recursively.
MAX_DEPTH = 64


def dotted(doc: Any, path: str) -> Any:
    """The value at the dotted ``path`` (``"status.state"``) of nested dicts ``doc``, or None
    where a key is missing or a step is not a dict."""
    for key in path.split("."):
        if not isinstance(doc, dict) or key not in doc:
            return None
        doc = doc[key]
    return doc


def nesting_depth(doc: Any) -> int:
    """How deeply arrays and objects nest in ``doc`` (0 for a number), without recursion."""
    deepest, stack = 0, [(doc, 1)]
    while stack:
        value, depth = stack.pop()
        if isinstance(value, (dict, list)):
            deepest = max(deepest, depth)
            items = value.values() if isinstance(value, dict) else value
            stack.extend((v, depth + 1) for v in items if isinstance(v, (dict, list)))
    return deepest


def read_json(path: str | Path) -> Any:
    """Parsed content of a JSON file; DgpcError naming the file if it is missing or not JSON."""
    path = Path(path)
    try:
        text = read_regular(path, "a JSON file").decode("utf-8")
    except UnicodeDecodeError:
        raise DgpcError("not a JSON file (not UTF-8 text)", source=path) from None
    numbers = _NumberCheck()
    try:
        doc = json.loads(text, parse_float=numbers.float, parse_int=numbers.int,
                         parse_constant=numbers.constant)
    except RecursionError:
        raise DgpcError(f"not valid JSON here: nested more than {MAX_DEPTH} levels deep",
                        source=path) from None
    except json.JSONDecodeError as e:
        raise DgpcError(f"not valid JSON: {e.msg} at line {e.lineno}, column {e.colno}",
                        source=path) from None
    except ValueError as e:  # an integer of more digits than Python converts
        raise DgpcError(f"not valid JSON: {e}", source=path) from None
    if nesting_depth(doc) > MAX_DEPTH:
        raise DgpcError(f"not valid JSON here: nested more than {MAX_DEPTH} levels deep",
                        source=path)
    if numbers.bad:
        where, what = first_non_finite(doc)
        raise DgpcError(f"{where}: non-finite number ({what})", source=path)
    return doc


class _NumberCheck:
    """Hooks of ``json.loads`` that note a non-finite number: the constants ``NaN``,
    ``Infinity`` and ``-Infinity`` that Python's json accepts, and numbers beyond the float
    range (``1e999`` parses to inf), so that :func:`read_json` can name the field."""

    def __init__(self):
        self.bad = False

    def float(self, text: str) -> float:
        value = float(text)
        if not math.isfinite(value):
            self.bad = True
        return value

    def int(self, text: str) -> int:
        value = int(text)
        if abs(value) > _FLOAT_MAX:
            self.bad = True
        return value

    def constant(self, text: str) -> float:
        self.bad = True
        return float(text)


_FLOAT_MAX = sys.float_info.max


def _non_finite(value: Any) -> bool:
    if isinstance(value, float):
        return not math.isfinite(value)
    return isinstance(value, int) and not isinstance(value, bool) and abs(value) > _FLOAT_MAX


def first_non_finite(doc: Any) -> tuple[str, str] | None:
    """``(field, what)`` of the first number in ``doc`` (document order) that is not a finite
    float: ``what`` is ``"NaN"``, ``"inf"``, ``"-inf"`` or ``"an integer beyond the float
    range"``; None when every number is finite."""
    stack: list[tuple[tuple, Any]] = [((), doc)]
    while stack:
        parts, value = stack.pop()
        if isinstance(value, dict):
            stack.extend(((*parts, k), v) for k, v in reversed(list(value.items())))
        elif isinstance(value, list):
            stack.extend(((*parts, i), v) for i, v in reversed(list(enumerate(value))))
        elif _non_finite(value):
            what = ("NaN" if math.isnan(value) else repr(value)) if isinstance(value, float) \
                else "an integer beyond the float range"
            return field_path(parts), what
    return None


def schema_exists(name: str) -> bool:
    """Whether ``io/schemas/<name>.schema.json`` ships in the package."""
    return resources.files(__package__).joinpath("schemas", f"{name}.schema.json").is_file()


@cache
def load_schema(name: str) -> dict:
    """The shipped JSON Schema ``io/schemas/<name>.schema.json``."""
    text = resources.files(__package__).joinpath("schemas", f"{name}.schema.json").read_text(
        encoding="utf-8")
    schema = json.loads(text)
    Draft202012Validator.check_schema(schema)
    return schema


def field_path(parts) -> str:
    """Dotted path of a JSON location: ``("handles", 2, "index")`` → ``handles[2].index``."""
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(top level)"


def _short(value: Any, limit: int = 60) -> str:
    text = json.dumps(value, ensure_ascii=False, default=str) if not isinstance(value, str) \
        else repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _describe(error) -> tuple[str, str]:
    """(field, reason) of one jsonschema ValidationError."""
    parts, v, inst = list(error.absolute_path), error.validator, error.instance
    custom = (error.schema.get("errorMessage") or {}).get(v) if isinstance(error.schema, dict) \
        else None
    if v == "required":
        missing = [k for k in error.validator_value if k not in inst]
        return field_path(parts + missing[:1]), "missing required field"
    if v == "additionalProperties":
        extra = sorted(k for k in inst if k not in error.schema.get("properties", {}))
        return field_path(parts + extra[:1]), "unknown field"
    if custom:
        return field_path(parts), custom
    if v == "type":
        expected = error.validator_value
        expected = " or ".join(expected) if isinstance(expected, list) else expected
        got = _JSON_TYPES.get(type(inst), type(inst).__name__)
        return field_path(parts), f"must be of type {expected}, got {got} {_short(inst)}"
    if v == "const":
        return field_path(parts), f"must be {_short(error.validator_value)}, got {_short(inst)}"
    if v == "enum":
        allowed = _short(error.validator_value)
        return field_path(parts), f"must be one of {allowed}, got {_short(inst)}"
    if v in ("minItems", "maxItems"):
        word = "at least" if v == "minItems" else "at most"
        return field_path(parts), f"must have {word} {error.validator_value} items, got {len(inst)}"
    if v in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        op = {"minimum": "≥", "maximum": "≤", "exclusiveMinimum": ">", "exclusiveMaximum": "<"}[v]
        return field_path(parts), f"must be {op} {error.validator_value}, got {_short(inst)}"
    return field_path(parts), error.message if len(error.message) <= 120 \
        else error.message[:119] + "…"


def validate(doc: Any, schema: dict, source: str | Path) -> None:
    """Check ``doc`` against a JSON Schema; DgpcError ``"SOURCE: field: reason"`` on the most
    relevant violation (shallowest first), where field is a path like ``data.shape[1]``."""
    errors = list(Draft202012Validator(schema).iter_errors(doc))
    if errors:
        field, reason = _describe(max(errors, key=relevance))
        raise DgpcError(f"{field}: {reason}", source=source)
