"""The ``net`` artifact: STEM.json (envelope) + STEM.obj (the m×n net as quads), SPEC §3."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DgpcError
from .artifact import (
    artifact_files,
    artifact_paths,
    listed_file,
    load_envelope,
    read_listed,
    reread,
)
from .atomic import write_files
from .coordinates import bad_rows, coordinate_problem
from .obj import check_net_faces, format_net_obj, parse_net_obj
from .units import DEFAULT_UNITS, stored, to_mm

KIND = "net"


@dataclass
class NetArtifact:
    """A net ``f (m, n, 3)`` in the length unit ``units`` with the envelope fields of its
    artifact (SPEC §3).

    ``data`` holds what the OBJ cannot (``shape``, ``geodesic_family``, ``units``, ``obj``,
    ``obj_sha256`` are filled in by :func:`write_net`; callers add e.g. ``surface``,
    ``handles``, ``reference``).
    """

    f: np.ndarray
    units: str = DEFAULT_UNITS
    parameters: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    data: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    status: dict = field(default_factory=dict)

    @property
    def shape(self) -> tuple[int, int]:
        """Grid size ``(m, n)``."""
        return int(self.f.shape[0]), int(self.f.shape[1])

    @property
    def f_mm(self) -> np.ndarray:
        """The net in millimetres, where the stages compute (:mod:`dgpc_cli.io.units`)."""
        return to_mm(self.f, self.units)

    @property
    def reference_pieces(self) -> str:
        """Which pieces of its reference mesh the net is fitted to and measured against:
        ``"largest"`` when made with ``init --largest-component``, else ``"all"``."""
        return "largest" if self.parameters.get("largest_component") else "all"

    @property
    def extend(self) -> float:
        """How far (fraction of the reference's diagonal) the net may run past its reference
        (``init --extend``); 0 for a net kept on it."""
        return float(self.parameters.get("extend", 0.0))

    def reference_parameters(self) -> dict:
        """The parameters above that a stage passes on to the nets it writes."""
        return {**({"largest_component": True} if self.reference_pieces == "largest" else {}),
                **({"extend": self.extend} if self.extend else {})}


def check_net_array(f, source) -> np.ndarray:
    """``f`` as a float64 ``(m, n, 3)`` array with m, n ≥ 2 and finite; DgpcError otherwise."""
    f = np.asarray(f, dtype=np.float64)
    if f.ndim != 3 or f.shape[2] != 3 or f.shape[0] < 2 or f.shape[1] < 2:
        raise DgpcError(f"f: a net is an (m, n, 3) array with m, n >= 2, got shape "
                        f"{tuple(f.shape)}", source=source)
    bad = bad_rows(f.reshape(-1, 3))
    if bad.size:
        u, v = divmod(int(bad[0]), f.shape[1])
        raise DgpcError(f"f: vertex (u, v) = ({u}, {v}) has {coordinate_problem(f[u, v])}",
                        source=source)
    return f


def net_files(stem: str | Path, net: NetArtifact) -> dict[Path, bytes]:
    """The bytes of ``STEM.json`` and ``STEM.obj`` (nothing written), checked against
    ``net.schema.json``; to be written with other files in one :func:`write_files` call."""
    json_path, _ = artifact_paths(stem)
    f = stored(check_net_array(net.f, json_path), net.units)
    m, n = f.shape[:2]
    data = {**net.data, "shape": [m, n], "geodesic_family": "u", "units": net.units}
    return artifact_files(KIND, stem, format_net_obj(f), data, inputs=net.inputs,
                          parameters=net.parameters, metrics=net.metrics, status=net.status)


def write_net(stem: str | Path, net: NetArtifact, *, force: bool = False) -> tuple[Path, Path]:
    """Write ``STEM.json`` + ``STEM.obj`` atomically; returns their paths.

    The envelope is checked against ``net.schema.json`` before anything is written.
    """
    files = net_files(stem, net)
    write_files(files, force=force)
    json_path, obj_path = files
    return json_path, obj_path


def net_shape(data: dict, json_path: str | Path) -> tuple[int, int]:
    """``(m, n)`` of a net's ``data.shape``: whole numbers written as such (JSON Schema takes
    ``9.0`` for an integer; numpy does not); DgpcError naming the JSON otherwise."""
    shape = data.get("shape")
    if not (isinstance(shape, list) and len(shape) == 2
            and all(isinstance(k, int) and not isinstance(k, bool) for k in shape)):
        raise DgpcError(f"data.shape: {shape!r} is not two whole numbers [m, n]",
                        source=json_path)
    return shape[0], shape[1]


@reread
def read_net(stem: str | Path) -> NetArtifact:
    """Read and validate a net artifact (envelope, OBJ hash, vertex count, finiteness)."""
    json_path, _ = artifact_paths(stem)
    doc = load_envelope(json_path, KIND)
    data = doc["data"]
    m, n = net_shape(data, json_path)
    obj_path = listed_file(data["obj"], json_path, "data.obj")
    obj_bytes = read_listed(obj_path, data["obj_sha256"], json_path, "data.obj_sha256")
    f = parse_net_obj(obj_bytes, m, n, obj_path)
    check_net_faces(obj_bytes, m, n, obj_path)
    return NetArtifact(f=f, units=data["units"], parameters=doc["parameters"],
                       inputs=doc["inputs"], data=data, metrics=doc["metrics"],
                       status=doc["status"])
