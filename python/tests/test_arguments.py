"""Python refuses what the command line refuses: every public function's
arguments are checked before anything is solved or written, a boolean, a
string or NaN where a number is expected is a ValueError, a string, path
or flag of the wrong type a TypeError, and every message is one line
naming the argument and the bad value."""

import math

import numpy as np
import pytest

import viscoslide as vs

STUDY = """
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
q1 = 5026.548245743669
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3.0e3
speed = 0.01
"""

NAN = math.nan


@pytest.fixture()
def study(tmp_path):
    p = tmp_path / "study.toml"
    p.write_text(STUDY)
    return p


@pytest.fixture(scope="module")
def small():
    return vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, seed=3)


def refused(call, kind, *needles):
    """``call()`` raises ``kind`` in one line that holds every needle."""
    with pytest.raises(kind) as e:
        call()
    message = str(e.value)
    assert type(e.value) is kind or kind is Exception, f"{type(e.value).__name__}: {message}"
    assert "\n" not in message, message
    for needle in needles:
        assert needle in message, f"{needle!r} not in {message!r}"
    return message


@pytest.mark.parametrize(
    "kwargs, kind, needles",
    [
        ({"q1": [NAN, 3e3]}, ValueError, ("q1[0]", "nan")),
        ({"q1": "abc"}, ValueError, ("q1", "'abc'")),
        ({"q1": [1e3, True]}, ValueError, ("q1[1]", "True")),
        ({"scales": [2, "4"]}, ValueError, ("scales[1]", "'4'")),
        ({"scales": [2, 4], "speed": True}, ValueError, ("speed", "True")),
        ({"scales": [2, 4], "speed": NAN}, ValueError, ("speed", "nan")),
        ({"scales": [2, 4], "speeds": [1e-2, "fast"]}, ValueError, ("speeds[1]", "'fast'")),
        ({"scales": [2, 4], "cells_per_wavelength": "4"}, ValueError, ("cells_per_wavelength", "'4'")),
        ({"scales": [2, 4], "cells_per_wavelength": True}, ValueError, ("cells_per_wavelength", "True")),
        ({"scales": [2, 4], "shard": 1}, TypeError, ("shard", "1")),
        ({"scales": [2, 4], "shard": "1"}, ValueError, ("shard", "'1'")),
        ({"scales": [2, 4], "backend": 1}, TypeError, ("backend", "1")),
        ({"scales": [2, 4], "set": 3}, TypeError, ("set", "3")),
        ({"scales": [2, 4], "set": "loading.speed"}, ValueError, ("set", "'loading.speed'")),
        ({"scales": [2, 4], "set": {"loading.speed": NAN}}, ValueError, ("set 'loading.speed'", "nan")),
        ({"scales": [2, 4], "set": "loading.colour=1.0"}, ValueError, ("set 'loading.colour=1.0'", "colour")),
        ({"scales": [2, 4], "as_frame": "yes"}, TypeError, ("as_frame", "'yes'")),
    ],
)
def test_magnification_refuses_bad_arguments_before_writing(study, tmp_path, kwargs, kind, needles):
    out = tmp_path / "out"
    refused(lambda: vs.magnification(study, out=out, **kwargs), kind, *needles)
    assert not out.exists()


def test_magnification_takes_set_as_the_command_line_writes_it(study):
    one = vs.magnification(study, scales=[2, 4], set="loading.speed=0.02", backend="cpu")
    many = vs.magnification(study, scales=[2, 4], set=["loading.speed=0.02"], backend="cpu")
    mapping = vs.magnification(study, scales=[2, 4], set={"loading.speed": 0.02}, backend="cpu")
    assert one["speed"].tolist() == [0.02, 0.02]
    assert one["friction_coefficient"].tolist() == many["friction_coefficient"].tolist()
    assert one["friction_coefficient"].tolist() == mapping["friction_coefficient"].tolist()
    refused(lambda: vs.magnification(3, scales=[2, 4]), TypeError, "config", "3")


