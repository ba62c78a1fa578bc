"""Sweeps, Persson's theory and the kernel table from Python agree with
single solves and with the command line."""

import json

import numpy as np
import pytest

import viscoslide as vs


@pytest.fixture(scope="module")
def small():
    return vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, seed=3)


def test_friction_curve_equals_single_solves(small, rubber):
    speeds = [1e-3, 1e-2]
    seen = []
    curve = vs.friction_curve(small, rubber, speeds, normal_load=0.3, backend="cpu", progress=seen.append)
    assert set(curve) == set(vs.COLUMNS)
    assert [p["point"] for p in seen] == [1, 2]
    for k, v in enumerate(speeds):
        one = vs.solve(small, rubber, speed=v, normal_load=0.3, backend="cpu")
        assert curve["friction_coefficient"][k] == one.friction_coefficient
        assert curve["contact_area_fraction"][k] == one.contact_area_fraction
    assert curve["speed"].tolist() == speeds
    assert curve["iterations"].dtype == np.int64


def test_speeds_as_a_range_a_generator_or_a_tuple_are_the_list(small, rubber):
    reference = vs.friction_curve(small, rubber, [0.0, 1.0], normal_load=0.3, backend="cpu")
    for speeds in (range(2), (v for v in (0.0, 1.0)), (0.0, 1.0)):
        curve = vs.friction_curve(small, rubber, speeds, normal_load=0.3, backend="cpu")
        assert curve["speed"].tolist() == [0.0, 1.0]
        assert np.array_equal(curve["friction_coefficient"], reference["friction_coefficient"])
    varied = vs.sweep(small, rubber, speed=1e-3, normal_load=0.3, backend="cpu",
                            vary={"material.poisson": (p for p in (0.4, 0.5))})
    assert varied["material.poisson"].tolist() == [0.4, 0.5]


@pytest.mark.parametrize(
    "speeds, message",
    [
        (np.ma.masked_array([1e-3, 1e-2], mask=[False, True]), r"speeds has 1 masked value.*\(1,\)"),
        ({1e-3, 1e-2}, "1-D sequence of numbers .*got a set"),
        ({1e-3: 1}, "1-D sequence of numbers .*got a dict"),
        ((v for v in (1e-3, float("nan"))), r"speeds\[1\] must be finite"),
    ],
)
def test_speeds_that_are_not_an_ordered_list_of_numbers_are_named(small, rubber, speeds, message):
    with pytest.raises(ValueError, match=message):
        vs.friction_curve(small, rubber, speeds, normal_load=0.3, backend="cpu")


def test_sweep_over_loads_and_xi(small, rubber):
    table = vs.sweep(small, rubber, xi=[0.0, 1e-2], mean_pressure=[2000.0, 4000.0], backend="cpu")
    assert len(table["xi"]) == 4
    assert abs(table["friction_coefficient"][0]) < 1e-12  # at rest: no friction but round-off
    assert table["normal_load"][2] == pytest.approx(4000.0 * 1e-4)
    with pytest.raises(ValueError, match="exactly one of speed"):
        vs.sweep(small, rubber, normal_load=1.0)


def test_sweep_as_frame(small, rubber):
    pandas = pytest.importorskip("pandas")
    frame = vs.friction_curve(small, rubber, [1e-2], normal_load=0.3, backend="cpu", as_frame=True)
    assert isinstance(frame, pandas.DataFrame) and list(frame.columns) == list(vs.COLUMNS)


def test_persson_matches_the_solve_record(small, rubber):
    r = vs.solve(small, rubber, speed=1e-2, normal_load=0.3, backend="cpu")
    theory = vs.persson(small, rubber, [1e-2], normal_load=0.3)
    assert theory["psd"] == "self_affine"
    assert theory["friction_coefficient"][0] == r.summary["persson_friction_coefficient"]
    assert theory["contact_area_fraction"][0] == r.summary["persson_contact_area_fraction"]


def test_kernel_table_matches_the_kernel_command(cli, repo):
    out = cli(
        "kernel", "--config", str(repo / "configs" / "default.toml"), "--cell-size", "3.9e-5",
        "--speed", "0.0117", "--offset", "0,0", "--offset", "-1,0", "--offset", "2,1", "--json",
    )
    rows = json.loads(out)
    m = vs.Material.from_toml(repo / "configs" / "default.toml")
    k = vs.kernel_table(m, nx=3, ny=3, cell_size=3.9e-5, speed=0.0117)
    d = vs.kernel_table(m, nx=3, ny=3, cell_size=3.9e-5, speed=0.0117, derivative=True)
    assert k.shape == (5, 5)
    for row in rows:
        i, j = row["i"] + 2, row["j"] + 2
        assert k[i, j] == pytest.approx(row["K"], rel=1e-12)
        assert d[i, j] == pytest.approx(row["dK_dx"], rel=1e-12)
    # Rectangular cells, as `kernel --cell-size-y`.
    out = cli(
        "kernel", "--config", str(repo / "configs" / "default.toml"), "--cell-size", "3.9e-5",
        "--cell-size-y", "1.3e-5", "--speed", "0.0117", "--offset", "-1,2", "--json",
    )
    row = json.loads(out)[0]
    k = vs.kernel_table(m, nx=3, ny=3, cell_size=3.9e-5, cell_size_y=1.3e-5, speed=0.0117)
    d = vs.kernel_table(
        m, nx=3, ny=3, cell_size=3.9e-5, cell_size_y=1.3e-5, speed=0.0117, derivative=True
    )
    assert k[1, 4] == pytest.approx(row["K"], rel=1e-12)
    assert d[1, 4] == pytest.approx(row["dK_dx"], rel=1e-12)
    with pytest.raises(ValueError, match="cell_size_y"):
        vs.kernel_table(m, nx=3, cell_size=3.9e-5, cell_size_y=-1.0, speed=0.0117)


