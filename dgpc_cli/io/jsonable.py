"""JSON values: conversion from numpy, reading, and JSON Schema validation with one-line errors."""

from __future__ import annotations

import json
import math
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from jsonschema import Draft202012Validator
from jsonschema.exceptions import relevance

from ..errors import DgpcError

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


def read_json(path: str | Path) -> Any:
    """Parsed content of a JSON file; DgpcError naming the file if it is missing or not JSON."""
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise DgpcError("no such file", source=path) from None
    except IsADirectoryError:
        raise DgpcError("is a directory, expected a JSON file", source=path) from None
    except UnicodeDecodeError:
        raise DgpcError("not a JSON file (not UTF-8 text)", source=path) from None
    except OSError as e:
        raise DgpcError(f"cannot read: {e.strerror or e}", source=path) from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise DgpcError(f"not valid JSON: {e.msg} at line {e.lineno}, column {e.colno}",
                        source=path) from None


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