@pytest.mark.parametrize(
    "kwargs, kind, needles",
    [
        ({"speed": True}, ValueError, ("speed", "True")),
        ({"speed": "0.01"}, ValueError, ("speed", "'0.01'")),
        ({"speed": NAN}, ValueError, ("speed", "nan")),
        ({"mean_pressure": True}, ValueError, ("mean_pressure", "True")),
        ({"temperature": "20"}, ValueError, ("temperature", "'20'")),
        ({"direction_deg": NAN}, ValueError, ("direction_deg", "nan")),
        ({"tolerance": True}, ValueError, ("tolerance", "True")),
        ({"max_iterations": "4"}, ValueError, ("max_iterations", "'4'")),
        ({"max_matvecs": 2.5}, ValueError, ("max_matvecs", "2.5")),
        ({"thickness": "1e-3"}, ValueError, ("thickness", "'1e-3'")),
        ({"thickness": 1e-3, "layer_base": "glued"}, ValueError, ("layer_base", "'glued'")),
        ({"layer_base": 5}, TypeError, ("layer_base", "5")),
        ({"formulation": 1}, TypeError, ("formulation", "1")),
        ({"formulation": "sideways"}, ValueError, ("formulation", "'sideways'")),
        ({"mesh": 1}, TypeError, ("mesh", "1")),
        ({"mesh": "hexagonal"}, ValueError, ("mesh", "hexagonal")),
        ({"precision": "f16"}, ValueError, ("precision", "'f16'")),
        ({"backend": 1}, TypeError, ("backend", "1")),
        ({"backend": "tpu"}, ValueError, ("backend", "'tpu'")),
        ({"progress": "yes"}, TypeError, ("progress", "'yes'")),
    ],
)
def test_solve_refuses_bad_arguments(small, rubber, kwargs, kind, needles):
    args = {"speed": 0.01, "mean_pressure": 3000.0, **kwargs}
    refused(lambda: vs.solve(small, rubber, **args), kind, *needles)


@pytest.mark.parametrize(
    "kwargs, kind, needles",
    [
        ({"speed": True}, ValueError, ("speed", "True")),
        ({"speed": [0.01, True]}, ValueError, ("speed[1]", "True")),
        ({"speed": "abc"}, ValueError, ("speed", "'abc'")),
        ({"speed": [NAN]}, ValueError, ("speed[0]", "nan")),
        ({"speed": np.array([0.01, np.inf])}, ValueError, ("speed[1]", "inf")),
        ({"speed": np.ones((2, 2))}, ValueError, ("speed", "(2, 2)")),
        ({"mean_pressure": [3000.0, False]}, ValueError, ("mean_pressure[1]", "False")),
        ({"mean_pressure": -1.0}, ValueError, ("mean_pressure", "-1")),
        ({"temperature": True}, ValueError, ("temperature", "True")),
        ({"tolerance": NAN}, ValueError, ("tolerance", "nan")),
        ({"as_frame": "yes"}, TypeError, ("as_frame", "'yes'")),
        ({"progress": 3}, TypeError, ("progress", "3")),
        ({"vary": 3}, TypeError, ("vary", "int")),
        ({"vary": {"loading.direction_deg": [NAN]}}, ValueError, ("loading.direction_deg", "NaN")),
        ({"vary": {"loading.direction_deg": [True]}}, ValueError, ("direction_deg", "true")),
        ({"vary": {"loading.direction_deg": ["10"]}}, ValueError, ("direction_deg", '"10"')),
        ({"vary": {"solver.tolerance": [1e-9]}, "tolerance": 1e-6}, ValueError, ("solver.tolerance", "tolerance")),
        ({"tolerence": 1e-6}, TypeError, ("sweep()", "'tolerence'")),
    ],
)
def test_sweep_refuses_bad_arguments_before_any_solve(small, rubber, kwargs, kind, needles):
    seen = []
    args = {"speed": 0.01, "mean_pressure": 3000.0, "backend": "cpu", **kwargs}
    if "progress" not in kwargs:
        args["progress"] = seen.append
    refused(lambda: vs.sweep(small, rubber, **args), kind, *needles)
    assert seen == []


