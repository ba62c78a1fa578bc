"""Errors are Python exceptions: ConvergenceError carries the history,
configuration mistakes are ValueErrors, missing files FileNotFoundErrors;
everything public has a docstring."""

import inspect

import pytest

import viscoslide as vs


def test_a_solve_that_does_not_converge_raises_with_its_history(pad, rubber):
    with pytest.raises(vs.ConvergenceError) as info:
        vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", max_iterations=1, cascade_levels=1)
    e = info.value
    assert isinstance(e, RuntimeError)
    assert e.iterations == 1 and len(e.history) == 1
    assert e.residual == e.history[-1] and e.matvecs > 0
    assert "no convergence" in str(e)


def test_configuration_errors(repo):
    with pytest.raises(ValueError, match="colour"):
        vs.solve_config(repo / "configs" / "default.toml", set={"loading.colour": 1.0}, backend="cpu")
    with pytest.raises(FileNotFoundError):
        vs.solve_config(repo / "configs" / "missing.toml")
    with pytest.raises(FileNotFoundError):
        vs.Surface.from_file(repo / "missing.x3p")


def test_huge_values_read_as_scientific_in_the_engines_messages(pad, rubber):
    """A value f64 writes out in full (1e300 as 301 digits) reads as
    1e300 in the engine's ValueError naming it."""
    for key, value in (("temperature", 1e300), ("tolerance", 1e300)):
        with pytest.raises(ValueError) as info:
            vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", **{key: value})
        message = str(info.value)
        assert "1e300" in message and len(message) < 250, message


def test_a_toml_file_without_material_is_named(tmp_path):
    path = tmp_path / "loading.toml"
    path.write_text("[loading]\nspeed = 1.0\n")
    with pytest.raises(ValueError, match=r"no \[material\] section"):
        vs.Material.from_toml(path)
    path.write_text('[material]\nmodel = "sls"\nrelaxed_modulus = 1e6\n')
    with pytest.raises(ValueError, match="glassy_modulus"):
        vs.Material.from_toml(path)


def test_public_api_is_documented():
    for name in vs.__all__:
        obj = getattr(vs, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            assert inspect.getdoc(obj), name
            for attr, member in vars(obj).items() if inspect.isclass(obj) else []:
                if not attr.startswith("_") and (inspect.isfunction(member) or isinstance(member, (property, classmethod))):
                    assert inspect.getdoc(getattr(obj, attr)), f"{name}.{attr}"


def test_repr(pad, rubber):
    r = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
    assert repr(r).startswith("Result(64 x 64, friction_coefficient=")
    assert "64 x 64 cells" in repr(pad)
    assert "creep term" in repr(rubber)


def test_a_layer_far_below_a_cell_raises_and_the_interpreter_lives_on(pad, rubber):
    # 1e-12 m on 156 um cells grew to 24 GB and killed the interpreter.
    with pytest.raises(ValueError, match=r"of a cell.*1e-3"):
        vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, thickness=1e-12, backend="cpu")
    # A bonded incompressible layer far below a cell: the thin-layer law.
    r = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, thickness=1e-6, backend="cpu")
    assert r.friction_coefficient > 0
    r = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, thickness=1e-6, layer_base="frictionless", backend="cpu")
    assert r.friction_coefficient > 0


def test_arguments_are_named_in_their_errors(pad, rubber):
    with pytest.raises(ValueError, match="speed must be a real number, got the boolean True"):
        vs.solve(pad, rubber, speed=True, normal_load=0.3, backend="cpu")
    with pytest.raises(ValueError, match=r"n = 1180591620717411303424 is too large"):
        vs.Surface.self_affine(2**70, 0.01, 0.8, scales=8, rms_slope=0.02)
    with pytest.raises(ValueError, match=r"seed = 1180591620717411303424 is too large"):
        vs.Surface.self_affine(64, 0.01, 0.8, scales=8, rms_slope=0.02, seed=2**70)
    tiny = vs.Surface.from_array([[0.0, 1e-6], [2e-6, 0.0]], 1e-3)
    with pytest.raises(ValueError, match=r"2 x 2 grid is too small"):
        vs.solve(tiny, rubber, speed=1e-3, normal_load=1e-6, backend="cpu")


