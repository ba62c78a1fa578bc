"""vs.magnification: the command's study from Python, the same numbers
and the same refusals."""

import json

import numpy as np
import pytest

import viscoslide as vs

CONFIG = """
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
formulation = "periodic"
"""


@pytest.fixture()
def config(tmp_path):
    p = tmp_path / "study.toml"
    p.write_text(CONFIG)
    return p


def test_levels_equal_separate_solves(config):
    table = vs.magnification(config, scales=[3, 8], backend="cpu")
    assert set(table) == set(vs.MAGNIFICATION_COLUMNS)
    assert table["n"].dtype == np.int64 and len(table["q1"]) == 2
    assert table["rms_slope"][0] < table["rms_slope"][1]
    for k in range(2):
        one = vs.solve_config(
            config,
            set={
                "surface.generate.q1": float(table["q1"][k]),
                "surface.generate.n": int(table["n"][k]),
                "surface.generate.rms_slope": float(table["rms_slope"][k]),
            },
            backend="cpu",
        )
        assert one.friction_coefficient == pytest.approx(table["friction_coefficient"][k], rel=1e-9)
        assert one.contact_area_fraction == pytest.approx(table["contact_area_fraction"][k], rel=1e-9)


def test_as_frame_out_dir_and_speeds(config, tmp_path):
    pytest.importorskip("pandas")
    out = tmp_path / "study"
    frame = vs.magnification(config, scales=[4, 8], speeds=[3e-3, 1e-2], out=out, backend="cpu", as_frame=True)
    assert len(frame) == 4 and list(frame["speed"]) == [3e-3, 3e-3, 1e-2, 1e-2]
    assert "warnings" in frame.attrs and frame.attrs["psd"]["c0_m4"] > 0
    doc = json.loads((out / "magnification.json").read_text())
    assert [lv["friction_coefficient"] for lv in doc["levels"]] == list(frame["friction_coefficient"])
    # Resumed from the stored points: the same numbers.
    again = vs.magnification(config, scales=[4, 8], speeds=[3e-3, 1e-2], out=out, backend="cpu")
    assert list(again["wall_time_s"]) == list(frame["wall_time_s"])


def test_refusals_are_the_commands(config, tmp_path):
    with pytest.raises(ValueError, match="exceeds the configuration's q1"):
        vs.magnification(config, q1=[6000.0])
    # The messages name the arguments (and the command's flags beside).
    with pytest.raises(ValueError, match=r"exactly one of q1 \(--q1"):
        vs.magnification(config)
    with pytest.raises(ValueError, match=r"cells_per_wavelength \(--cells-per-wavelength\) must be at least 2"):
        vs.magnification(config, scales=[4], cells_per_wavelength=1.0)
    with pytest.raises(ValueError, match=r"speeds \(--speeds\) lists 0.01 twice"):
        vs.magnification(config, scales=[4], speeds=[1e-2, 1e-2])
    with pytest.raises(ValueError, match=r"scales \(--scales\) must increase strictly"):
        vs.magnification(config, scales=[4, 2], out=tmp_path / "never")
    assert not (tmp_path / "never").exists()


def test_heating_is_refused_before_anything_is_written(tmp_path):
    # The levels are isothermal: a [heating] section would be ignored.
    p = tmp_path / "heated.toml"
    p.write_text(CONFIG + "\n[heating]\nconductivity = 0.25\ndiffusivity = 1.16e-7\nblock_length = 0.01\n")
    out = tmp_path / "never"
    with pytest.raises(ValueError, match=r"\[heating\].*--set heating.enabled=false"):
        vs.magnification(p, scales=[4, 8], out=out, backend="cpu")
    assert not out.exists()
    table = vs.magnification(p, scales=[4, 8], backend="cpu", set={"heating.enabled": False})
    assert len(table["q1"]) == 2
