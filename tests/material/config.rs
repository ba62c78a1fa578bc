//! `[material]` configs: every model builds, SLS times convert exactly, and
//! bad input gives a one-line error naming the key and its unit.

use std::path::Path;

use viscoslide::config;
use viscoslide::material::{
    material_toml, CreepSpectrum, Material, MaterialConfig, PronySeries, PronyTerm,
};

/// Write `text` as a config in a fresh directory and build its material.
fn build(text: &str) -> Result<Material, String> {
    let dir = tempfile::tempdir().unwrap();
    build_in(dir.path(), text)
}

fn build_in(dir: &Path, text: &str) -> Result<Material, String> {
    let path = dir.join("run.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = config::load(&path, &[]).map_err(|e| e.to_string())?;
    let m: &MaterialConfig = loaded.material().map_err(|e| e.to_string())?;
    m.build(&loaded.base_dir).map_err(|e| e.to_string())
}

/// The error text, which must be one line and mention every `needle`.
fn error(text: &str, needles: &[&str]) -> String {
    let e = build(text).expect_err("must fail");
    assert!(!e.contains('\n'), "not one line: {e}");
    for n in needles {
        assert!(e.contains(n), "'{e}' does not mention '{n}'");
    }
    e
}

const SLS: &str = "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.0e6\nglassy_modulus = 9.0e6\n";

#[test]
fn sls_creep_and_relaxation_time_give_the_same_material() {
    let a = build(&format!("{SLS}creep_time = 0.01\n")).unwrap();
    // theta = tau E0 / E_inf = 0.01 / 3.
    let b = build(&format!("{SLS}relaxation_time = {}\n", 0.01 / 3.0)).unwrap();
    let (ta, tb) = (a.spectrum.terms[0].time, b.spectrum.terms[0].time);
    // One multiply and one divide: within 2 ulps.
    assert!((ta - tb).abs() <= 4.0 * f64::EPSILON * ta, "{ta} vs {tb}");
    for w in [1.0, 100.0, 1e4] {
        let (ea, eb) = (a.spectrum.modulus(w), b.spectrum.modulus(w));
        assert!((ea - eb).norm() / ea.norm() < 1e-14);
    }
    assert_eq!(a.poisson, 0.5);
}

#[test]
fn creep_spectrum_and_prony_models_build() {
    let c = build(
        "[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e9\n\
         creep_spectrum = [[1e-8, 1e-3], [5e-8, 1e-1]]\npoisson = 0.45\n",
    )
    .unwrap();
    assert_eq!(c.spectrum.terms.len(), 2);
    assert_eq!(c.poisson, 0.45);
    assert!((c.spectrum.relaxed_compliance() - (1e-9 + 6e-8)).abs() < 1e-22);

    let p = build(
        "[material]\nmodel = \"prony\"\nrelaxed_modulus = 2e6\n\
         prony = [[1e6, 1e-4], [8e6, 1e-3], [1e6, 1e-1]]\n",
    )
    .unwrap();
    let reference = PronySeries::new(
        2e6,
        [(1e6, 1e-4), (8e6, 1e-3), (1e6, 1e-1)]
            .iter()
            .map(|&(modulus, time)| PronyTerm { modulus, time })
            .collect(),
    )
    .unwrap();
    for w in [1e-2, 1.0, 1e3, 1e6] {
        let (a, b) = (p.spectrum.modulus(w), reference.modulus(w));
        // Exact conversion: round-off (see tests/material/conversion.rs).
        assert!((a - b).norm() / b.norm() < 1e-12);
    }
}

#[test]
fn file_model_loads_a_written_material_toml() {
    let dir = tempfile::tempdir().unwrap();
    let spectrum = CreepSpectrum::standard_linear_solid(2e6, 6e6, 0.02).unwrap();
    let m = Material::new(spectrum, 0.49).unwrap();
    std::fs::create_dir(dir.path().join("mat")).unwrap();
    std::fs::write(
        dir.path().join("mat/material.toml"),
        material_toml(&m, None).unwrap(),
    )
    .unwrap();
    let loaded = build_in(
        dir.path(),
        "[material]\nmodel = \"file\"\nfile = \"mat/material.toml\"\n",
    )
    .unwrap();
    // Floats are written in shortest round-trip form: bit-identical.
    assert_eq!(loaded, m);
    // poisson in the config overrides the file's.
    let over = build_in(
        dir.path(),
        "[material]\nmodel = \"file\"\nfile = \"mat/material.toml\"\npoisson = 0.3\n",
    )
    .unwrap();
    assert_eq!(over.poisson, 0.3);
    let missing = build_in(
        dir.path(),
        "[material]\nmodel = \"file\"\nfile = \"nope.toml\"\n",
    )
    .expect_err("missing file");
    assert!(
        missing.contains("nope.toml") && !missing.contains('\n'),
        "{missing}"
    );
}

#[test]
fn shipped_example_configs_build() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs");
    for name in [
        "material_paper_sls.toml",
        "material_prony.toml",
        "material_sbr_like.toml",
    ] {
        let loaded = config::load(&root.join(name), &[]).unwrap();
        let m = loaded.material().unwrap().build(&loaded.base_dir);
        assert!(m.is_ok(), "{name}: {m:?}");
    }
}

