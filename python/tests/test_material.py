"""Materials: E(w) matches `viscoslide material show`; the constructors
agree with each other; a DMA fit matches `viscoslide material fit`."""

import math

import numpy as np
import pytest

import viscoslide as vs


def show_table(text):
    """(w, E1, E2) rows of the `material show` table."""
    rows = []
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 4:
            try:
                rows.append([float(p) for p in parts[:3]])
            except ValueError:
                pass
    return np.array(rows)


@pytest.mark.parametrize("config", ["material_paper_sls.toml", "material_prony.toml", "material_sbr_like.toml"])
def test_complex_modulus_matches_material_show(cli, repo, config):
    # Decades, so that the printed frequencies (4 digits) are exact.
    out = cli("material", "show", str(repo / "configs" / config), "--from", "1", "--to", "1e8", "--points", "9")
    table = show_table(out)
    assert len(table) == 9
    assert np.allclose(table[:, 0], np.logspace(0, 8, 9), rtol=1e-15)
    m = vs.Material.from_toml(repo / "configs" / config)
    e = m.complex_modulus(table[:, 0])
    # `material show` prints 5 significant digits.
    np.testing.assert_allclose(e.real, table[:, 1], rtol=6e-6)
    np.testing.assert_allclose(e.imag, table[:, 2], rtol=6e-6)


def test_sls_limits_and_shapes(rubber):
    e = rubber.complex_modulus(np.array([[1e-6, 1e9]]))
    assert e.shape == (1, 2) and e.dtype == np.complex128
    assert e[0, 0].real == pytest.approx(1e7 / 3, rel=1e-6)
    assert e[0, 1].real == pytest.approx(1e7, rel=1e-6)
    assert rubber.relaxed_modulus == pytest.approx(1e7 / 3)
    assert np.ndim(rubber.complex_modulus(10.0)) == 0


def test_complex_modulus_refuses_masked_frequencies(rubber):
    w = np.ma.masked_array([1.0, 10.0, 100.0], mask=[False, True, False])
    with pytest.raises(ValueError, match=r"omega has 1 masked value.*\(1,\)"):
        rubber.complex_modulus(w)
    unmasked = np.ma.masked_array([1.0, 10.0], mask=False)
    assert np.array_equal(rubber.complex_modulus(unmasked), rubber.complex_modulus(np.array([1.0, 10.0])))


def test_the_constructors_describe_one_material(rubber):
    (c, tau), = rubber.creep_spectrum_terms
    spectrum = vs.Material.creep_spectrum([tau], [c], glassy_modulus=1e7)
    relaxation = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, relaxation_time=0.01 / 3)
    # The SLS's Prony form: E(t) = E0 + (E_inf - E0) exp(-t / theta), theta = tau E0 / E_inf.
    prony = vs.Material.prony([1e7 - 1e7 / 3], [0.01 / 3], relaxed_modulus=1e7 / 3)
    w = np.logspace(-1, 5, 13)
    for other in (spectrum, relaxation, prony):
        np.testing.assert_allclose(other.complex_modulus(w), rubber.complex_modulus(w), rtol=1e-12)


def test_fit_dma_matches_material_fit(cli, repo, tmp_path):
    lines = [l for l in (repo / "configs" / "data" / "sbr_like_dma.csv").read_text().splitlines() if not l.startswith("#")]
    header = lines[0].split(",")
    assert header == ["temperature_c", "frequency_hz", "e1_pa", "e2_pa"], header
    values = np.array([[float(x) for x in l.split(",")] for l in lines[1:]])
    data = {name: values[:, k] for k, name in enumerate(header)}
    m = vs.Material.fit_dma(
        data["frequency_hz"], data["e1_pa"], data["e2_pa"], wlf=(8.86, 101.6, 17.0), temperature=17.0,
        temperatures=data["temperature_c"],
    )
    cli("material", "fit", str(repo / "configs" / "data" / "sbr_like_dma.csv"), "--wlf", "8.86,101.6,17",
        "--temperature", "17", "--out", str(tmp_path))
    fitted = vs.Material.from_toml(tmp_path / "material.toml")
    w = np.logspace(-2, 8, 21)
    np.testing.assert_allclose(m.complex_modulus(w), fitted.complex_modulus(w), rtol=1e-9)
    assert m.fit_info["rms_relative_error_e1"] < 0.05
    assert m.fit_info["warnings"] == []


def test_fit_dma_warns_as_material_fit(cli, repo, tmp_path):
    """Data at 60 C stop below the glassy plateau, and the same points
    without their temperatures merge ten of them: each is warned, with the
    numbers material fit records."""
    lines = [l for l in (repo / "configs" / "data" / "sbr_like_dma.csv").read_text().splitlines() if not l.startswith("#")]
    values = np.array([[float(x) for x in l.split(",")] for l in lines[1:]])
    hot = values[values[:, 0] == 60.0]
    with pytest.warns(UserWarning, match="do not reach the glassy plateau") as caught:
        m = vs.Material.fit_dma(hot[:, 1], hot[:, 2], hot[:, 3], temperatures=hot[:, 0])
    assert len(caught) == 1
    (warned,) = m.fit_info["warnings"]
    assert "E_inf = 1.084e12 Pa" in warned
    path = tmp_path / "hot.csv"
    path.write_text("\n".join([lines[0]] + [l for l in lines[1:] if l.startswith("60,")]) + "\n")
    cli("material", "fit", str(path), "--out", str(tmp_path / "fit"))
    assert warned in (tmp_path / "fit" / "material.toml").read_text()
    with pytest.warns(UserWarning) as caught:
        merged = vs.Material.fit_dma(values[:, 1], values[:, 2], values[:, 3])
    notes = merged.fit_info["warnings"]
    assert [str(c.message) for c in caught] == notes
    assert any("several temperatures merged" in n for n in notes), notes
    assert any("the fit misses its data" in n for n in notes), notes
