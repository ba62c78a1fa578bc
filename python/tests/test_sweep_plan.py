"""The Python sweep is planned by the command line's sweep planner: the
same points in the same order for a vary over two keys and speeds, the
same numbers, and a bad ``vary`` key refused with the command line's
message before anything is solved."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import viscoslide as vs
from viscoslide import _native

CONFIG = """
[material]
model = "sls"
relaxed_modulus = 3333333.3333333335
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4.0
rms_slope = 0.02
seed = 3

[loading]
normal_load = 0.3
speed = 0.05

[sweep]
speed = [0.05, 0.5]
include_static = false
normal_load = [0.3]

[sweep.vary]
"loading.direction_deg" = [0.0, 30.0]
"surface.generate.rms_slope" = [0.01, 0.02]
"""

VARY = {"surface.generate.rms_slope": [0.01, 0.02], "loading.direction_deg": [0.0, 30.0]}


@pytest.fixture(scope="module")
def pad():
    return vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, seed=3)


def binary(repo):
    path = os.environ.get("VISCOSLIDE_CLI") or str(repo / "target" / "release" / "viscoslide")
    if not os.path.exists(path):
        pytest.skip("the viscoslide binary is not built (cargo build --release)")
    return path


def test_python_and_the_command_line_plan_the_same_points(cli, tmp_path, pad, rubber):
    config = tmp_path / "sweep.toml"
    config.write_text(CONFIG)
    out = tmp_path / "out"
    cli("sweep", str(config), "--out", str(out), "--backend", "cpu")
    points = [json.loads(p.read_text()) for p in sorted((out / "points").glob("p*.json"))]
    assert len(points) == 8
    # The native planner's points are the command line's, field for field.
    plan = _native.SweepPlan(
        pad._native, rubber._native, "{}", "{}", None, None, "cpu", "speed", [0.05, 0.5], "normal_load", [0.3], list(VARY.items())
    )
    assert json.loads(plan.points_json()) == [p["point"] for p in points]
    # The sweep solves them in that order, with the command line's numbers.
    swept = vs.sweep(pad, rubber, speed=[0.05, 0.5], normal_load=0.3, vary=VARY, backend="cpu")
    assert swept["speed"].tolist() == [p["point"]["speed"]["speed"] for p in points]
    for key in VARY:
        assert swept[key].tolist() == [p["point"]["vary"][key] for p in points]
    assert swept["loading.direction_deg"].tolist() == [0.0, 0.0, 0.0, 0.0, 30.0, 30.0, 30.0, 30.0]
    assert swept["surface.generate.rms_slope"].tolist() == [0.01, 0.01, 0.02, 0.02] * 2
    for column in ("friction_coefficient", "contact_area_fraction"):
        for got, point in zip(swept[column], points):
            assert math.isclose(got, point[column], rel_tol=1e-12), (column, point["point"])


@pytest.mark.parametrize(
    "key, values",
    [
        ("loading.temprature", "[7.0]"),
        ("loading.speed", "[1.0]"),
        ("sweep.seeds", "[1]"),
        ("loading.direction_deg", "[10.0, 10]"),
        ("solver.mesh", '["uniform", "hexagonal"]'),
    ],
)
def test_a_bad_vary_is_refused_with_the_command_lines_message_before_any_solve(repo, tmp_path, pad, rubber, key, values):
    config = tmp_path / "sweep.toml"
    text = CONFIG.split("[sweep.vary]")[0] + f'[sweep.vary]\n"{key}" = {values}\n'
    config.write_text(text)
    env = dict(os.environ, VISCOSLIDE_BACKEND="cpu")
    run = subprocess.run(
        [binary(repo), "sweep", str(config), "--out", str(tmp_path / "out")], env=env, capture_output=True, text=True
    )
    assert run.returncode != 0 and not (tmp_path / "out").exists()
    expected = run.stderr.strip().splitlines()[-1]
    seen = []
    with pytest.raises(ValueError) as e:
        vs.sweep(pad, rubber, speed=[0.05, 0.5], normal_load=0.3, vary={key: json.loads(values)}, progress=seen.append)
    message = str(e.value)
    assert seen == [], "points were solved before the refusal"
    assert "\n" not in message and key in message
    # The same words after the file's (or sweep's) name.
    assert message.split("[sweep.vary]", 1)[1] == expected.split("[sweep.vary]", 1)[1], (message, expected)


def test_a_key_written_twice_is_refused_as_the_command_line_refuses_it(pad, rubber):
    seen = []
    with pytest.raises(ValueError, match=r'"loading.temperature" and "loading.temperature " are the same key') as e:
        vs.sweep(pad, rubber, speed=0.05, normal_load=0.3, progress=seen.append,
                 vary={"loading.temperature": [7.0], "loading.temperature ": [8.0]})
    assert seen == [] and "\n" not in str(e.value)


def test_any_key_of_the_sections_can_be_varied(pad, rubber):
    # A material key, a layer without a thickness argument, and q1 in place
    # of the surface's scales.
    out = vs.sweep(pad, rubber, speed=0.05, mean_pressure=3000.0, backend="cpu",
                   vary={"material.poisson": [0.45, 0.5], "layer.thickness": [1e-3], "surface.generate.q1": [2000.0]})
    assert out["material.poisson"].tolist() == [0.45, 0.5]
    cut = vs.Surface.self_affine(32, 0.01, 0.8, q1=2000.0, rms_slope=0.02, seed=3)
    one = vs.solve(cut, rubber, speed=0.05, mean_pressure=3000.0, thickness=1e-3, backend="cpu")
    assert out["friction_coefficient"][1] == one.friction_coefficient
    assert np.all(np.isfinite(out["friction_coefficient"]))


@pytest.mark.filterwarnings("ignore")
def test_list_valued_keys_are_object_columns(pad, rubber):
    # A creep spectrum of two rows and of one, WLF constants of three
    # numbers: one value per point, as a dict value is, in the dict and in
    # a DataFrame alike (not stacked, not refused after the solves).
    spectrum = vs.Material.creep_spectrum([1e-3, 1e-2], [1e-7, 2e-7], glassy_modulus=1e7)
    rows = [[[1e-7, 1e-3], [2e-7, 1e-2]], [[1e-7, 1e-3]]]
    wlf = [[8.86, 101.6, 17.0], [8.0, 100.0, 17.0]]
    cases = [
        (spectrum, {}, "material.creep_spectrum", rows),
        (rubber, {"temperature": 20.0}, "material.wlf", wlf),
    ]
    for material, options, key, values in cases:
        out = vs.sweep(pad, material, speed=[0.01, 0.1], mean_pressure=3e3, backend="cpu", vary={key: values}, **options)
        column = out[key]
        assert column.dtype == object and column.shape == (4,), key
        assert column.tolist() == [values[0], values[0], values[1], values[1]]
        assert np.all(np.isfinite(out["friction_coefficient"]))
        pandas = pytest.importorskip("pandas")
        frame = vs.sweep(pad, material, speed=[0.01, 0.1], mean_pressure=3e3, backend="cpu", vary={key: values}, as_frame=True, **options)
        assert isinstance(frame, pandas.DataFrame) and len(frame) == 4
        assert frame[key].tolist() == column.tolist()
        assert frame["friction_coefficient"].tolist() == out["friction_coefficient"].tolist()
