"""Frictional heating from Python (physics.md section 14): ``heating=`` of
``solve``, ``sweep`` and ``friction_curve`` gives the numbers of
``viscoslide solve`` with the same ``[heating]`` section, the identity
``mu_heated(v, T0) = mu(v, T_eff)`` against an independent isothermal
solve, the refusals before anything is solved, and ``Result.heat`` (the
heat of a solved contact) against the heated solve's own fixed point."""

import json
import math

import numpy as np
import pytest

import viscoslide as vs
from test_parity import assert_close

#: The case of tests/heat/heated.rs: a single-relaxation rubber with the
#: "universal" WLF constants at T_ref = 17 C, a 32^2 periodic cell of
#: 0.2 mm at 1 MPa sliding at 0.1 m/s under a 5 cm block (a rise of
#: kelvins, the block's background heating dominating).
MATERIAL = dict(
    relaxed_modulus=3.3333333333333335e6, glassy_modulus=1.0e7, creep_time=1e-4, poisson=0.5, wlf=(8.86, 101.6, 17.0)
)
GENERATE = dict(n=32, length=0.0002, hurst=0.8, scales=4, rms_slope=0.3, seed=3)
HEATING = dict(conductivity=0.25, diffusivity=1e-7, block_length=0.05)
LOADING = dict(speed=0.1, mean_pressure=1e6, temperature=17.0)

CONFIG = """
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 1e-4
poisson = 0.5
wlf = [8.86, 101.6, 17.0]

[surface.generate]
n = 32
length = 0.0002
hurst = 0.8
scales = 4
rms_slope = 0.3
seed = 3

[loading]
mean_pressure = 1e6
speed = 0.1
temperature = 17.0

[solver]
formulation = "periodic"
tolerance = 1e-11

[heating]
conductivity = 0.25
diffusivity = 1e-7
block_length = 0.05
"""


@pytest.fixture(scope="module")
def wlf_rubber():
    return vs.Material.sls(**MATERIAL)


@pytest.fixture(scope="module")
def cell():
    return vs.Surface.generate(**GENERATE)


@pytest.fixture(scope="module")
def heated(cell, wlf_rubber):
    return vs.solve(cell, wlf_rubber, **LOADING, formulation="periodic", tolerance=1e-11, heating=HEATING, backend="cpu")


def test_solve_with_heating_equals_the_command_line(cli, tmp_path, heated):
    """The same case through ``viscoslide solve`` and ``vs.solve``: the
    heating object's numbers to 1e-12 relative (both are the same
    computation on the same map: any difference would be a different
    problem, not rounding), every other entry equal, the temperature map
    element by element, its orientation (axis 0 = x) that of
    ``temperature.npy``."""
    config = tmp_path / "case.toml"
    config.write_text(CONFIG)
    out = tmp_path / "cli"
    cli("solve", str(config), "--backend", "cpu", "--out", str(out))
    with open(out / "summary.json") as f:
        expected = json.load(f)
    h = heated.heating
    assert h is not None and h == heated.summary["heating"]
    assert_close(h, expected["heating"], "heating")
    # The run is worth comparing: a rise of kelvins, below the bracket, and
    # the heated friction below the isothermal one at T0.
    assert 1.0 < h["temperature_rise"]["effective"] < 50.0, h["temperature_rise"]
    # The effective rise is Theta(T_eff), T_eff - T0 to the search's
    # tolerance (1e-3 K by default): the chosen branch's rise plus its
    # residual g(T_eff) = T0 + Theta(T_eff) - T_eff.
    branch = next(b for b in h["branches"] if b["temperature"] == h["effective_temperature"])
    assert math.isclose(branch["rise"], h["effective_temperature"] - h["ambient_temperature"], rel_tol=1e-12)
    assert math.isclose(h["temperature_rise"]["effective"], branch["rise"] + branch["residual"], rel_tol=1e-12)
    assert abs(branch["residual"]) <= 1e-3
    assert heated.friction_coefficient < h["isothermal_friction_coefficient"]
    assert h["persson_friction_coefficient"] is not None
    assert len(h["branches"]) >= 1 and h["chosen_branch"] == "cold"
    assert h["fixed_point_evaluations"] == len(h["evaluations"])
    assert math.isclose(heated.friction_coefficient, expected["friction_coefficient"], rel_tol=1e-12)
    assert np.array_equal(heated.pressure, np.load(out / "pressure.npy"))
    rise = heated.temperature_rise
    cli_rise = np.load(out / "temperature.npy")
    assert rise.shape == (32, 32) and rise.dtype == np.float64
    assert np.array_equal(rise, cli_rise)
    # The depth profile of temperature_depth.csv, row by row.
    depth = heated.temperature_depth
    table = np.loadtxt(out / "temperature_depth.csv", delimiter=",", skiprows=1, ndmin=2)
    for k, name in enumerate(("depth", "mean_rise", "max_rise", "mean_source")):
        assert np.array_equal(depth[name], table[:, k]), name
    # Result.write gives the command's heated outputs.
    written = {p.rsplit("/", 1)[-1] for p in heated.write(tmp_path / "py")}
    assert {"temperature.npy", "temperature.png", "temperature_depth.csv", "summary.json"} <= written
    assert np.array_equal(np.load(tmp_path / "py" / "temperature.npy"), rise)
    with open(tmp_path / "py" / "summary.json") as f:
        assert_close(json.load(f)["heating"], expected["heating"], "heating")
    # solve_config reads [heating] as the command does.
    from_config = vs.solve_config(config, backend="cpu")
    assert_close(from_config.heating, expected["heating"], "heating")
    assert np.array_equal(from_config.temperature_rise, cli_rise)
    assert "heated to T_eff" in repr(heated)


