"""Temperature (WLF shift of every creep time, physics.md section 12) and
sweeps over config keys (``vary=``) from Python: the same identities,
numbers and refusals as the command line."""

import json
import math
import os
import warnings

import numpy as np
import pytest

import viscoslide as vs

WLF = (8.86, 101.6, 17.0)


def shift(t):
    """``a_T`` written out: ``log10 a_T = -C1 (T - T_ref) / (C2 + T - T_ref)``."""
    dt = t - 17.0
    return 10.0 ** (-8.86 * dt / (101.6 + dt))


@pytest.fixture(scope="module")
def small():
    return vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, seed=3)


@pytest.fixture(scope="module")
def warm_rubber():
    return vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01, wlf=WLF)


def rel(a, b):
    return abs(a - b) / abs(b)


def test_solve_at_temperature_equals_the_shifted_speed(small, warm_rubber):
    # As the Rust test: the problems differ only in where a_T multiplies;
    # 1e-9 relative leaves room for rounding (solves converged to 1e-10).
    for formulation in ("nonperiodic", "periodic"):
        for t in (7.0, 37.0):
            a = shift(t)
            hot = vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=t,
                           formulation=formulation, tolerance=1e-10, backend="cpu")
            ref = vs.solve(small, warm_rubber, speed=a * 0.05, mean_pressure=3000.0,
                           formulation=formulation, tolerance=1e-10, backend="cpu")
            assert rel(hot.friction_coefficient, ref.friction_coefficient) < 1e-9
            assert rel(hot.friction_coefficient_dissipation, ref.friction_coefficient_dissipation) < 1e-9
            assert rel(hot.contact_area_fraction, ref.contact_area_fraction) < 1e-9
            assert hot.summary["temperature"] == t
            assert rel(hot.summary["shift_factor"], a) < 1e-13
            assert ref.summary["temperature"] == 17.0 and ref.summary["shift_factor"] == 1.0


def test_persson_and_friction_curve_take_the_temperature(small, warm_rubber):
    speeds = np.logspace(-4, 1, 6)
    t = 7.0
    a = shift(t)
    hot = vs.persson(small, warm_rubber, speeds, mean_pressure=3000.0, temperature=t)
    ref = vs.persson(small, warm_rubber, a * speeds, mean_pressure=3000.0)
    np.testing.assert_allclose(hot["friction_coefficient"], ref["friction_coefficient"], rtol=1e-9, atol=0)
    np.testing.assert_allclose(hot["contact_area_fraction"], ref["contact_area_fraction"], rtol=1e-9, atol=0)
    assert hot["temperature"] == t and rel(hot["shift_factor"], a) < 1e-13
    curve = vs.friction_curve(small, warm_rubber, [0.05], mean_pressure=3000.0, temperature=t, backend="cpu")
    one = vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=t, backend="cpu")
    assert curve["friction_coefficient"][0] == one.friction_coefficient
    assert curve["temperature"][0] == t and rel(curve["shift_factor"][0], a) < 1e-13


def test_sweep_vary_crosses_keys_with_speeds(small, warm_rubber):
    out = vs.sweep(small, warm_rubber, speed=[0.05, 0.5], mean_pressure=3000.0,
                   vary={"loading.temperature": [7.0, 27.0], "surface.generate.rms_slope": [0.01, 0.02]},
                   backend="cpu")
    assert len(out["speed"]) == 8
    # Keys in name order, the last fastest, then speeds.
    assert out["loading.temperature"].tolist() == [7.0] * 4 + [27.0] * 4
    assert out["surface.generate.rms_slope"].tolist() == [0.01, 0.01, 0.02, 0.02] * 2
    np.testing.assert_allclose(out["shift_factor"], [shift(t) for t in out["temperature"]], rtol=1e-13)
    other = vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.01, seed=3)
    one = vs.solve(other, warm_rubber, speed=0.5, mean_pressure=3000.0, temperature=27.0, backend="cpu")
    assert out["friction_coefficient"][5] == one.friction_coefficient


