"""vs.surface_temperature: the steady surface temperature rise under a
surface heat flux map (physics.md section 14), its orientation, the
periodic cell against ``q / (lam m)`` and the block's background, and
argument errors that name the argument."""

import math
import warnings

import numpy as np
import pytest

import viscoslide as vs

LAM, KAPPA = 0.25, 1e-7


def test_a_periodic_mode_is_q_over_lambda_m():
    # One surface mode on rectangular cells, sliding at 30 degrees: the
    # rise is Re[q(k) / (lam m)], m^2 = |k|^2 - i v (k.e_v) / kappa, to
    # 1e-9 of the largest (the transforms' round-off is ~1e-15).
    nx, ny, dx, dy, v, deg = 32, 24, 2e-6, 3e-6, 0.4, 30.0
    x = (np.arange(nx) + 0.5)[:, None] * dx
    y = (np.arange(ny) + 0.5)[None, :] * dy
    k = (2 * math.pi * 3 / (nx * dx), -2 * math.pi * 2 / (ny * dy))
    phase = k[0] * x + k[1] * y + 0.4
    flux = 1e5 * np.cos(phase)
    t = math.radians(deg)
    m = np.sqrt(complex(k[0] ** 2 + k[1] ** 2, -v * (k[0] * math.cos(t) + k[1] * math.sin(t)) / KAPPA))
    want = np.real(1e5 * np.exp(1j * phase) / (LAM * m))
    got = vs.surface_temperature(flux, dx, v, LAM, KAPPA, periodic=True, direction_deg=deg, cell_size_y=dy)
    assert got.shape == (nx, ny) and got.dtype == np.float64
    assert np.max(np.abs(got - want)) <= 1e-9 * np.max(np.abs(want))


def test_the_block_adds_its_background():
    flux = np.full((8, 6), 2e4)
    flux[3, 2] += 1e5
    v, block = 0.1, 0.02
    free = vs.surface_temperature(flux, 1e-6, v, LAM, KAPPA, periodic=True)
    assert abs(free.mean()) < 1e-12 * free.max()
    blocked = vs.surface_temperature(flux, 1e-6, v, LAM, KAPPA, periodic=True, block_length=block)
    qbar = flux.mean()
    background = 4 / 3 * qbar * math.sqrt(KAPPA * block / v / math.pi) / LAM
    np.testing.assert_allclose(blocked - free, background, rtol=1e-12)


def test_a_passage_too_short_for_the_cell_warns():
    # 8 um cell, depth 8e-6 / (2 pi) = 1.27 um; one passage of a 1 cm block
    # diffuses sqrt(KAPPA * 0.01 / v): at 1 m/s 32 um (quiet), at 300 m/s
    # 1.8 um, less than the depth over 0.3 (warned).
    flux = np.full((8, 6), 2e4)
    flux[3, 2] += 1e5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        vs.surface_temperature(flux, 1e-6, 1.0, LAM, KAPPA, periodic=True, block_length=0.01)
    with pytest.warns(UserWarning, match="longest period 8.000e-6 m"):
        vs.surface_temperature(flux, 1e-6, 300.0, LAM, KAPPA, periodic=True, block_length=0.01)


def test_a_pad_trails_heat_behind_and_keeps_the_orientation():
    # A hot spot off the middle of a 12 x 7 map: the hottest cell is in its
    # row (axis 0 = x), warmer behind (-x) than ahead; sliding along +y is
    # the transposed problem sliding along +x.
    flux = np.zeros((12, 7))
    flux[8, 2] = 1e6
    rise = vs.surface_temperature(flux, 2e-6, 0.05, LAM, KAPPA)
    assert rise.shape == (12, 7)
    assert np.unravel_index(np.argmax(rise), rise.shape) == (8, 2)
    assert rise[7, 2] > rise[9, 2]
    along_y = vs.surface_temperature(flux, 2e-6, 0.05, LAM, KAPPA, direction_deg=90.0, cell_size_y=3e-6)
    along_x = vs.surface_temperature(flux.T, 3e-6, 0.05, LAM, KAPPA, cell_size_y=2e-6)
    np.testing.assert_allclose(along_y, along_x.T, rtol=0, atol=1e-12 * along_y.max())
    # Linear in the flux, 1 / lam in the conductivity; float32 and integer
    # maps are converted.
    np.testing.assert_allclose(
        vs.surface_temperature(flux.astype(np.float32), 2e-6, 0.05, 2 * LAM, KAPPA), rise / 2, rtol=1e-12
    )


@pytest.mark.parametrize(
    "change, words",
    [
        ({"speed": 0.0}, ["speed", "> 0"]),
        ({"speed": float("nan")}, ["speed", "finite"]),
        ({"conductivity": -0.2}, ["conductivity"]),
        ({"diffusivity": 0}, ["diffusivity"]),
        ({"cell_size": -1e-6}, ["cell_size"]),
        ({"cell_size_y": 0.0}, ["cell_size_y"]),
        ({"direction_deg": float("inf")}, ["direction_deg"]),
        ({"block_length": 0.01}, ["block_length", "periodic=True"]),
        ({"periodic": True, "block_length": -1.0}, ["block_length"]),
        ({"periodic": True, "block_length": 3e-6}, ["shorter than the periodic cell", "4.0000e-6 m"]),
        ({"flux": np.array([[1.0, np.nan]])}, ["flux", "non-finite", "(0, 1)"]),
        ({"flux": np.ones(5)}, ["flux", "2-dimensional"]),
        ({"flux": np.ones((0, 3))}, ["flux", "empty"]),
        ({"flux": np.ones((2, 2), dtype=complex)}, ["flux", "real"]),
        ({"flux": np.full((4, 3), 1e308)}, ["temperature rise overflows", "cell (0, 0)"]),
    ],
)
def test_argument_errors_name_the_argument(change, words):
    args = dict(flux=np.ones((4, 3)), cell_size=1e-6, speed=0.1, conductivity=LAM, diffusivity=KAPPA)
    args.update(change)
    with pytest.raises(ValueError) as e:
        vs.surface_temperature(**args)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_a_flag_of_the_wrong_type_and_masked_flux_are_named():
    """``periodic='yes'`` is a flag of the wrong type: a ``TypeError`` (as
    every flag of the package, README "Errors and warnings"); the masked
    points of a masked array are refused as masked, in one line, not as
    non-finite values they do not hold; a masked array with nothing
    masked is its data."""
    flux = np.ones((4, 3))
    with pytest.raises(TypeError, match="periodic must be True or False, got 'yes'"):
        vs.surface_temperature(flux, 1e-6, 0.1, LAM, KAPPA, periodic="yes")
    mask = np.zeros((4, 3), dtype=bool)
    mask[2, 1] = mask[3, 0] = True
    with pytest.raises(ValueError) as e:
        vs.surface_temperature(np.ma.masked_array(flux, mask=mask), 1e-6, 0.1, LAM, KAPPA)
    message = str(e.value)
    assert "flux has 2 masked value(s), the first at index (2, 1)" in message, message
    assert "non-finite" not in message and "\n" not in message, message
    unmasked = np.ma.masked_array(flux, mask=np.zeros((4, 3), dtype=bool))
    np.testing.assert_array_equal(
        vs.surface_temperature(unmasked, 1e-6, 0.1, LAM, KAPPA), vs.surface_temperature(flux, 1e-6, 0.1, LAM, KAPPA)
    )