#[test]
fn bad_input_gives_clear_one_line_errors() {
    // Missing keys name the key and the unit.
    error(
        "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3e6\ncreep_time = 0.01\n",
        &["glassy_modulus", "Pa"],
    );
    error(
        "[material]\nmodel = \"sls\"\nglassy_modulus = 3e6\ncreep_time = 0.01\n",
        &["relaxed_modulus", "Pa"],
    );
    error(SLS, &["creep_time", "relaxation_time", "s"]);
    error(
        "[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e9\n",
        &["creep_spectrum", "1/Pa"],
    );
    error(
        "[material]\nmodel = \"prony\"\nrelaxed_modulus = 1e6\n",
        &["prony", "Pa"],
    );
    error("[material]\nmodel = \"file\"\n", &["file"]);
    // Negative and non-finite values.
    error("[material]\nmodel = \"sls\"\nrelaxed_modulus = -3e6\nglassy_modulus = 9e6\ncreep_time = 0.01\n", &["relaxed_modulus", "positive"]);
    error(
        &format!("{SLS}creep_time = -0.01\n"),
        &["creep_time", "positive"],
    );
    error(&format!("{SLS}creep_time = nan\n"), &["creep_time", "NaN"]);
    error("[material]\nmodel = \"sls\"\nrelaxed_modulus = nan\nglassy_modulus = 9e6\ncreep_time = 0.01\n", &["relaxed_modulus"]);
    error(
        &format!("{SLS}creep_time = 0.01\npoisson = nan\n"),
        &["poisson"],
    );
    error(
        &format!("{SLS}creep_time = 0.01\npoisson = 0.7\n"),
        &["poisson"],
    );
    error(
        "[material]\nmodel = \"prony\"\nrelaxed_modulus = 1e6\nprony = [[-1e6, 1e-3]]\n",
        &["prony", "entry 0"],
    );
    error("[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e9\ncreep_spectrum = [[1e-8, 0.0]]\n", &["creep_spectrum", "entry 0"]);
    // E_inf < E0.
    error("[material]\nmodel = \"sls\"\nrelaxed_modulus = 9e6\nglassy_modulus = 3e6\ncreep_time = 0.01\n", &["glassy_modulus", "relaxed_modulus"]);
    // Both times.
    error(
        &format!("{SLS}creep_time = 0.01\nrelaxation_time = 0.003\n"),
        &["creep_time", "relaxation_time", "not both"],
    );
    // A key the model does not use.
    error(
        &format!("{SLS}creep_time = 0.01\nprony = [[1e6, 1e-3]]\n"),
        &["prony", "sls"],
    );
    error("[material]\nmodel = \"prony\"\nrelaxed_modulus = 1e6\nglassy_modulus = 2e6\nprony = [[1e6, 1e-3]]\n", &["glassy_modulus", "prony"]);
    // A row of another length: not read as its first two numbers.
    for row in ["[1e-8, 0.01, 5.0]", "[1e-8]", "[]"] {
        let n = row.matches(',').count() + usize::from(row != "[]");
        error(
            &format!("[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e9\ncreep_spectrum = [[2e-8, 1.0], {row}]\n"),
            &["creep_spectrum", &format!("invalid length {n}"), "length 2"],
        );
        error(
            &format!("[material]\nmodel = \"prony\"\nrelaxed_modulus = 1e6\nprony = [{row}]\n"),
            &["prony", &format!("invalid length {n}"), "length 2"],
        );
    }
}

/// Moduli a creep spectrum or a Prony series implies are held to the range
/// the keys that give them directly are (a compliance of 1e20 1/Pa made
/// `E0` 1e-20 Pa and a friction of 1e23).
#[test]
fn implied_moduli_are_held_to_the_range_of_solids() {
    error(
        "[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e7\ncreep_spectrum = [[1e20, 0.01]]\n",
        &["implies a relaxed modulus E0 of 1e-20 Pa", "[1e-3, 1e15]"],
    );
    error(
        "[material]\nmodel = \"prony\"\nrelaxed_modulus = 1e6\nprony = [[1e30, 1e-3]]\n",
        &["implies a glassy modulus E_inf", "model = \"prony\""],
    );
    assert!(build(
        "[material]\nmodel = \"creep_spectrum\"\nglassy_modulus = 1e7\ncreep_spectrum = [[2e-7, 0.01]]\n"
    )
    .is_ok());
}

/// A fit of data at one temperature records that temperature without WLF
/// constants; constants given beside it in a config shift from there, so
/// the material at that temperature is the fitted spectrum itself (it was
/// taken as describing T_ref: a friction 100 times off at 60 C).
#[test]
fn a_fit_at_one_temperature_keeps_it_for_constants_given_later() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("fit60.toml"),
        format!("{SLS}creep_time = 0.01\n\n[fit]\ntemperature = 60.0\n"),
    )
    .unwrap();
    let plain = build_in(
        dir.path(),
        "[material]\nmodel = \"file\"\nfile = \"fit60.toml\"\n",
    )
    .unwrap();
    assert_eq!(plain.temperature, Some(60.0));
    let shifted = build_in(
        dir.path(),
        "[material]\nmodel = \"file\"\nfile = \"fit60.toml\"\nwlf = [8.86, 101.6, 17.0]\n",
    )
    .unwrap();
    assert_eq!(shifted.temperature, Some(60.0));
    let at60 = shifted.at_temperature(60.0).unwrap();
    assert_eq!(at60.spectrum, plain.spectrum);
    // At T_ref the creep times are a_T(17) / a_T(60) longer.
    let at17 = shifted.at_temperature(17.0).unwrap();
    let ratio = at17.spectrum.terms[0].time / plain.spectrum.terms[0].time;
    let want = 10f64.powf(8.86 * 43.0 / (101.6 + 43.0));
    assert!((ratio / want - 1.0).abs() < 1e-12, "{ratio} {want}");
}
