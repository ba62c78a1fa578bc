"""Shared fixtures: the repository, the command-line binary (for parity
tests), the paper's material and small surfaces."""

import os
import pathlib
import shutil
import subprocess

import pytest

import viscoslide as vs

REPO = pathlib.Path(__file__).resolve().parents[2]

# Solves whose test names no backend run on the CPU (a GPU adapter emulated
# on the CPU would only be slower), as in the Rust test suite.
os.environ.setdefault("VISCOSLIDE_BACKEND", "cpu")


@pytest.fixture(scope="session")
def repo() -> pathlib.Path:
    return REPO


@pytest.fixture(scope="session")
def cli():
    """Run the ``viscoslide`` binary (VISCOSLIDE_CLI, else
    target/release/viscoslide) on the CPU; skips when it is not built."""
    path = os.environ.get("VISCOSLIDE_CLI") or str(REPO / "target" / "release" / "viscoslide")
    if not os.path.exists(path) and shutil.which("viscoslide") is None:
        pytest.skip("the viscoslide binary is not built (cargo build --release)")
    if not os.path.exists(path):
        path = shutil.which("viscoslide")

    def run(*args: str) -> str:
        env = dict(os.environ, VISCOSLIDE_BACKEND="cpu")
        out = subprocess.run([path, *args], cwd=REPO, env=env, capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        return out.stdout

    return run


@pytest.fixture(scope="session")
def rubber() -> vs.Material:
    """The paper's single-relaxation material (E_inf = 10 MPa, E_inf/E0 = 3, tau = 10 ms)."""
    return vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01)


@pytest.fixture(scope="session")
def pad() -> vs.Surface:
    """A 64 x 64 self-affine pad of side 1 cm."""
    return vs.Surface.self_affine(64, 0.01, 0.8, scales=8, rms_slope=0.02, rolloff_q0=5026.548, seed=1)
