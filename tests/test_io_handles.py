"""Handles files: targets and offsets, and one-line errors naming the entry."""

import json

import numpy as np
import pytest

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.handles import read_handles

M, N = 3, 4
F = np.arange(M * N * 3, dtype=float).reshape(M, N, 3)


def write(tmp_path, doc, raw=None):
    path = tmp_path / "handles.json"
    path.write_text(raw if raw is not None else json.dumps(doc))
    return path


def test_targets_and_offsets(tmp_path):
    path = write(tmp_path, {"handles": [
        {"index": [2, 3], "target": [1.0, 2.0, 3.5]},
        {"index": [0, 1], "offset": [0.0, 0.0, -1.0]},
    ]})
    ids, targets = read_handles(path, (M, N), F)
    assert ids.dtype == np.int64 and ids.tolist() == [2 * N + 3, 1]
    assert targets.shape == (2, 3)
    assert targets[0].tolist() == [1.0, 2.0, 3.5]
    assert targets[1].tolist() == (F[0, 1] + [0.0, 0.0, -1.0]).tolist()


@pytest.mark.parametrize("handles, message", [
    ([], "handles: must have at least 1 items, got 0"),
    ([{"index": [0, 0]}], r"handles\[0\]: give exactly one of 'target' or 'offset'"),
    ([{"index": [0, 0], "target": [0, 0, 0], "offset": [0, 0, 0]}],
     r"handles\[0\]: give exactly one of 'target' or 'offset'"),
    ([{"index": [0, 0], "target": [0, 0, 0]}, {"index": [0, 1], "target": [0, 0]}],
     r"handles\[1\]\.target: must have at least 3 items"),
    ([{"index": [0], "target": [0, 0, 0]}], r"handles\[0\]\.index: must have at least 2 items"),
    ([{"index": [0, -1], "target": [0, 0, 0]}], r"handles\[0\]\.index\[1\]: must be ≥ 0"),
    ([{"index": [0, 1.5], "target": [0, 0, 0]}],
     r"handles\[0\]\.index\[1\]: must be of type integer"),
    ([{"index": [0, 0], "target": [0, "a", 0]}],
     r"handles\[0\]\.target\[1\]: must be of type number"),
    ([{"target": [0, 0, 0]}], r"handles\[0\]\.index: missing required field"),
    ([{"index": [0, 0], "target": [0, 0, 0], "weight": 2}],
     r"handles\[0\]\.weight: unknown field"),
    ([{"index": [0, 0], "target": [0, 0, 0]}, {"index": [0, 1], "target": [0, 0, 0]},
      {"index": [3, 1], "target": [0, 0, 0]}],
     r"handles\[2\]\.index: \(3, 1\) is outside the 3 x 4 grid"),
    ([{"index": [0, 4], "offset": [0, 0, 0]}], r"handles\[0\]\.index: \(0, 4\) is outside"),
    ([{"index": [1, 1], "target": [0, 0, 0]}, {"index": [1, 1], "offset": [1, 0, 0]}],
     r"handles\[1\]\.index: vertex \(1, 1\) is already a handle in handles\[0\]"),
])
def test_invalid(tmp_path, handles, message):
    path = write(tmp_path, {"handles": handles})
    with pytest.raises(DgpcError, match=message) as err:
        read_handles(path, (M, N), F)
    assert str(err.value).startswith(f"{path}: ") and "\n" not in str(err.value)


@pytest.mark.parametrize("raw, message", [
    ('{"handles": [{"index": [0, 0], "target": [0, NaN, 0]}]}',
     r"handles\[0\]\.target\[1\]: non-finite number \(NaN\)"),
    ('{"handles": [{"index": [0, 0], "offset": [1e999, 0, 0]}]}',
     r"handles\[0\]\.offset\[0\]: non-finite number \(inf\)"),
    ('{"handles": [', "not valid JSON"),
    ('[]', r"\(top level\): must be of type object, got array"),
    ('{"handle": []}', "handles: missing required field"),
])
def test_invalid_raw(tmp_path, raw, message):
    path = write(tmp_path, None, raw=raw)
    with pytest.raises(DgpcError, match=message) as err:
        read_handles(path, (M, N), F)
    assert err.value.source == str(path)


def test_missing_file(tmp_path):
    with pytest.raises(DgpcError, match="no such file"):
        read_handles(tmp_path / "nope.json", (M, N), F)


def test_offset_from_non_finite_vertex(tmp_path):
    f = F.copy()
    f[1, 2, 0] = np.nan
    path = write(tmp_path, {"handles": [{"index": [1, 2], "offset": [0, 0, 1]}]})
    with pytest.raises(DgpcError, match=r"handles\[0\]\.offset"):
        read_handles(path, (M, N), f)