def test_refusals_are_one_line(small, rubber, warm_rubber):
    cases = [
        (lambda: vs.solve(small, rubber, speed=0.05, mean_pressure=3000.0, temperature=20.0), "WLF"),
        (lambda: vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=-90.0), "T_ref - C2"),
        (lambda: vs.persson(small, rubber, [1e-3], mean_pressure=3000.0, temperature=20.0), "WLF"),
        (lambda: vs.sweep(small, warm_rubber, speed=[0.05], mean_pressure=3000.0,
                          vary={"loading.temprature": [7.0]}), "temprature"),
        (lambda: vs.sweep(small, warm_rubber, speed=[0.05], mean_pressure=3000.0,
                          vary={"loading.temperature": ["hot"]}), "temperature"),
        (lambda: vs.sweep(small, warm_rubber, speed=[0.05], mean_pressure=3000.0,
                          vary={"loading.speed": [1.0]}), "loading.speed"),
        (lambda: vs.sweep(small, warm_rubber, speed=[0.05], mean_pressure=3000.0,
                          vary={"surface.generate.colour": [1.0]}), "colour"),
        (lambda: vs.sweep(small, warm_rubber, speed=[0.05], mean_pressure=3000.0,
                          vary={"loading.temperature": []}), "empty"),
    ]
    for call, needle in cases:
        with pytest.raises(ValueError) as e:
            call()
        assert needle in str(e.value) and "\n" not in str(e.value), str(e.value)


def test_material_toml_fitted_with_wlf_carries_its_constants(repo):
    m = vs.Material.from_toml(repo / "configs" / "data" / "sbr_like_material.toml")
    assert m.wlf == WLF
    assert vs.Material.from_toml(repo / "configs" / "material_sbr_like.toml").wlf == WLF
    assert not math.isnan(shift(7.0))


def test_a_temperature_beyond_the_wlf_data_is_warned_of(small, repo):
    # The constants said to be fitted from 0 to 40 C: at 45 C the solve is
    # answered with the Rust warning; inside, nothing warns.
    fitted = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01,
                             wlf=WLF, wlf_range=(0.0, 40.0))
    assert fitted.wlf_range == (0.0, 40.0)
    assert fitted.section["wlf_range"] == [0.0, 40.0]

    def data_warnings(t):
        r = vs.solve(small, fitted, speed=0.05, mean_pressure=3000.0, temperature=t,
                     formulation="periodic", backend="cpu")
        assert r.summary["wlf_range"] == [0.0, 40.0]
        return [w for w in r.summary["warnings"] if "DMA data" in w]

    assert data_warnings(20.0) == []
    above = data_warnings(45.0)
    assert len(above) == 1 and "45.0000 C lies 5.000 K above the DMA data (0 to 40 C)" in above[0], above
    # The shipped file records its data's range; a fit on several
    # temperatures records theirs.
    assert vs.Material.from_toml(repo / "configs" / "data" / "sbr_like_material.toml").wlf_range == (-20.0, 100.0)
    freq = np.array([1.0, 10.0, 100.0] * 2)
    e1 = 2e6 * (1.0 + 0.05 * np.log10(freq))
    m = vs.Material.fit_dma(freq, e1, 0.1 * e1, wlf=WLF, temperatures=[5.0] * 3 + [30.0] * 3, terms=8)
    assert m.wlf_range == (5.0, 30.0)
    assert vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=1e7, creep_time=0.01, wlf=WLF).wlf_range is None
    for bad, needle in [((40.0, 0.0), "lowest first"), ((0.0,), "two numbers")]:
        with pytest.raises(ValueError) as e:
            vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=1e7, creep_time=0.01, wlf=WLF, wlf_range=bad)
        assert needle in str(e.value) and "\n" not in str(e.value), str(e.value)
    # The data's frequencies: recorded by a fit (shifted to its
    # temperature), read from the shipped file, and warned of beyond a
    # decade (the Rust test's case: q1 = 3 q_L on 0.01 m, 20 m/s reaches
    # 3.77e4 rad/s against data up to 1e3).
    assert m.frequency_range == pytest.approx((2 * math.pi * 1.0 * shift(30.0) / shift(17.0), 2 * math.pi * 100.0 * shift(5.0) / shift(17.0)), rel=1e-12)
    assert vs.Material.from_toml(repo / "configs" / "data" / "sbr_like_material.toml").frequency_range[1] == pytest.approx(74609283.86623685, rel=1e-15)
    narrow = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01, wlf=WLF,
                             frequency_range=(1.0, 1e3))
    assert narrow.frequency_range == (1.0, 1e3)
    cell = vs.Surface.self_affine(16, 0.01, 0.8, scales=3, rms_slope=0.02, seed=3)
    r = vs.solve(cell, narrow, speed=20.0, mean_pressure=3000.0, formulation="periodic", backend="cpu")
    above = [w for w in r.summary["warnings"] if w.startswith("the sliding excites")]
    assert len(above) == 1 and "up to 3.770e4 rad/s, 1.6 decades above" in above[0], above
    # Persson's curve warns as `viscoslide persson` does: the temperature
    # beyond the WLF data, the speeds' frequencies beyond the frequency
    # data; inside both, nothing.
    with pytest.warns(UserWarning, match="above the DMA data"):
        curve = vs.persson(small, fitted, [1e-3], mean_pressure=3000.0, temperature=45.0)
    assert len(curve["warnings"]) == 1 and "45.0000 C lies 5.000 K above" in curve["warnings"][0], curve["warnings"]
    with pytest.warns(UserWarning, match="decades above"):
        curve = vs.persson(cell, narrow, [1e-3, 20.0], mean_pressure=3000.0, as_frame=True)
    assert any("decades above" in w for w in curve.attrs["warnings"]), curve.attrs["warnings"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet = vs.persson(small, fitted, [1e-3], mean_pressure=3000.0, temperature=20.0)
    assert quiet["warnings"] == [] and quiet["notes"] == []
    with pytest.raises(ValueError, match="frequency_range"):
        vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=1e7, creep_time=0.01, frequency_range=(1e3, 1.0))
    with pytest.raises(ValueError, match="give the constants too"):
        vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=1e7, creep_time=0.01, wlf_range=(0.0, 40.0))