def test_the_heated_friction_is_the_isothermal_friction_at_t_eff(cell, wlf_rubber, heated):
    """``mu_heated(v, T0) = mu(v, T_eff)`` (issue #40's target 1e-9): an
    independent isothermal solve at the reported temperature, from no warm
    start, to the solver's tolerance (1e-11 on the residual)."""
    t_eff = heated.heating["effective_temperature"]
    loading = dict(LOADING, temperature=t_eff)
    iso = vs.solve(cell, wlf_rubber, **loading, formulation="periodic", tolerance=1e-11, backend="cpu")
    assert iso.heating is None and iso.temperature_rise is None and iso.temperature_depth is None
    assert abs(heated.friction_coefficient / iso.friction_coefficient - 1) <= 1e-9


def test_heat_of_the_answer_is_its_fixed_point(heated):
    """``Result.heat`` of the heated answer (its solution at T_eff, the same
    thermal properties and block) is the fixed point's evaluation at
    T_eff: its source-weighted rise is ``Theta(T_eff)``, the report's
    effective rise (1e-12 relative: the same computation), its surface map
    the result's, element by element; the
    energy balance of the volume source with the default layers holds to
    1e-3 (issue #40), and the refined layers' to 1e-6."""
    h = heated.heating
    heat = heated.heat(0.25, 1e-7, block_length=0.05)
    assert heat["source"] == "volume"
    assert math.isclose(heat["effective_rise_k"], h["temperature_rise"]["effective"], rel_tol=1e-12)
    assert np.array_equal(heat["temperature_rise"], heated.temperature_rise)
    assert abs(heat["energy_balance"]) <= 1e-3
    assert math.isclose(heat["heat_total_w"], h["heat_total_w"], rel_tol=1e-12)
    refined = heated.heat(0.25, 1e-7, block_length=0.05, refined_layers=True)
    assert abs(refined["energy_balance"]) <= 1e-6
    # The surface source: its own balance against the stencil's friction
    # power (the work of the pressure, exact up to rounding).
    surface = heated.heat(0.25, 1e-7, block_length=0.05, source="surface")
    assert surface["source"] == "surface" and abs(surface["energy_balance"]) <= 1e-9
    # The surface source has no depth layers to refine.
    with pytest.raises(ValueError, match="surface source has none"):
        heated.heat(0.25, 1e-7, block_length=0.05, source="surface", refined_layers=True)


def test_heat_of_an_isothermal_pad_is_its_surface_work(pad, rubber):
    """On a pad the heat of a solution takes the surface source by default,
    and its rise grows with the friction power: halving the conductivity
    doubles it (the steady moving-source problem is linear in 1/lam at a
    fixed diffusivity), cell by cell to rounding."""
    result = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
    a = result.heat(0.25, 1e-7)
    b = result.heat(0.125, 1e-7)
    assert a["source"] == "surface" and a["background_rise_k"] is None
    assert a["temperature_rise"].shape == result.pressure.shape
    assert a["max_rise_k"] > 0
    np.testing.assert_allclose(b["temperature_rise"], 2 * a["temperature_rise"], rtol=1e-12, atol=0)
    # Named by its argument, as the command line names --block-length.
    with pytest.raises(ValueError, match="block_length is for a periodic cell"):
        result.heat(0.25, 1e-7, block_length=0.05)
    with pytest.raises(ValueError, match="volume"):
        result.heat(0.25, 1e-7, source="volume")
    with pytest.raises(ValueError, match="conductivity"):
        result.heat(-1.0, 1e-7)


