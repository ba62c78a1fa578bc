"""solve_config gives what `viscoslide solve` gives: the same summary
(numbers to 1e-12 relative, everything else equal; timings excepted) and
identical maps."""

import json
import math

import numpy as np
import pytest

import viscoslide as vs

#: Keys that measure the run (wall-clock time, memory), not results, at any
#: depth (`time_s`: the smooth-pad solve's and the GPU stages' times;
#: `solve_time_s`, `heat_time_s`: the heated solve's split).
TIMES = {"wall_time_s", "timings", "time_s", "solve_time_s", "heat_time_s", "peak_memory_bytes"}


def assert_close(a, b, path="summary"):
    if isinstance(a, dict):
        assert set(a) == set(b), f"{path}: keys differ: {set(a) ^ set(b)}"
        for k in a:
            if k not in TIMES:
                assert_close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            assert_close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0) or a == b, f"{path}: {a} != {b}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.mark.parametrize(
    "overrides",
    [
        {},
        {"loading.xi": 1e-3, "surface.generate.n": 64, "solver.formulation": "periodic"},
        {"surface.generate.n": 64, "solver.precision": "mixed"},
    ],
    ids=["default", "set", "mixed"],
)
def test_solve_config_equals_the_command_line(cli, repo, tmp_path, overrides):
    config = repo / "configs" / "default.toml"
    sets = [a for k, v in overrides.items() for a in ("--set", f"{k}={json.dumps(v)}")]
    cli("solve", str(config), "--backend", "cpu", "--out", str(tmp_path), *sets)
    with open(tmp_path / "summary.json") as f:
        expected = json.load(f)
    result = vs.solve_config(config, set=overrides, backend="cpu")
    for key in ("friction_coefficient", "friction_coefficient_dissipation", "contact_area_fraction", "approach"):
        assert math.isclose(result.summary[key], expected[key], rel_tol=1e-12), key
    assert math.isclose(result.friction_coefficient, expected["friction_coefficient"], rel_tol=1e-12)
    assert math.isclose(result.contact_area_fraction, expected["contact_area_fraction"], rel_tol=1e-12)
    assert math.isclose(result.approach, expected["approach"], rel_tol=1e-12)
    assert_close(result.summary, expected)
    for name in ("pressure", "contact", "gap", "displacement"):
        assert np.array_equal(getattr(result, name), np.load(tmp_path / f"{name}.npy")), name
    with open(tmp_path / "analysis.json") as f:
        assert_close(result.analysis(), json.load(f), "analysis")


def test_relative_paths_resolve_against_the_config(repo, tmp_path, monkeypatch):
    """A config naming a file relative to itself works from any directory."""
    monkeypatch.chdir(tmp_path)
    m = vs.Material.from_toml(repo / "configs" / "material_sbr_like.toml")
    assert len(m.creep_spectrum_terms) > 10
    assert m.section["file"].startswith(str(repo))


def test_write_produces_the_command_line_files(repo, tmp_path):
    result = vs.solve_config(repo / "configs" / "default.toml", set={"surface.generate.n": 64}, backend="cpu")
    written = result.write(tmp_path / "out")
    names = {p.rsplit("/", 1)[-1] for p in written}
    assert {"summary.json", "pressure.npy", "contact.npy", "analysis.json"} <= names
    assert np.array_equal(np.load(tmp_path / "out" / "pressure.npy"), result.pressure)


def test_mixed_precision_matches_f64(pad, rubber):
    """``precision="mixed"`` (f32 Krylov products, f64 refinement) gives the
    f64 answer of the f32-rounded operator: friction and area within 1e-6
    (tests/solver/mixed_precision.rs pins the same on more cases), the same contact
    set, and says so in the summary; a bad name is refused."""
    kw = dict(xi=1.17e-2, normal_load=0.3, backend="cpu", tolerance=1e-10)
    f = vs.solve(pad, rubber, **kw)
    m = vs.solve(pad, rubber, precision="mixed", **kw)
    assert f.summary["precision"] == "f64" and m.summary["precision"] == "mixed"
    assert m.summary["exact_matvecs"] > 0 and f.summary["exact_matvecs"] == 0
    assert math.isclose(m.friction_coefficient, f.friction_coefficient, rel_tol=1e-6)
    assert math.isclose(m.contact_area_fraction, f.contact_area_fraction, rel_tol=1e-6)
    assert np.array_equal(m.contact, f.contact)
    with pytest.raises(ValueError, match="precision"):
        vs.solve(pad, rubber, precision="f16", **kw)