def _numbers(value, path=""):
    """Every number of a nested summary with its path; nulls as None."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _numbers(v, f"{path}.{k}")
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            yield from _numbers(v, f"{path}[{i}]")
    elif value is None or (isinstance(value, (int, float)) and not isinstance(value, bool)):
        yield path, value


def test_temperature_bounds_are_the_rust_ones(small, warm_rubber):
    # The validity range |log10 a_T| <= 50 of WLF = (8.86, 101.6, 17):
    # T >= 17 - 101.6 * 50 / 58.86 = -69.306 C, quoted as -69.3 C. Near the
    # pole a_T overflowed and the solve returned nan.
    for t in (-84.4, -80.0):
        for call in (
            lambda: vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=t, backend="cpu"),
            lambda: vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=t,
                             formulation="periodic", backend="cpu"),
            lambda: vs.persson(small, warm_rubber, [1e-3], mean_pressure=3000.0, temperature=t),
        ):
            with pytest.raises(ValueError) as e:
                call()
            msg = str(e.value)
            assert f"temperature {t:g} C" in msg and "T >= -69.3 C" in msg and "\n" not in msg, msg
    # Just inside: every number of the summary finite, the nulls those at T_ref.
    ref = vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, backend="cpu")
    near = vs.solve(small, warm_rubber, speed=0.05, mean_pressure=3000.0, temperature=-69.3, backend="cpu")
    values = dict(_numbers(near.summary))
    assert all(v is None or math.isfinite(v) for v in values.values()), values
    assert [p for p, v in values.items() if v is None] == [p for p, v in _numbers(ref.summary) if v is None]
    assert near.summary["shift_factor"] > 1e49 and math.isfinite(near.friction_coefficient_dissipation)


def test_absurd_wlf_constants_are_refused_in_rust(repo):
    sls = dict(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01)
    for wlf, needle in (
        ((1e300, 101.6, 17.0), "C1 = 1e300"),
        ((60.0, 101.6, 17.0), "|C1| <= 50"),
        ((8.86, 0.0, 17.0), "C2 > 0"),
        ((8.86, 101.6, 17.0, 4.0), "wlf"),
    ):
        with pytest.raises(ValueError) as e:
            vs.Material.sls(**sls, wlf=wlf)
        assert "wlf" in str(e.value) and needle in str(e.value) and "\n" not in str(e.value), str(e.value)
    w = np.logspace(0, 3, 4)
    with pytest.raises(ValueError) as e:
        vs.Material.fit_dma(w, 1e6 + 0 * w, 1e5 + 0 * w, wlf=(1e300, 101.6, 17.0), temperatures=[17.0] * 4)
    assert "wlf" in str(e.value) and "C1" in str(e.value), str(e.value)
    with pytest.raises(ValueError) as e:
        vs.Material.fit_dma(w, 1e6 + 0 * w, 1e5 + 0 * w, wlf=WLF, temperatures=[17.0, 17.0, 17.0, -80.0])
    assert "temperature -80 C" in str(e.value) and "T >= -69.3 C" in str(e.value), str(e.value)


def test_a_section_rebuilds_a_material_fitted_off_its_reference(small, repo, cli, tmp_path):
    # A spectrum fitted at 30 C with constants referred to 17 C: its
    # section (recorded in every solve's configuration) lost the constants,
    # so the written configuration refused any temperature. Now the
    # section rebuilds the same material at its own temperature and at
    # others, to rounding (1e-12: the creep times pass through two shift
    # factors instead of one).
    freq = np.array([1.0, 10.0, 100.0] * 2)
    e1 = 2e6 * (1.0 + 0.05 * np.log10(freq))
    m = vs.Material.fit_dma(freq, e1, 0.1 * e1, wlf=WLF, temperature=30.0,
                            temperatures=[5.0] * 3 + [30.0] * 3, terms=8)
    section = m.section
    c1, c2, t_ref = section["wlf"]
    assert t_ref == 30.0 and c2 == pytest.approx(101.6 + 13.0, rel=1e-15)
    assert c1 == pytest.approx(8.86 * 101.6 / (101.6 + 13.0), rel=1e-15)
    assert section["wlf_range"] == [5.0, 30.0]
    rebuilt = vs.Material._from_section(section)
    w = np.logspace(-2, 4, 7)
    assert np.allclose(rebuilt.complex_modulus(w), m.complex_modulus(w), rtol=1e-14, atol=0)
    for t in (None, 12.0, 40.0):
        kw = {} if t is None else {"temperature": t}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a, b = (vs.solve(small, x, speed=0.05, mean_pressure=3000.0, formulation="periodic",
                             backend="cpu", **kw) for x in (m, rebuilt))
        assert rel(a.friction_coefficient, b.friction_coefficient) < 1e-12, t
    # A material.toml fitted at 30 C by the command line: read as
    # `model = "file"` reads it, with that as its section.
    csv = tmp_path / "dma.csv"
    csv.write_text("frequency_hz,e1_pa,e2_pa,temperature_c\n"
                   + "".join(f"{f},{a},{0.1 * a},{t}\n" for f, a, t in zip(freq, e1, [5.0] * 3 + [30.0] * 3)))
    cli("material", "fit", str(csv), "--wlf", "8.86,101.6,17.0", "--temperature", "30", "--terms", "8",
        "--out", str(tmp_path / "fit"))
    out = tmp_path / "fit" / "material.toml"
    read = vs.Material.from_toml(out)
    assert read.section["model"] == "file" and read.section["file"] == os.path.realpath(out)
    assert read.wlf == WLF
    again = vs.Material._from_section(read.section)
    assert np.array_equal(again.complex_modulus(w), read.complex_modulus(w))


def test_kernel_table_at_temperature_is_the_shifted_speed(cli, tmp_path, warm_rubber):
    """``kernel_table(temperature=T)`` takes the material at ``T``, as
    ``viscoslide kernel`` takes ``[loading] temperature``: its table is the
    reference temperature's at the shifted speed, ``K(v, T) = K(a_T v,
    T_ref)``, and the command's coefficients."""
    v, a = 0.0117, 3.9e-5
    for t in (7.0, 17.0, 40.0):
        for derivative in (False, True):
            hot = vs.kernel_table(warm_rubber, nx=3, cell_size=a, speed=v, temperature=t, derivative=derivative)
            shifted = vs.kernel_table(warm_rubber, nx=3, cell_size=a, speed=shift(t) * v, derivative=derivative)
            np.testing.assert_allclose(hot, shifted, rtol=1e-10, atol=0)
    config = tmp_path / "k.toml"
    config.write_text(
        '[material]\nmodel = "sls"\nrelaxed_modulus = 3333333.3333333335\nglassy_modulus = 1e7\n'
        "creep_time = 0.01\npoisson = 0.5\nwlf = [8.86, 101.6, 17.0]\n[loading]\ntemperature = 40.0\n"
    )
    rows = json.loads(
        cli("kernel", "--config", str(config), "--cell-size", str(a), "--speed", str(v), "--offset", "1,-1", "--json")
    )
    k = vs.kernel_table(warm_rubber, nx=3, cell_size=a, speed=v, temperature=40.0)
    d = vs.kernel_table(warm_rubber, nx=3, cell_size=a, speed=v, temperature=40.0, derivative=True)
    assert k[3, 1] == pytest.approx(rows[0]["K"], rel=1e-12)
    assert d[3, 1] == pytest.approx(rows[0]["dK_dx"], rel=1e-12)
    # Without WLF constants a temperature has no meaning: refused, as the
    # command refuses it.
    plain = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01)
    with pytest.raises(ValueError, match="WLF"):
        vs.kernel_table(plain, nx=3, cell_size=a, speed=v, temperature=20.0)
    with pytest.raises(ValueError, match="temperature must be finite"):
        vs.kernel_table(warm_rubber, nx=3, cell_size=a, speed=v, temperature=float("nan"))
