"""The strips and flat artifacts: shipped JSON Schemas (valid and invalid cases), reading
checks, inspect."""

import copy
import json

import pytest
from cli_helpers import dgpc, metrics

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.flat import read_flat
from dgpc_cli.io.jsonable import load_schema, validate


@pytest.fixture(scope="module")
def artifacts(tmp_path_factory):
    d = tmp_path_factory.mktemp("art")
    dgpc("init", "--surface", "revolution", "--profile", "sphere-zone", "--rows", 6, "--cols",
         5, "-o", d / "n")
    dgpc("planarize-strips", d / "n", "-o", d / "s")
    dgpc("unfold", d / "s", "-o", d / "f")
    return d


def _doc(d, stem):
    return json.loads((d / f"{stem}.json").read_text())


def _edited(doc, path, value):
    """A deep copy of ``doc`` with the item at ``path`` (keys and indices) set to ``value``."""
    doc = copy.deepcopy(doc)
    target = doc
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return doc


@pytest.mark.parametrize("kind, stem", [("strips", "s"), ("flat", "f")])
def test_written_artifacts_are_valid(artifacts, kind, stem):
    validate(_doc(artifacts, stem), load_schema(kind), "x")


@pytest.mark.parametrize("path, value, message", [
    (("kind",), "net", "kind"),
    (("data", "strips", 0, "id"), "strip-7", "data.strips[0].id"),
    (("data", "strips", 0, "planarity"), -1.0, "data.strips[0].planarity"),
    (("data", "strips", 0, "ruling_directions", 0), [1.0, 0.0], "ruling_directions[0]"),
    (("data", "source_shape"), [5], "data.source_shape"),
])
def test_invalid_strips_documents(artifacts, path, value, message):
    doc = _edited(_doc(artifacts, "s"), path, value)
    with pytest.raises(DgpcError, match=message.replace("[", r"\[").replace("]", r"\]")):
        validate(doc, load_schema("strips"), "x")


@pytest.mark.parametrize("path, value, message", [
    (("data", "parts", 0, "outline"), [[0, 0], [1, 0]], "outline"),
    (("data", "parts", 0, "label"), [0, 0, 0], "label"),
    (("data", "parts", 0, "class"), "K1", "class"),
    (("data", "parts", 0, "area"), -2.0, "area"),
    (("data", "parts", 0, "alignment", "relabel"), "flipped", "relabel"),
    (("data", "classes", 0, "quantity"), 0, "quantity"),
    (("data", "classes"), [], "data.classes"),
    (("data", "parts", 0, "id"), "S-v00.0", "data.parts[0].id: must be a part id"),
    (("data", "parts", 0, "rows"), [0, 2.5], "rows"),
    (("data", "joints"), [{"strip": "S-v00", "row": 0, "position": 1.0,
                           "parts": ["S-v00.1", "S-v00.2"]}], "data.joints[0].row"),
    (("data", "units"), "yd", "data.units: must be a length unit"),
])
def test_invalid_flat_documents(artifacts, path, value, message):
    doc = _edited(_doc(artifacts, "f"), path, value)
    with pytest.raises(DgpcError, match=message.replace("[", r"\[").replace("]", r"\]")):
        validate(doc, load_schema("flat"), "x")


def test_flat_reading_checks_classes_against_parts(artifacts, tmp_path):
    doc = _doc(artifacts, "f")
    doc["data"]["classes"][0]["quantity"] += 1
    (tmp_path / "f.json").write_text(json.dumps(doc))
    for path in artifacts.glob("f.*"):
        if path.name != "f.json":
            (tmp_path / path.name).write_bytes(path.read_bytes())
    with pytest.raises(DgpcError, match="quantity"):
        read_flat(tmp_path / "f")


def test_flat_carries_what_nest_needs(artifacts):
    flat = read_flat(artifacts / "f")
    assert [p["id"] for p in flat.parts] == ["S-v00", "S-v01", "S-v02", "S-v03"]
    cls = flat.classes[0]
    assert cls["quantity"] == 4 and cls["representative"] == "S-v00"
    for part in flat.parts:
        assert part["class"] == cls["id"]
        assert len(part["outline"]) == 12 and part["area"] > 0     # 2m points, ccw
        assert len(part["score"]) == 4 and all(len(s) == 2 for s in part["score"])
        assert part["alignment"]["relative_error"] <= 1e-9


def test_inspect_strips_and_flat(artifacts):
    ms = metrics(artifacts / "s")
    assert ms["n_strips"] == 4 and set(ms["per_strip"]) == {"S-v00", "S-v01", "S-v02", "S-v03"}
    mf = metrics(artifacts / "f")
    assert mf["n_classes"] == 1 and mf["classes"]["C01"]["quantity"] == 4
