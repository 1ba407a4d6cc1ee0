"""The pipelines' inputs in samples/ are what samples/generate.py makes, byte for byte."""

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_committed_samples_are_the_generators_output():
    r = subprocess.run([sys.executable, str(ROOT / "samples" / "generate.py"), "--check"],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr


def test_check_names_an_edited_sample(tmp_path, capsys):
    shutil.copytree(ROOT / "samples", tmp_path / "samples")
    spec = importlib.util.spec_from_file_location("generate", ROOT / "samples" / "generate.py")
    generate = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generate)
    generate.ROOT, generate.HERE = tmp_path, tmp_path / "samples"
    felt = tmp_path / "samples" / "meshes" / "felt.obj"
    felt.write_bytes(felt.read_bytes().replace(b"v ", b"v  ", 1))
    before = felt.read_bytes()
    assert generate.main(["--check"]) == 1
    assert "differs: samples/meshes/felt.obj" in capsys.readouterr().err
    assert felt.read_bytes() == before                      # --check writes nothing
    assert generate.main([]) == 0 and generate.main(["--check"]) == 0


def _generator():
    spec = importlib.util.spec_from_file_location("generate", ROOT / "samples" / "generate.py")
    generate = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generate)
    return generate


def test_last_bit_differences_of_the_math_kernels_are_the_same_output():
    """numpy's exp/sin/cos kernels differ by CPU in the last bit; a file written on another
    machine is still the generator's output, a changed digit or format is not."""
    same = _generator().same_up_to_rounding
    old = b"v 1.3413849329964761e-07 0.4 1.960696920032581e-07\nf 1 2 3\n"
    assert same(old, b"v 1.3413849329964764e-07 0.4 1.9606969200325811e-07\nf 1 2 3\n")
    assert not same(old, b"v 1.3413849329964761e-07 0.4000001 1.960696920032581e-07\nf 1 2 3\n")
    assert not same(old, b"v 1.3413849329964761e-07 0.4 1.960696920032581e-07\nf 1 2 4\n")
    assert not same(old, old.replace(b"v ", b"v  "))
    assert not same(old, old + b"f 1 3 4\n")
