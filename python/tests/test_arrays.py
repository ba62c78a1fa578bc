"""numpy in and out: any real dtype and memory order is converted; bad
arrays and values are a ValueError that names the problem."""

import numpy as np
import pytest

import viscoslide as vs


def solve(heights, rubber):
    surface = vs.Surface.from_array(heights, 0.01)
    return vs.solve(surface, rubber, xi=1.17e-2, mean_pressure=3000.0, backend="cpu")


def test_fortran_order_and_float32_give_the_c_float64_result(pad, rubber):
    h32 = pad.heights.astype(np.float32)
    reference = solve(h32.astype(np.float64), rubber)
    for variant in (np.asfortranarray(h32), h32, np.asfortranarray(h32.astype(np.float64))):
        r = solve(variant, rubber)
        assert np.array_equal(r.pressure, reference.pressure)
        assert r.friction_coefficient == reference.friction_coefficient
    assert reference.pressure.shape == pad.shape
    assert reference.pressure.dtype == np.float64 and reference.pressure.flags.c_contiguous


def test_heights_round_trip_with_axis_0_along_x(pad):
    h = pad.heights
    s = vs.Surface.from_array(h[:, :40], 0.01, detrend="none")
    assert s.shape == (64, 40)
    assert np.array_equal(s.heights, h[:, :40])
    assert s.physical_sizes == pytest.approx((0.01, 0.01 * 40 / 64))


@pytest.mark.parametrize(
    "heights, length, message",
    [
        (np.full((8, 8), np.nan), 0.01, "NaN"),
        (np.zeros((8, 8)) + 1j, 0.01, "complex"),
        (np.zeros(8), 0.01, "2-dimensional"),
        (np.zeros((2, 8, 8)), 0.01, "2-dimensional"),
        (np.array([["a", "b"], ["c", "d"]]), 0.01, "real numbers"),
        (np.zeros((8, 8), dtype=object), 0.01, "real numbers"),
        (np.zeros((8, 8)), -0.01, "length must be > 0"),
        (np.zeros((8, 8)), float("nan"), "length must be finite"),
        (np.zeros((1, 8)), 0.01, "at least 2 x 2"),
    ],
)
def test_bad_heights_are_named(heights, length, message):
    with pytest.raises(ValueError, match=message):
        vs.Surface.from_array(heights, length)


def test_one_nan_is_located():
    h = np.zeros((8, 8))
    h[3, 5] = np.nan
    with pytest.raises(ValueError, match=r"1 non-finite value.*\(3, 5\)"):
        vs.Surface.from_array(h, 0.01)


def test_an_infinite_height_with_fill_missing_is_not_sent_to_fill_missing():
    h = np.zeros((8, 8))
    h[2, 6] = np.inf
    h[4, 4] = np.nan
    with pytest.raises(ValueError, match=r"1 infinite value.*\(2, 6\)") as e:
        vs.Surface.from_array(h, 0.01, fill_missing=True)
    assert "pass fill_missing" not in str(e.value)


def test_non_square_cells_are_kept():
    s = vs.Surface.from_array(np.zeros((8, 4)), 0.01, length_y=0.01)
    assert s.cell_sizes == (0.01 / 8, 0.01 / 4)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"xi": 1e-2, "normal_load": -1.0}, "normal load must be positive"),
        ({"xi": 1e-2, "speed": 1.0, "normal_load": 1.0}, "only one of speed"),
        ({"normal_load": 1.0}, "needs speed"),
        ({"xi": 1e-2}, "needs one of normal_load"),
        ({"xi": float("nan"), "normal_load": 1.0}, "xi must be finite"),
        ({"xi": 1j, "normal_load": 1.0}, "xi must be real"),
        ({"speed": -1.0, "normal_load": 1.0}, "speed must be >= 0"),
        ({"xi": 1e-2, "normal_load": 1.0, "formulation": "spherical"}, "formulation"),
        ({"xi": 1e-2, "normal_load": 1.0, "backend": "tpu"}, "backend"),
        ({"xi": 1e-2, "normal_load": 1.0, "tolerance": 2.0}, "tolerance"),
        ({"xi": 1e-2, "normal_load": 1.0, "thickness": -1e-3}, "thickness must be > 0"),
    ],
)
def test_bad_loading_is_named(pad, rubber, kwargs, message):
    with pytest.raises(ValueError, match=message):
        vs.solve(pad, rubber, **kwargs)


def test_bad_generator_and_material_keys_are_named():
    with pytest.raises(ValueError, match="hurst"):
        vs.Surface.self_affine(16, 0.01, 1.5, scales=4, rms_slope=0.02)
    with pytest.raises(ValueError, match="unknown field `colour`"):
        vs.Surface.generate(n=16, length=0.01, hurst=0.8, scales=4, rms_slope=0.02, colour="red")
    with pytest.raises(ValueError, match="glassy_modulus"):
        vs.Material.sls(relaxed_modulus=1e7, glassy_modulus=-1.0, creep_time=0.01)
    with pytest.raises(ValueError, match="times and weights"):
        vs.Material.creep_spectrum([0.1, 1.0], [1e-7], glassy_modulus=1e7)


