"""The examples in examples/python/ run (matplotlib and SurfaceTopography
installed) and say what they promise."""

import os
import subprocess
import sys

import pytest

pytest.importorskip("matplotlib")
pytest.importorskip("SurfaceTopography")


def run(repo, *args):
    env = dict(os.environ, VISCOSLIDE_BACKEND="cpu")
    out = subprocess.run([sys.executable, *args], cwd=repo, env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_friction_speed_curve(repo, tmp_path):
    out = run(repo, "examples/python/friction_speed.py", str(tmp_path / "curve.png"))
    assert "friction peak" in out
    assert (tmp_path / "curve.png").stat().st_size > 10_000


def test_measured_topography(repo, cli, tmp_path, pad):
    import numpy as np

    np.save(tmp_path / "scan.npy", pad.heights)
    cli("surface", "convert", str(tmp_path / "scan.npy"), str(tmp_path / "scan.x3p"), "--length", "0.01")
    out = run(repo, "examples/python/measured_topography.py", str(tmp_path / "scan.x3p"), str(tmp_path / "solve"))
    assert "Result(64 x 64" in out and "contact spots" in out
    assert (tmp_path / "solve" / "summary.json").exists()
