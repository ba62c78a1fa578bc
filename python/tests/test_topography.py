"""SurfaceTopography interop by duck typing: a Topography gives the same
result as its heights passed as an array."""

import numpy as np
import pytest

import viscoslide as vs

SurfaceTopography = pytest.importorskip("SurfaceTopography")


def test_a_topography_solves_like_its_heights(pad, rubber):
    h = pad.heights
    topo = SurfaceTopography.Topography(h, physical_sizes=(0.01, 0.01), periodic=False)
    from_topo = vs.solve(topo, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
    from_array = vs.solve(vs.Surface.from_array(h, 0.01), rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
    assert np.array_equal(from_topo.pressure, from_array.pressure)
    assert from_topo.friction_coefficient == from_array.friction_coefficient
    assert from_topo.summary["config"]["solver"]["formulation"] == "non_periodic"


def test_a_periodic_topography_is_solved_periodic_under_auto(pad, rubber):
    topo = SurfaceTopography.Topography(pad.heights, physical_sizes=(0.01, 0.01), periodic=True)
    r = vs.solve(topo, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
    assert r.summary["formulation"] == "periodic"
    same = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", formulation="periodic")
    assert np.array_equal(r.pressure, same.pressure)


def test_a_rectangular_topography_keeps_its_axes(pad):
    h = pad.heights[:, :32]
    # Periodic: taken as it is (a scan would lose its mean plane).
    topo = SurfaceTopography.Topography(h, physical_sizes=(0.01, 0.005), periodic=True)
    s = vs.Surface.coerce(topo)
    assert s.shape == (64, 32)
    assert np.array_equal(s.heights, h)
    rect = SurfaceTopography.Topography(h, physical_sizes=(0.01, 0.01))
    assert vs.Surface.coerce(rect).cell_sizes == pytest.approx((0.01 / 64, 0.01 / 32))


def test_a_measured_file_read_by_surface_topography(cli, tmp_path, pad, rubber):
    """An .x3p scan (written by `viscoslide surface convert`) read through
    SurfaceTopography solves like the same file read by viscoslide."""
    np.save(tmp_path / "scan.npy", pad.heights[:, :48])
    cli("surface", "convert", str(tmp_path / "scan.npy"), str(tmp_path / "scan.x3p"), "--length", "0.01")
    ours = vs.Surface.from_file(tmp_path / "scan.x3p")
    topo = SurfaceTopography.open_topography(str(tmp_path / "scan.x3p")).topography().to_unit("m")
    assert topo.nb_grid_pts == (64, 48)
    theirs = vs.Surface.coerce(topo)
    assert np.array_equal(theirs.heights, ours.heights)
    assert theirs.physical_sizes == pytest.approx(ours.physical_sizes, rel=1e-12)
    a = vs.solve(topo, rubber, xi=1.17e-2, mean_pressure=3000.0, backend="cpu")
    b = vs.solve(ours, rubber, xi=1.17e-2, mean_pressure=3000.0, backend="cpu")
    assert np.array_equal(a.pressure, b.pressure)


def test_other_objects_are_refused(rubber):
    with pytest.raises(TypeError, match="heights"):
        vs.solve(np.zeros((8, 8)), rubber, xi=1e-2, normal_load=1.0)


def test_units_are_converted_and_missing_points_refused(pad):
    h = pad.heights
    in_um = SurfaceTopography.Topography(h * 1e6, physical_sizes=(1e4, 1e4), unit="um", periodic=True)
    s = vs.Surface.coerce(in_um)
    np.testing.assert_allclose(s.heights, h, rtol=1e-12)
    assert s.physical_sizes == pytest.approx((0.01, 0.01))
    holes = np.ma.masked_array(h, mask=np.zeros_like(h, dtype=bool))
    holes.mask[3, 4] = True
    missing = SurfaceTopography.Topography(holes, physical_sizes=(0.01, 0.01))
    with pytest.raises(ValueError, match="missing.*fill_missing=True"):
        vs.Surface.coerce(missing)


def test_the_periodic_formulation_takes_an_array_as_one_period(rubber, pad, tmp_path):
    """An array that is one period, not marked periodic, solved with
    ``formulation="periodic"``: its heights are kept (no plane removed) and
    its answer is the one of the same array marked periodic, with a warning
    that states the step between its opposite edges; an explicit
    ``detrend`` is still applied. A file read without ``periodic`` behaves
    the same."""
    h = pad.heights
    marked = vs.solve(vs.Surface.from_array(h, 0.01, periodic=True), rubber, xi=1.17e-2,
                      mean_pressure=3000.0, backend="cpu", formulation="periodic")
    with pytest.warns(UserWarning, match="not marked periodic"):
        unmarked = vs.solve(vs.Surface.from_array(h, 0.01), rubber, xi=1.17e-2,
                            mean_pressure=3000.0, backend="cpu", formulation="periodic")
    assert np.array_equal(unmarked.pressure, marked.pressure)
    assert unmarked.summary["surface_preprocessing"]["detrend"] == "none"
    assert not any("not marked periodic" in w for w in marked.summary["warnings"])
    with pytest.warns(UserWarning, match="not marked periodic"):
        planed = vs.solve(vs.Surface.from_array(h, 0.01, detrend="plane"), rubber, xi=1.17e-2,
                          mean_pressure=3000.0, backend="cpu", formulation="periodic")
    assert planed.summary["surface_preprocessing"]["detrend"] == "plane"
    # The non-periodic formulation: the scan's plane is removed as before.
    pad_solve = vs.solve(vs.Surface.from_array(h, 0.01), rubber, xi=1.17e-2, mean_pressure=3000.0,
                         backend="cpu")
    assert pad_solve.summary["surface_preprocessing"]["detrend"] == "plane"
    np.save(tmp_path / "map.npy", h)
    with pytest.warns(UserWarning, match="not marked periodic"):
        from_file = vs.solve(vs.Surface.from_file(str(tmp_path / "map.npy"), length=0.01), rubber, xi=1.17e-2,
                             mean_pressure=3000.0, backend="cpu", formulation="periodic")
    assert np.array_equal(from_file.pressure, marked.pressure)


def test_a_curve_of_a_topography_takes_solves_preparation_keys(pad, rubber):
    """``friction_curve`` and ``sweep`` of a topography with a missing
    point take ``fill_missing`` (and ``detrend``) as ``solve`` does (they
    said "pass fill_missing=True" to a call that had, and "this Surface
    was prepared already" of a topography), and give solve's answer."""
    h = pad.heights.copy()
    h[3, 4] = np.nan
    topo = SurfaceTopography.Topography(np.ma.masked_invalid(h), physical_sizes=(0.01, 0.01), periodic=False)
    one = vs.solve(topo, rubber, speed=0.01, normal_load=0.3, backend="cpu", fill_missing=True, detrend="plane")
    curve = vs.friction_curve(topo, rubber, [0.01], normal_load=0.3, backend="cpu", fill_missing=True, detrend="plane")
    assert curve["friction_coefficient"][0] == one.friction_coefficient
    with pytest.raises(ValueError, match="fill_missing"):
        vs.friction_curve(topo, rubber, [0.01], normal_load=0.3, backend="cpu")