@pytest.mark.parametrize(
    "change, words",
    [
        ({"heating": dict(HEATING, conductivity=-1.0)}, "[heating] conductivity = -1 W/(m K) must be positive"),
        ({"heating": dict(HEATING, conductivity=float("nan"))}, "heating['conductivity'] must be finite"),
        ({"heating": dict(HEATING, colour="red")}, "heating: unknown field `colour`"),
        ({"heating": dict(HEATING, conductivity="0.25")}, "heating: key `conductivity`: invalid type"),
        ({"heating": dict(HEATING, source="bogus")}, '[heating] source = "bogus"'),
        ({"heating": dict(HEATING, branch="warm")}, '[heating] branch = "warm"'),
        ({"heating": dict(HEATING, closure="per_scale")}, '[heating] closure = "per_scale"'),
        ({"heating": dict(HEATING, density=1100.0, specific_heat=2000.0)}, "not both"),
        ({"heating": {"conductivity": 0.25, "diffusivity": 1e-7}}, "[heating] block_length (m) is needed"),
        ({"heating": {"diffusivity": 1e-7, "block_length": 0.05}}, "needs conductivity"),
        ({"heating": dict(HEATING, max_rise=0.0)}, "[heating] max_rise = 0 K"),
        ({"temperature": None}, "needs [loading] temperature"),
        ({"formulation": "nonperiodic"}, "block_length applies to periodic cells"),
        ({"heating": dict(HEATING, block_length=1e-4)}, "shorter than the periodic cell"),
    ],
)
def test_bad_heating_is_refused_before_solving(cell, wlf_rubber, change, words):
    """Every refusal one line naming the key (and value), the library's
    message, before any iteration (the progress callback never called)."""
    calls = []
    args = dict(LOADING, formulation="periodic", heating=HEATING, progress=calls.append, backend="cpu")
    args.update(change)
    with pytest.raises(ValueError) as e:
        vs.solve(cell, wlf_rubber, **args)
    message = str(e.value)
    assert words in message and "\n" not in message, message
    assert calls == []


def test_a_heated_solves_progress_names_its_evaluations(cell, wlf_rubber, heated):
    """Each iteration of a heated solve carries the stage it belongs to:
    the evaluations in order, each an isothermal solve, as many as the
    report counts; an isothermal solve's iterations carry no stage."""
    calls = []
    r = vs.solve(cell, wlf_rubber, **LOADING, formulation="periodic", tolerance=1e-11, heating=HEATING, backend="cpu", progress=calls.append)
    assert r.heating == heated.heating | {k: r.heating[k] for k in ("wall_time_s", "solve_time_s", "heat_time_s")}
    stages = [c["stage"] for c in calls]
    assert stages[0] == "heated: evaluation 1 at 17.0000 C: isothermal solve", stages[0]
    distinct = list(dict.fromkeys(stages))
    assert all(s.startswith("heated: evaluation ") and s.endswith(": isothermal solve") for s in distinct), distinct
    assert len(distinct) == r.heating["fixed_point_evaluations"], distinct
    assert [int(s.split()[2]) for s in distinct] == list(range(1, len(distinct) + 1))
    iso = []
    vs.solve(cell, wlf_rubber, **LOADING, formulation="periodic", backend="cpu", progress=iso.append)
    assert iso and all("stage" not in c for c in iso)


def test_a_disabled_heating_still_checks_its_keys(cell, wlf_rubber):
    """``enabled=False`` is the isothermal solve, but its keys are the
    heated points' too: a wrong value is refused, naming it, before any
    iteration, not carried unnoticed."""
    calls = []
    args = dict(LOADING, formulation="periodic", progress=calls.append, backend="cpu")
    with pytest.raises(ValueError, match=r"\[heating\] conductivity = -1 W/\(m K\) must be positive"):
        vs.solve(cell, wlf_rubber, **args, heating=dict(HEATING, conductivity=-1.0, enabled=False))
    with pytest.raises(ValueError, match=r'\[heating\] source = "bogus"'):
        vs.sweep(
            cell,
            wlf_rubber,
            speed=[0.01, 0.1],
            mean_pressure=1e6,
            temperature=17.0,
            formulation="periodic",
            heating=dict(HEATING, source="bogus"),
            vary={"heating.enabled": [False]},
            progress=calls.append,
        )
    assert calls == []
    # Without what only the heated solve needs, a disabled section is fine.
    iso = vs.solve(cell, wlf_rubber, **dict(args, progress=None), heating={"enabled": False})
    assert iso.heating is None