def test_kernel_table_checks_cells_and_speeds_as_the_kernel_command(cli, repo):
    """``kernel_table`` refuses what ``viscoslide kernel`` refuses, with its
    words: a layer below the bound of a cell, cells beyond the range of the
    kernel's arithmetic (not a table of NaN); it warns of a layer thinner
    than a cell as the command does, and takes ``speed=inf``, the glassy
    limit, giving the command's ``--speed inf`` coefficients."""
    config = str(repo / "configs" / "default.toml")
    m = vs.Material.from_toml(config)
    with pytest.raises(ValueError) as e:
        vs.kernel_table(m, nx=4, cell_size=1e-4, speed=0.01, thickness=1e-9)
    assert str(e.value).startswith("[layer] thickness = 1e-9 m is 1.000e-5 of a cell (1e-4 m), below the bound of 1e-3 of a cell")
    for cell, text in ((1e-300, "1e-300"), (1e200, "1e200")):
        with pytest.raises(ValueError, match=f"the cell size {text} m is beyond the range"):
            vs.kernel_table(m, nx=4, cell_size=cell, speed=0.01)
    with pytest.warns(UserWarning, match=r"\[layer\] thickness = 0.00005 m is thinner than one cell"):
        vs.kernel_table(m, nx=4, cell_size=1e-4, speed=0.01, thickness=5e-5)
    glassy = vs.kernel_table(m, nx=3, cell_size=3.9e-5, speed=float("inf"))
    rows = json.loads(
        cli("kernel", "--config", config, "--cell-size", "3.9e-5", "--speed", "inf", "--offset", "0,0", "--offset", "2,-1", "--json")
    )
    for row in rows:
        assert row["K_viscoelastic"] == 0.0
        assert glassy[row["i"] + 2, row["j"] + 2] == pytest.approx(row["K"], rel=1e-12)
    with pytest.raises(ValueError, match="speed"):
        vs.kernel_table(m, nx=3, cell_size=3.9e-5, speed=-float("inf"))


def test_a_surface_from_a_psd_table_keeps_its_table(tmp_path, rubber):
    """A surface synthesised from a q, C table: Persson's theory uses the
    table (as for the same [surface.generate] psd in a config), not the
    radial average of one realisation."""
    q = np.logspace(np.log10(2 * np.pi / 0.01), np.log10(2 * np.pi / 0.01 * 64), 30)
    c = 1e-18 * (q / q[0]) ** (-2 * (1 + 0.8))
    path = tmp_path / "psd.csv"
    path.write_text("q_per_m,c_m4\n" + "".join(f"{a:.17g},{b:.17g}\n" for a, b in zip(q, c)))
    surface = vs.Surface.generate(n=64, length=0.01, seed=2, psd=path)
    assert surface.shape == (64, 64)
    theory = vs.persson(surface, rubber, [1e-2], normal_load=0.3)
    given = vs.persson(vs.Surface.from_array(surface.heights, 0.01), rubber, [1e-2], normal_load=0.3)
    assert theory["psd"] != given["psd"] == "radial_average"


def test_persson_warns_beyond_the_small_slope_limit(rubber):
    steep = vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=3.0, seed=3)
    needle = "the rms slope of the PSD is 3.000e0, beyond 1"
    with pytest.warns(UserWarning, match=needle):
        theory = vs.persson(steep, rubber, [1e-3, 1.0], normal_load=0.3)
    assert any(needle in w for w in theory["warnings"])


def test_persson_refuses_integrals_beyond_double_precision(small, rubber):
    # As `viscoslide persson`: a nominal pressure so small that G(q1)
    # overflows is refused, never a NaN G(q1) beside A/A0 = 1.
    with pytest.raises(ValueError, match="leave double precision"):
        vs.persson(small, rubber, [1e-3, 1.0], mean_pressure=1e-300)


def test_persson_refuses_speeds_beyond_double_precision(small, rubber):
    # q1 v overflows at 1e308 m/s: a ValueError, not a PanicException.
    with pytest.raises(ValueError, match="leave double precision"):
        vs.persson(small, rubber, [1e308], normal_load=0.3)
