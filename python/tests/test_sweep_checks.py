"""A sweep checks every point before its first solve: a value that one
combination cannot take is refused with nothing solved, as the command
line's ``[sweep.vary]`` refuses it."""

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


def test_too_many_combinations_are_refused_at_once(small, rubber):
    vary = {"solver.tolerance": [1e-9 * (1 + k) for k in range(101)], "loading.direction_deg": [0.1 * k for k in range(100)]}
    with pytest.raises(ValueError, match="limit of 10000"):
        vs.sweep(small, rubber, speed=1e-2, normal_load=0.3, backend="cpu", vary=vary)
