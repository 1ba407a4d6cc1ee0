"""Reading and writing: artifacts (JSON + OBJ), reference meshes, handles files (SPEC §3).

Reference meshes live in :mod:`dgpc_cli.io.mesh` (imports trimesh, so not re-exported here).
"""

from .artifact import (
    artifact_paths,
    dumps_json,
    file_input,
    load_envelope,
    make_envelope,
    sha256_bytes,
    sha256_file,
)
from .atomic import write_files
from .handles import read_handles
from .net import NetArtifact, read_net, write_net

__all__ = [
    "NetArtifact",
    "artifact_paths",
    "dumps_json",
    "file_input",
    "load_envelope",
    "make_envelope",
    "read_handles",
    "read_net",
    "sha256_bytes",
    "sha256_file",
    "write_files",
    "write_net",
]