@pytest.mark.parametrize(
    "call, kind, needles",
    [
        (lambda s, m: vs.friction_curve(s, m, True, mean_pressure=3000.0), ValueError, ("speeds", "True")),
        (lambda s, m: vs.friction_curve(s, m, [0.01, NAN], mean_pressure=3000.0), ValueError, ("speeds[1]", "nan")),
        (lambda s, m: vs.friction_curve(s, m, [0.01], mean_pressure="3e3"), ValueError, ("mean_pressure", "'3e3'")),
        (lambda s, m: vs.friction_curve(s, m, [0.01], mean_pressure=3e3, as_frame=1), TypeError, ("as_frame", "1")),
        (lambda s, m: vs.friction_curve(s, m, [0.01], mean_pressure=3e3, tolerence=1e-6), TypeError, ("friction_curve()", "'tolerence'")),
        (lambda s, m: vs.friction_curve(s, m, mean_pressure=3e3, speed=[0.01]), TypeError, ("friction_curve()", "'speed'", "speeds")),
        (lambda s, m: vs.friction_curve(s, m, [0.01], mean_pressure=3e3, vary={"solver.tolerance": [NAN]}), ValueError, ("solver.tolerance", "NaN")),
        (lambda s, m: vs.persson(s, m, True, mean_pressure=3000.0), ValueError, ("speeds", "True")),
        (lambda s, m: vs.persson(s, m, ["fast"], mean_pressure=3000.0), ValueError, ("speeds[0]", "'fast'")),
        (lambda s, m: vs.persson(s, m, [0.01], mean_pressure=NAN), ValueError, ("mean_pressure", "nan")),
        (lambda s, m: vs.persson(s, m, [0.01]), ValueError, ("exactly one of normal_load (N) and mean_pressure (Pa)",)),
        (lambda s, m: vs.persson(s, m, [0.01], normal_load=0.3, mean_pressure=3e3), ValueError, ("exactly one of normal_load",)),
        (lambda s, m: vs.persson(s, m, [0.01], mean_pressure=3e3, temperature=True), ValueError, ("temperature", "True")),
        (lambda s, m: vs.persson(s, m, [0.01], mean_pressure=3e3, window=5), TypeError, ("window", "5")),
        (lambda s, m: vs.persson(s, "rubber", [0.01], mean_pressure=3e3), TypeError, ("material", "str")),
        (lambda s, m: vs.kernel_table(m, nx=True, cell_size=1e-4, speed=0.01), ValueError, ("nx", "True")),
        (lambda s, m: vs.kernel_table(m, nx=8, cell_size=1e-4, speed=0.01, derivative="yes"), TypeError, ("derivative", "'yes'")),
        (lambda s, m: vs.kernel_table(m, nx=8, cell_size=1e-4, speed=NAN), ValueError, ("speed", "nan")),
    ],
)
def test_curves_refuse_bad_arguments(small, rubber, call, kind, needles):
    refused(lambda: call(small, rubber), kind, *needles)