@pytest.mark.parametrize(
    "keys, message",
    [
        ({"anisotropy": {"ratio": float("nan"), "angle_deg": 0.0}}, "anisotropy.ratio must be finite, got nan"),
        ({"anisotropy": {"ratio": 2.0, "angle_deg": np.float32("inf")}}, "anisotropy.angle_deg must be finite, got inf"),
        ({"seed": 2**70}, "seed is out of the range of a 64-bit whole number"),
        ({"length": 10**400}, "length is out of the range of a 64-bit whole number"),
    ],
)
def test_generator_values_json_cannot_carry_are_named(keys, message):
    args = {"n": 16, "length": 0.01, "hurst": 0.8, "scales": 4, "rms_slope": 0.02, **keys}
    with pytest.raises(ValueError, match=message):
        vs.Surface.generate(**args)


def test_a_0d_array_is_a_generator_number():
    args = {"n": 16, "hurst": 0.8, "scales": 4, "rms_slope": 0.02, "seed": 2}
    a = vs.Surface.generate(length=np.array(0.01), **args)
    assert np.array_equal(a.heights, vs.Surface.generate(length=0.01, **args).heights)


def test_a_stretch_the_grid_cannot_hold_is_warned(rubber):
    """`anisotropy` beyond q1 / q_L along an axis leaves a ridged surface
    whatever the ratio: the surface is made and warned, and a solve on it
    carries the warning; a stretch the grid holds is quiet."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        vs.Surface.self_affine(64, 0.01, 0.8, scales=16, rms_slope=0.02, anisotropy=(2.0, 45.0))
    with pytest.warns(UserWarning, match=r"anisotropy.ratio = 20 .*ridged"):
        ridged = vs.Surface.self_affine(64, 0.01, 0.8, scales=16, rms_slope=0.02, anisotropy=(20.0, 0.0))
    with pytest.warns(UserWarning, match="ridged"):
        r = vs.solve(ridged, rubber, xi=1.17e-2, mean_pressure=3000.0, backend="cpu")
    assert any("ridged" in w for w in r.summary["warnings"]), r.summary["warnings"]


def test_filled_points_are_counted_and_many_are_warned_about(pad, rubber):
    """`fill_missing` fills NaN points by harmonic interpolation: their
    count is in the summary (`filled_points`), and more than 5 % of the map
    filled is warned about, as the command line does."""
    h = pad.heights.copy()
    h[3, 5] = np.nan
    few = vs.solve(vs.Surface.from_array(h, 0.01, fill_missing=True), rubber, xi=1.17e-2,
                   mean_pressure=3000.0, backend="cpu")
    assert few.summary["filled_points"] == 1
    assert not any("missing from the contact" in w for w in few.summary["warnings"])
    h[20:40, 20:40] = np.nan
    with pytest.warns(UserWarning, match="401 of 4096 points .* missing from the contact"):
        many = vs.solve(vs.Surface.from_array(h, 0.01, fill_missing=True), rubber, xi=1.17e-2,
                        mean_pressure=3000.0, backend="cpu")
    assert many.summary["filled_points"] == 401


def test_numpy_scalars_make_the_same_generated_surface():
    """``Surface.generate`` takes numpy scalars as ``self_affine`` does
    (a ``np.int64`` count raised a bare json TypeError), and a value of
    another type is a TypeError naming its key."""
    plain = vs.Surface.generate(n=32, length=0.01, hurst=0.8, scales=4, rms_slope=0.02, seed=3)
    numpy = vs.Surface.generate(n=np.int64(32), length=np.float64(0.01), hurst=np.float64(0.8),
                                scales=np.int32(4), rms_slope=np.float64(0.02), seed=np.uint8(3))
    assert np.array_equal(plain.heights, numpy.heights)
    with pytest.raises(TypeError, match="rms_slope must be a number or a string, got object"):
        vs.Surface.generate(n=32, length=0.01, hurst=0.8, scales=4, rms_slope=object())


def test_editing_a_summary_changes_nothing(pad, rubber):
    r = solve(pad.heights, rubber)
    mu = r.friction_coefficient
    s = r.summary
    s["friction_coefficient"] = 99.0
    s["warnings"].append("edited")
    assert r.summary["friction_coefficient"] == mu == r.friction_coefficient
    assert "edited" not in r.summary["warnings"]


class _Topography:
    """A topography-like object: ``heights()`` and ``physical_sizes`` in m."""

    unit = "m"
    physical_sizes = (0.01, 0.01)

    def __init__(self, heights):
        self._heights = heights

    def heights(self):
        return self._heights


@pytest.mark.parametrize(
    "heights, message",
    [
        (np.ma.masked_array(np.ones((8, 8)) + 1j, mask=False), "complex"),
        (np.ma.masked_array(np.ones((8, 8), dtype=bool), mask=False), "dtype bool"),
        (np.ma.masked_array(np.full((8, 8), "1e-6"), mask=False), "real numbers"),
        ([[0.0, 1e-6], [1e-6]], "heights\\(\\) must be an array of real numbers"),
    ],
)
def test_a_topographys_heights_of_the_wrong_kind_are_refused_not_cast(heights, message):
    """A masked map of booleans, complex numbers or strings is refused as
    from_array refuses the same values unmasked (not cast to float, which
    drops an imaginary part or parses strings)."""
    with pytest.raises(ValueError, match=message):
        vs.Surface.from_topography(_Topography(heights))


def test_a_topographys_masked_integer_heights_are_taken_with_their_holes():
    h = np.ma.masked_array(np.ones((8, 8), dtype=np.int32), mask=False)
    h.mask[2, 3] = True
    s = vs.Surface.from_topography(_Topography(h), fill_missing=True, detrend="none")
    assert s.shape == (8, 8) and np.all(s.heights == 1.0)