def test_solve_config_takes_set_as_the_command_line_writes_it(repo):
    cfg = repo / "configs" / "default.toml"
    small = {"surface.generate.n": 32, "surface.generate.scales": 4, "surface.generate.rolloff_q0": 1000}
    a = vs.solve_config(cfg, set=small, backend="cpu")
    b = vs.solve_config(cfg, set=[f"{k}={v}" for k, v in small.items()], backend="cpu")
    assert a.friction_coefficient == b.friction_coefficient
    with pytest.raises(ValueError, match="colour"):
        vs.solve_config(cfg, set="loading.colour=1.0", backend="cpu")
    with pytest.raises(TypeError, match="set must be a mapping"):
        vs.solve_config(cfg, set=3, backend="cpu")


def test_a_topography_without_a_unit_is_taken_as_metres_with_a_warning():
    class Topo:
        physical_sizes = (0.01, 0.01)

        def heights(self):
            import numpy as np

            return np.random.default_rng(1).normal(size=(16, 16)) * 1e-6

    with pytest.warns(UserWarning, match="no unit"):
        vs.Surface.from_topography(Topo())


def test_numbers_beyond_a_float_and_progress_of_the_wrong_type_are_named(pad, rubber):
    """A whole number beyond a double (``10**400``) is a ValueError naming
    its argument (it was an OverflowError without a name), as any number
    out of range; ``progress`` of the wrong type is a TypeError (it was a
    ValueError)."""
    with pytest.raises(ValueError, match=r"^speed is out of the range of a float .*401 digits"):
        vs.solve(pad, rubber, speed=10**400, normal_load=0.3, backend="cpu")
    with pytest.raises(ValueError, match=r"^speeds\[1\] is out of the range of a float"):
        vs.friction_curve(pad, rubber, [1e-2, -(10**400)], normal_load=0.3, backend="cpu")
    for bad in (1, "yes", 0.5):
        with pytest.raises(TypeError, match=f"progress must be None, True or a callable, got {bad!r}"):
            vs.solve(pad, rubber, speed=1e-2, normal_load=0.3, backend="cpu", progress=bad)
        with pytest.raises(TypeError, match="progress must be None, True or a callable"):
            vs.friction_curve(pad, rubber, [1e-2], normal_load=0.3, backend="cpu", progress=bad)


def test_decimals_are_taken_as_fractions_are(pad, rubber):
    """A ``Decimal`` (as read from a CSV file or a database) is a real
    number, rounded to a double as a ``Fraction`` is; it was refused as
    "must be a real number" while a ``Fraction`` was taken. Its NaN and
    infinity are refused as a float's."""
    from decimal import Decimal
    from fractions import Fraction

    by_float = vs.solve(pad, rubber, speed=0.01, normal_load=0.3, backend="cpu")
    for speed in (Decimal("0.01"), Fraction(1, 100)):
        r = vs.solve(pad, rubber, speed=speed, normal_load=Decimal("0.3"), backend="cpu")
        assert r.friction_coefficient == by_float.friction_coefficient
    curve = vs.friction_curve(pad, rubber, [Decimal("0.01")], normal_load=0.3, backend="cpu")
    assert curve["friction_coefficient"][0] == by_float.friction_coefficient
    for bad, words in (
        (Decimal("NaN"), "speed must be finite"),
        (Decimal("Infinity"), "speed must be finite"),
        (Decimal("sNaN"), "speed must be a number, got the signalling NaN"),
    ):
        with pytest.raises(ValueError, match=words):
            vs.solve(pad, rubber, speed=bad, normal_load=0.3, backend="cpu")