@pytest.mark.parametrize(
    "call, kind, needles",
    [
        (lambda s: s.psd(window=5), TypeError, ("window", "5")),
        (lambda s: s.psd(window="triangle"), ValueError, ("triangle",)),
        (lambda s: s.stats(window=5), TypeError, ("window", "5")),
        (lambda s: vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, anisotropy=2.0), ValueError, ("anisotropy", "2.0")),
        (lambda s: vs.Surface.self_affine(32, 0.01, True, scales=4, rms_slope=0.02), ValueError, ("hurst", "True")),
        (lambda s: vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=NAN), ValueError, ("rms_slope", "nan")),
        (lambda s: vs.Surface.generate(n="32", length=0.01, hurst=0.8, scales=4, rms_slope=0.02), ValueError, ("`n`", '"32"')),
        (lambda s: vs.Surface.generate(n=32, length=0.01, hurst=0.8, scales=4, rms_slope=NAN), ValueError, ("rms_slope", "nan")),
        (lambda s: vs.Surface.from_array(np.zeros((4, 4)), 0.01, periodic="yes"), TypeError, ("periodic", "'yes'")),
        (lambda s: vs.Surface.from_array(np.zeros((4, 4)), 0.01, fill_missing=1), TypeError, ("fill_missing", "1")),
        (lambda s: vs.Surface.from_array(np.zeros((4, 4)), 0.01, detrend=2), TypeError, ("detrend", "2")),
        (lambda s: vs.Surface.from_array(np.zeros((4, 4)), True), ValueError, ("length", "True")),
        (lambda s: vs.Surface.from_file(3, 0.01), TypeError, ("path", "3")),
        (lambda s: vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=3e6, creep_time=0.01, wlf=8.86), ValueError, ("wlf", "8.86")),
        (lambda s: vs.Material.sls(relaxed_modulus=1e6, glassy_modulus=3e6, creep_time=0.01, wlf=(8.86, 101.6, NAN)), ValueError, ("wlf[2]", "nan")),
        (lambda s: vs.Material.sls(relaxed_modulus=True, glassy_modulus=3e6, creep_time=0.01), ValueError, ("relaxed_modulus", "True")),
        (lambda s: vs.Material.sls(relaxed_modulus=1e6, glassy_modulus="3e6", creep_time=0.01), ValueError, ("glassy_modulus", "'3e6'")),
        (lambda s: vs.Material.fit_dma([1.0, 10.0], [1e6, 2e6], [1e5, 2e5], wlf=8.86), ValueError, ("wlf", "8.86")),
        (lambda s: vs.Material.fit_dma([1.0, 10.0], [1e6, 2e6], [1e5, 2e5], angular="yes"), TypeError, ("angular", "'yes'")),
        (lambda s: vs.Material.fit_dma([1.0, 10.0], [1e6, 2e6], [1e5, 2e5], terms=True), ValueError, ("terms", "True")),
        (lambda s: vs.Material.fit_dma([1.0, -10.0, 100.0], [1e6, 2e6, 3e6], [1e5, 2e5, 3e5]), ValueError, ("point 1", "angular frequency", "must be positive")),
        (lambda s: vs.Material.fit_dma([1.0, 10.0, 100.0], [1e6, 2e6, 3e6], [1e5, 0.0, 3e5]), ValueError, ("point 1", "E2 = 0")),
        (lambda s: vs.Material.fit_dma([1.0, 10.0, 100.0], [1e6, 2e6, 3e6], [1e5, 2e5, 3e5], terms=1000), ValueError, ("terms = 1000", "decades")),
        (lambda s: vs.Material.from_toml(3), TypeError, ("path", "3")),
    ],
)
def test_surfaces_and_materials_refuse_bad_arguments(small, call, kind, needles):
    refused(lambda: call(small), kind, *needles)


def test_a_layer_base_without_a_layer_is_refused(small, rubber):
    refused(lambda: vs.solve(small, rubber, xi=1.17e-2, mean_pressure=3000.0, layer_base="frictionless"),
            ValueError, "layer_base='frictionless' needs thickness=")


def test_solve_config_refuses_bad_arguments(repo):
    cfg = repo / "configs" / "default.toml"
    refused(lambda: vs.solve_config(3), TypeError, "path", "3")
    refused(lambda: vs.solve_config(cfg, set=["loading.xi"]), ValueError, "set", "'loading.xi'")
    refused(lambda: vs.solve_config(cfg, set={"loading.xi": NAN}), ValueError, "set 'loading.xi'", "nan")
    refused(lambda: vs.solve_config(cfg, set={3: 1.0}), TypeError, "set", "3")
    refused(lambda: vs.solve_config(cfg, backend=1), TypeError, "backend", "1")
    refused(lambda: vs.solve_config(cfg, set="loading.colour=1.0"), ValueError, "set 'loading.colour=1.0'", "colour")


def test_result_write_names_its_directory(small, rubber):
    result = vs.solve(small, rubber, speed=0.01, mean_pressure=3000.0, backend="cpu")
    refused(lambda: result.write(3), TypeError, "directory", "3")
    refused(lambda: result.write(""), ValueError, "directory", "empty path")
    refused(lambda: vs.Surface.from_file(""), ValueError, "path", "empty path")
    refused(lambda: vs.solve_config(""), ValueError, "path", "empty path")


def test_result_write_to_a_file_says_it_is_a_file(small, rubber, tmp_path):
    result = vs.solve(small, rubber, speed=0.01, mean_pressure=3000.0, backend="cpu")
    taken = tmp_path / "taken"
    taken.write_text("keep")
    refused(lambda: result.write(taken), OSError, str(taken), "is a file, not a directory")
    refused(lambda: result.write(taken / "out"), OSError, str(taken), "not a directory")
    assert taken.read_text() == "keep"