def test_at_rest_the_heated_answer_is_the_isothermal_one(cell, wlf_rubber):
    """``speed=0``: nothing is dissipated; the answer is the isothermal solve
    at T0 with every rise zero, and says so."""
    rest = dict(LOADING, speed=0.0)
    heated = vs.solve(cell, wlf_rubber, **rest, formulation="periodic", heating=HEATING, backend="cpu")
    iso = vs.solve(cell, wlf_rubber, **rest, formulation="periodic", backend="cpu")
    h = heated.heating
    assert h["effective_temperature"] == 17.0 and h["temperature_rise"]["effective"] == 0.0
    assert heated.friction_coefficient == iso.friction_coefficient
    assert not heated.temperature_rise.any()
    assert any(w.startswith("at rest") for w in heated.summary["warnings"])


def test_heat_of_a_layer_takes_the_surface_source_and_warns_as_the_heated_solve(cell, wlf_rubber):
    """On a layer ``Result.heat`` defaults to the surface work (as
    ``[heating]`` and ``heat --from-run`` do: the volume source is the
    half-space's, refused naming ``source="surface"``), and warns where the
    heat reaches through the layer with the heated solve's own warning (a
    50 um layer, heat reaching 2.24e-4 m in one passage of the block)."""
    layer = dict(LOADING, mean_pressure=1e5, formulation="periodic", thickness=5e-5, backend="cpu")
    heated = vs.solve(cell, wlf_rubber, **layer, heating=HEATING)
    expected = [w for w in heated.summary["warnings"] if w.startswith("the heat problem is a rubber half-space")]
    assert len(expected) == 1 and "2.236e-4 m deep" in expected[0], heated.summary["warnings"]
    with pytest.warns(UserWarning) as record:
        heat = heated.heat(0.25, 1e-7, block_length=0.05)
    assert heat["source"] == "surface"
    assert expected[0] in heat["notes"]
    assert expected[0] in [str(w.message) for w in record]
    with pytest.raises(ValueError) as e:
        heated.heat(0.25, 1e-7, block_length=0.05, source="volume")
    assert 'source="volume"' in str(e.value) and 'pass source="surface"' in str(e.value), str(e.value)


def test_heat_at_rest_is_zero_with_the_heated_solves_note(cell, wlf_rubber):
    """A solution at rest (``speed=0``) has no heat: ``Result.heat`` answers
    zero rise everywhere and a zero balance, with the at-rest note warned
    (as the heated solve at rest, and ``heat --from-run``), instead of
    refusing the speed."""
    rest = vs.solve(cell, wlf_rubber, **dict(LOADING, speed=0.0), formulation="periodic", backend="cpu")
    with pytest.warns(UserWarning, match=r"^at rest \(speed = 0\) nothing is dissipated"):
        heat = rest.heat(0.25, 1e-7, block_length=0.05)
    assert heat["source"] == "volume"
    for key in ("max_rise_k", "effective_rise_k", "background_rise_k", "heat_total_w", "friction_power_w", "energy_balance"):
        assert heat[key] == 0.0, key
    assert heat["temperature_rise"].shape == (32, 32) and not heat["temperature_rise"].any()


def test_heating_needs_wlf_and_a_mapping(cell):
    plain = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=1e-4)
    with pytest.raises(ValueError, match=r"\[heating\] needs the material's WLF constants"):
        vs.solve(cell, plain, speed=0.1, mean_pressure=1e6, formulation="periodic", heating=HEATING)
    with pytest.raises(TypeError, match="heating must be a dict"):
        vs.solve(cell, plain, speed=0.1, mean_pressure=1e6, heating=0.25)
    with pytest.raises(TypeError, match="a key is a"):
        vs.solve(cell, plain, speed=0.1, mean_pressure=1e6, heating={1: 0.25})


