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
