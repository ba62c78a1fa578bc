"""Non-square pixels: a SurfaceTopography topography whose pixels are
rectangular solves on its own grid (Love's rectangle, physics.md
section 11), with the cell sides in the summary."""

import numpy as np
import pytest

import viscoslide as vs

SurfaceTopography = pytest.importorskip("SurfaceTopography")


def _scan(nx, ny, lx, ly, seed=3):
    """A smooth band-limited surface on (0, lx) x (0, ly), sampled at the
    pixel centres (rms slope about 0.02)."""
    rng = np.random.default_rng(seed)
    x = (np.arange(nx) + 0.5) * lx / nx
    y = (np.arange(ny) + 0.5) * ly / ny
    h = np.zeros((nx, ny))
    for kx in range(-3, 4):
        for ky in range(0, 4):
            if (ky == 0 and kx <= 0) or kx * kx + ky * ky > 9:
                continue
            amp = (kx * kx + ky * ky) ** -0.9
            phase = rng.uniform(0, 2 * np.pi)
            h += amp * np.cos(2 * np.pi * (kx * x[:, None] / lx + ky * y[None, :] / ly) + phase)
    return h * 0.02 / np.sqrt(np.mean(np.gradient(h, lx / nx, axis=0) ** 2 + np.gradient(h, ly / ny, axis=1) ** 2))


def test_non_square_pixels_solve_on_their_own_grid(rubber):
    nx, ny, lx, ly = 48, 24, 0.01, 0.0125
    h = _scan(nx, ny, lx, ly)
    topo = SurfaceTopography.Topography(h, physical_sizes=(lx, ly))
    s = vs.Surface.coerce(topo)
    assert s.shape == (nx, ny)
    assert s.cell_sizes == pytest.approx((lx / nx, ly / ny), rel=1e-12)
    r = vs.solve(topo, rubber, speed=0.0117, mean_pressure=3e3, backend="cpu", tolerance=1e-10)
    assert r.summary["cell_size"] == pytest.approx(lx / nx, rel=1e-12)
    assert r.summary["cell_size_y"] == pytest.approx(ly / ny, rel=1e-12)
    assert r.summary["length"] == pytest.approx([lx, ly], rel=1e-12)
    assert 0.0 < r.summary["contact_area_fraction"] < 0.5
    # The same map turned a quarter (x -> y) and slid along +y is the same
    # problem: its pressure is the transpose, to the solver's tolerance.
    turned = SurfaceTopography.Topography(np.ascontiguousarray(h.T), physical_sizes=(ly, lx))
    t = vs.solve(turned, rubber, speed=0.0117, mean_pressure=3e3, direction_deg=90.0, backend="cpu", tolerance=1e-10)
    assert t.summary["cell_size"] == pytest.approx(ly / ny, rel=1e-12)
    p, q = r.pressure, t.pressure.T
    assert np.linalg.norm(p - q) <= 1e-7 * np.linalg.norm(p)
    assert t.summary["friction_coefficient"] == pytest.approx(r.summary["friction_coefficient"], rel=1e-6)


def test_from_array_takes_length_y(rubber):
    h = _scan(32, 16, 0.01, 0.02)
    s = vs.Surface.from_array(h, 0.01, length_y=0.02)
    assert s.cell_sizes == pytest.approx((0.01 / 32, 0.02 / 16), rel=1e-12)
    assert s.physical_sizes == pytest.approx((0.01, 0.02), rel=1e-12)


def test_extreme_aspect_ratio_warns(rubber):
    nx, ny, lx, ly = 64, 8, 0.01, 0.01
    h = _scan(nx, ny, lx, ly)
    r = vs.solve(vs.Surface.from_array(h, lx, length_y=ly), rubber, speed=0.0117, mean_pressure=3e3, backend="cpu")
    assert any("aspect ratio" in w for w in r.summary["warnings"])