def test_a_heating_key_given_as_none_takes_its_default(cell, wlf_rubber, heated):
    """``None`` for a key of ``heating=`` is the key left out, as ``None``
    is for every other argument (before: ``heating['enabled'] must be a
    real number, got None``, a boolean key called a number); a pad takes
    ``block_length=None`` as no block."""
    args = dict(LOADING, formulation="periodic", tolerance=1e-11, backend="cpu")
    same = vs.solve(cell, wlf_rubber, **args, heating=dict(HEATING, enabled=None, source=None, max_rise=None))
    assert same.heating["effective_temperature"] == heated.heating["effective_temperature"]
    assert same.friction_coefficient == heated.friction_coefficient
    pad = dict(args, formulation="nonperiodic")
    h = vs.solve(cell, wlf_rubber, **pad, heating=dict(conductivity=0.25, diffusivity=1e-7, block_length=None))
    assert h.heating is not None and h.heating["effective_temperature"] > 17.0
    with pytest.raises(ValueError, match=r"\[heating\] needs conductivity"):
        vs.solve(cell, wlf_rubber, **args, heating=dict(HEATING, conductivity=None))


def test_sweep_with_and_without_heating(cell, wlf_rubber, heated):
    """``vary={"heating.enabled": [False, True]}``: each speed isothermal
    and heated, as ``viscoslide sweep`` does; the heated point is the heated
    solve (the same numbers as ``vs.solve``: same computation, 1e-12), the
    isothermal point the first evaluation of it (the solve at T0 from no
    warm start, identical: 1e-12)."""
    columns = vs.friction_curve(
        cell,
        wlf_rubber,
        [0.1],
        mean_pressure=1e6,
        temperature=17.0,
        formulation="periodic",
        tolerance=1e-11,
        heating=HEATING,
        vary={"heating.enabled": [False, True]},
        backend="cpu",
    )
    assert set(vs.HEATING_COLUMNS) <= set(columns)
    assert list(columns["heating.enabled"]) == [False, True]
    cold, hot = 0, 1
    for c in vs.HEATING_COLUMNS:
        assert np.isnan(columns[c][cold]), c
    h = heated.heating
    assert math.isclose(columns["friction_coefficient"][hot], heated.friction_coefficient, rel_tol=1e-12)
    assert math.isclose(columns["effective_temperature"][hot], h["effective_temperature"], rel_tol=1e-12)
    assert math.isclose(columns["temperature_rise"][hot], h["temperature_rise"]["effective"], rel_tol=1e-12)
    assert math.isclose(columns["peak_surface_rise"][hot], h["temperature_rise"]["peak_surface"], rel_tol=1e-12)
    assert columns["branches"][hot] == len(h["branches"])
    assert columns["fixed_point_evaluations"][hot] == h["fixed_point_evaluations"]
    assert math.isclose(
        columns["isothermal_friction_coefficient"][hot], columns["friction_coefficient"][cold], rel_tol=1e-12
    )


def test_sweep_refuses_bad_heating_before_solving(cell, wlf_rubber):
    calls = []
    common = dict(mean_pressure=1e6, temperature=17.0, formulation="periodic", progress=calls.append)
    with pytest.raises(ValueError, match=r"\[heating\] conductivity = -1"):
        vs.sweep(cell, wlf_rubber, speed=[0.01, 0.1], heating=dict(HEATING, conductivity=-1.0), **common)
    # The heated combination lacks the thermal properties: named with its value.
    with pytest.raises(ValueError, match=r'"heating.enabled" = true: .*needs conductivity'):
        vs.sweep(cell, wlf_rubber, speed=[0.01, 0.1], vary={"heating.enabled": [False, True]}, **common)
    with pytest.raises(ValueError, match="both set it"):
        vs.sweep(
            cell,
            wlf_rubber,
            speed=[0.1],
            heating=dict(HEATING, enabled=True),
            vary={"heating.enabled": [False, True]},
            **common,
        )
    # A pad's heat problem depends on the speed: the last speed's cell
    # Peclet number is past the pad's limit, refused before the first
    # speed is solved.
    pad = dict(common, formulation="nonperiodic")
    pad_heating = dict(conductivity=0.25, diffusivity=1e-7)
    with pytest.raises(ValueError, match=r"\[heating\] the cell Peclet number"):
        vs.sweep(cell, wlf_rubber, speed=[0.1, 1e9], heating=pad_heating, **pad)
    assert calls == []
