"""Every check before anything is solved or written: a sweep checks every
point before its first solve (a value that one combination cannot take
is refused with nothing solved, as the command line's ``[sweep.vary]``
refuses it); a refused magnification study leaves ``out`` as it was, and
one into a directory another writer holds is refused at once."""

import pytest

import viscoslide as vs


@pytest.fixture(scope="module")
def small():
    return vs.Surface.self_affine(32, 0.01, 0.8, scales=4, rms_slope=0.02, seed=3)


@pytest.mark.parametrize(
    "options, vary, needle",
    [
        ({"formulation": "nonperiodic", "mesh": "adaptive"}, {"solver.precision": ["f64", "mixed"]}, "precision"),
        ({}, {"layer.thickness": [1e-3, -1.0]}, "thickness"),
        ({}, {"solver.tolerance": [1e-8, 2.0]}, "tolerance"),
        ({}, {"solver.tolerance": [1e-8, 1e-8]}, "twice"),
    ],
)
def test_a_bad_value_in_a_later_combination_solves_nothing(small, rubber, options, vary, needle):
    seen = []
    with pytest.raises(ValueError, match=needle) as e:
        vs.sweep(small, rubber, speed=[1e-2, 2e-2], normal_load=0.3, backend="cpu", vary=vary, progress=seen.append, **options)
    assert "\n" not in str(e.value)
    assert seen == [], "points were solved before the refusal"


@pytest.mark.filterwarnings("ignore:.*the finite pad's own")
def test_a_point_whose_solve_fails_is_named(small, rubber):
    # One matvec allowed at the later combination: its first point's solve
    # fails (after the earlier points were solved), and the error names it.
    seen = []
    with pytest.raises(vs.ConvergenceError) as e:
        vs.sweep(small, rubber, speed=[1e-2, 2e-2], normal_load=0.3, backend="cpu",
                 vary={"solver.max_matvecs": [100000, 1]}, progress=seen.append)
    assert len(seen) == 2
    if hasattr(e.value, "add_note"):
        assert e.value.__notes__ == ["in sweep point 3 of 4 (speed = 0.01, normal_load = 0.3, solver.max_matvecs = 1)"]


def test_too_many_combinations_are_refused_at_once(small, rubber):
    vary = {"solver.tolerance": [1e-9 * (1 + k) for k in range(101)], "loading.direction_deg": [0.1 * k for k in range(100)]}
    with pytest.raises(ValueError, match="limit of 10000"):
        vs.sweep(small, rubber, speed=1e-2, normal_load=0.3, backend="cpu", vary=vary)


STUDY = """
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 64
length = 0.01
hurst = 0.8
q1 = 5026.548245743669
rms_slope = 0.02
seed = 3

[loading]
mean_pressure = 3.0e3
speed = 0.01

[solver]
formulation = "non_periodic"
mesh = "adaptive"
"""


def test_a_refused_magnification_leaves_out_as_it_was(tmp_path):
    config = tmp_path / "study.toml"
    config.write_text(STUDY)
    out = tmp_path / "out"
    mixed = {"solver.precision": "mixed"}
    with pytest.raises(ValueError, match="precision"):
        vs.magnification(config, scales=[4, 8], set=mixed, out=out, backend="cpu")
    assert not out.exists()
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="precision"):
        vs.magnification(config, scales=[4, 8], set=mixed, out=out, backend="cpu")
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]
    vs.magnification(config, scales=[4, 8], out=out, backend="cpu")
    assert (out / "magnification.json").is_file()


def test_a_magnification_into_a_held_directory_is_refused(tmp_path):
    import fcntl
    import os

    config = tmp_path / "study.toml"
    config.write_text(STUDY)
    out = tmp_path / "out"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(Exception, match="another process is writing") as e:
            vs.magnification(config, scales=[4, 8], out=out, backend="cpu")
        assert "\n" not in str(e.value)
        assert list(out.iterdir()) == []
    finally:
        os.close(fd)


@pytest.mark.parametrize(
    "loads, needle",
    [
        ({"mean_pressure": 3e3, "approach": 1e-6}, "give only one of normal_load \\(N\\), mean_pressure \\(Pa\\) and approach \\(m\\)"),
        ({"normal_load": 0.3, "approach": 1e-6}, "give only one of normal_load \\(N\\), mean_pressure \\(Pa\\) and approach \\(m\\)"),
        ({"normal_load": 0.3, "mean_pressure": 3e3}, "give only one of normal_load \\(N\\), mean_pressure \\(Pa\\) and approach \\(m\\)"),
        ({"approach": 1e-6}, "a sweep prescribes the load"),
    ],
)
def test_two_loads_are_refused_as_solve_refuses_them(small, rubber, loads, needle):
    # None of them is dropped for the other: refused before any solve.
    for run in (
        lambda seen: vs.sweep(small, rubber, speed=[1e-2], backend="cpu", progress=seen.append, **loads),
        lambda seen: vs.friction_curve(small, rubber, [1e-2], backend="cpu", progress=seen.append, **loads),
    ):
        seen = []
        with pytest.raises(ValueError, match=needle) as e:
            run(seen)
        assert "\n" not in str(e.value)
        assert seen == [], "points were solved before the refusal"
