//! Inputs a solve used to accept with a misleading answer, or refuse with
//! a message naming the wrong cause: each is refused before anything is
//! solved or written, in one line naming the key and the bound.

use std::path::{Path, PathBuf};
use std::process::Output;

use viscoslide::io::npy;

use super::messages::{assert_refused, solve};

/// A config of the paper's material on the height map `file` (a side of
/// 1 cm), pressed by 0.3 N at `xi = 1.17e-2`.
fn file_config(dir: &Path, file: &Path) -> PathBuf {
    let p = dir.join("f.toml");
    std::fs::write(
        &p,
        format!(
            "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3333333333333335e6\nglassy_modulus = 1e7\ncreep_time = 0.01\npoisson = 0.5\n\
             [surface]\nfile = {:?}\nlength = 0.01\n\
             [loading]\nnormal_load = 0.3\nxi = 1.17e-2\n",
            file.to_str().unwrap()
        ),
    )
    .unwrap();
    p
}

/// An `n x n` .npy map of micrometre heights in `dir`.
fn npy_map(dir: &Path, n: usize) -> PathBuf {
    let h: Vec<f64> = (0..n * n).map(|k| (k as f64 * 0.37).sin() * 1e-6).collect();
    let f = dir.join(format!("h{n}.npy"));
    std::fs::write(&f, npy::encode_f64(&[n, n], &h)).unwrap();
    f
}

/// A 32 x 32 pad of the paper's single-relaxation material (creep time
/// `tau`), sliding at `xi`; `loading` is the rest of `[loading]`.
fn config(dir: &Path, tau: f64, loading: &str) -> PathBuf {
    let p = dir.join("c.toml");
    std::fs::write(
        &p,
        format!(
            "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3333333333333335e6\nglassy_modulus = 1e7\ncreep_time = {tau:e}\npoisson = 0.5\n\
             [surface.generate]\nn = 32\nlength = 0.01\nhurst = 0.8\nscales = 4\nrms_slope = 0.02\nseed = 1\n\
             [loading]\n{loading}\n"
        ),
    )
    .unwrap();
    p
}

/// Every `[loading]` value that is not a finite number is refused naming
/// its key, whether it comes from the file or from `--set` (an infinite
/// speed or xi used to solve, "v = inf m/s", and write a zero friction).
#[test]
fn non_finite_loading_values_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let load = "normal_load = 0.3";
    for (key, others) in [
        ("speed", load),
        ("xi", load),
        ("normal_load", "xi = 1.17e-2"),
        ("mean_pressure", "xi = 1.17e-2"),
        ("approach", "xi = 1.17e-2"),
        ("direction_deg", "xi = 1.17e-2\nnormal_load = 0.3"),
        ("temperature", "xi = 1.17e-2\nnormal_load = 0.3"),
    ] {
        for v in ["inf", "-inf", "nan"] {
            let needle = format!("[loading] {key} = ");
            let shown = if v == "nan" { "NaN" } else { v };
            // In the file.
            let cfg = config(tmp.path(), 0.01, &format!("{others}\n{key} = {v}"));
            let o = solve(tmp.path(), &cfg, &[]);
            assert_refused(&o, &[&needle, shown, "must be finite"]);
            // On the command line.
            let cfg = config(tmp.path(), 0.01, others);
            let set = format!("loading.{key}={v}");
            let o = solve(tmp.path(), &cfg, &[&set]);
            assert_refused(&o, &[&needle, shown, "must be finite"]);
        }
    }
    // A finite xi whose speed xi L / tau leaves double precision is xi's.
    let cfg = config(tmp.path(), 1e-5, load);
    let o = solve(tmp.path(), &cfg, &["loading.xi=1e307"]);
    assert_refused(&o, &["[loading] xi = 1e307", "beyond double precision"]);
}

/// A map whose default analysis band (`zeta1 = 1 <= |q|/q0 <= min(nx,
/// ny) / 2`) is empty is refused before the solve, naming its grid and the
/// 4 cells per side the band needs (it was solved, then refused by the
/// analysis as "analysis parameter `zeta2` = 1"). Without the analysis,
/// or with a band given, the same map solves.
#[test]
fn maps_too_small_for_the_analysis_are_refused_before_the_solve() {
    let tmp = tempfile::tempdir().unwrap();
    for n in [2, 3] {
        let cfg = file_config(tmp.path(), &npy_map(tmp.path(), n));
        let o = solve(tmp.path(), &cfg, &[]);
        assert_refused(
            &o,
            &[&format!("a {n} x {n} grid"), "at least 4 cells per side"],
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("analysis parameter"));
        for set in ["analysis.enabled=false", "analysis.zeta2=1.5"] {
            let o = solve(tmp.path(), &cfg, &[set]);
            assert!(
                o.status.success(),
                "{n} x {n}, {set}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            std::fs::remove_dir_all(tmp.path().join("out")).unwrap();
        }
    }
    // The smallest grid the band holds.
    let cfg = file_config(tmp.path(), &npy_map(tmp.path(), 4));
    let o = solve(tmp.path(), &cfg, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The last line of stderr (a refusal at the solve's start follows the
/// lines naming the backend and the grid).
fn last_line(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr);
    err.trim_end().lines().last().unwrap_or("").to_string()
}

/// Positive loads so small that the solve's numbers underflow are refused
/// naming the load: a mean pressure whose load over the map rounds to 0 N
/// or below f64's normal range (it was refused as "the normal load must be
/// positive, got 0 N"), and a load or approach whose one-cell pressure and
/// displacement square below 1e-300 (it was refused after the solve's
/// start as a contact set left empty).
#[test]
fn loads_whose_numbers_underflow_are_refused_naming_the_load() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), 0.01, "xi = 1.17e-2");
    for p in ["5e-324", "1e-310"] {
        let o = solve(tmp.path(), &cfg, &[&format!("loading.mean_pressure={p}")]);
        assert_refused(
            &o,
            &[
                &format!("[loading] mean_pressure = {p} Pa"),
                "below double precision",
            ],
        );
    }
    for (set, needle) in [
        ("loading.normal_load=1e-200", "the normal load 1e-200 N"),
        (
            "loading.mean_pressure=1e-200",
            "a mean pressure of 1e-200 Pa",
        ),
        ("loading.approach=1e-200", "the approach 1e-200 m"),
    ] {
        let o = solve(tmp.path(), &cfg, &[set]);
        assert_eq!(o.status.code(), Some(1), "{set}");
        let line = last_line(&o);
        assert!(
            line.contains(needle) && line.contains("below double precision"),
            "{set}: {line}"
        );
    }
    // A small load inside the range still solves.
    let o = solve(tmp.path(), &cfg, &["loading.normal_load=1e-100"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A measured map whose side lies outside the range of a generated
/// surface's `length` (1e-9 to 1e3 m) is refused naming the side and its
/// key (a pad of 1e150 m was refused as a load too small, or as a solve
/// that did not converge).
#[test]
fn map_sides_out_of_range_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = file_config(tmp.path(), &npy_map(tmp.path(), 8));
    for (set, needle) in [
        ("surface.length=1e150", "along x is 1e150 m (`length`"),
        ("surface.length=1e-12", "along x is 1e-12 m (`length`"),
        ("surface.length_y=1e150", "along y is 1e150 m (`length_y`"),
    ] {
        let o = solve(tmp.path(), &cfg, &[set]);
        assert_refused(&o, &[needle, "[1e-9, 1e3] m"]);
    }
}

/// A map whose rms height or rms slope overflows (heights near 1e295 m or
/// 1e150 m, a unit read wrong) is refused naming the statistic and the
/// largest height (it was solved, and reported an rms slope of inf).
#[test]
fn heights_whose_statistics_overflow_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    for (scale, what) in [(1e295, "rms height"), (1e150, "rms slope")] {
        let h: Vec<f64> = (0..32 * 32)
            .map(|k| (k as f64 * 0.37).sin() * scale)
            .collect();
        let f = tmp.path().join("big.npy");
        std::fs::write(&f, npy::encode_f64(&[32, 32], &h)).unwrap();
        let cfg = file_config(tmp.path(), &f);
        let o = solve(tmp.path(), &cfg, &[]);
        assert_refused(
            &o,
            &[
                &format!("the {what} of this map is inf"),
                "overflow",
                "unit",
            ],
        );
    }
}

/// A `--set` number beyond the range of its type is refused saying so,
/// naming the key (it was "invalid type: string \"1e400\""); one that
/// would be read as 0 is refused too.
#[test]
fn set_numbers_out_of_range_are_named() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), 0.01, "normal_load = 0.3\nxi = 1.17e-2");
    for (set, key, why) in [
        ("loading.xi=1e400", "xi", "out of the range of a double"),
        ("loading.xi=-1e400", "xi", "out of the range of a double"),
        (
            "surface.generate.n=1e400",
            "n",
            "out of the range of a double",
        ),
        ("loading.xi=1e-400", "xi", "below the range of a double"),
        (
            "surface.generate.seed=99999999999999999999",
            "seed",
            "out of the range of a 64-bit integer",
        ),
    ] {
        let o = solve(tmp.path(), &cfg, &[set]);
        assert_refused(&o, &[&format!("--set {set}"), &format!("key `{key}`"), why]);
        assert!(!String::from_utf8_lossy(&o.stderr).contains("invalid type"));
    }
}

/// A value so large or small that f64 writes it out in full (`1e300` as
/// 301 digits) reads in scientific notation in the refusal naming it.
#[test]
fn huge_and_tiny_values_read_as_scientific_in_refusals() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), 0.01, "normal_load = 0.3\nxi = 1.17e-2");
    for (set, shown) in [
        ("loading.temperature=1e300", "temperature = 1e300 C"),
        ("loading.temperature=-1e-300", "temperature = -1e-300 C"),
        ("solver.tolerance=1e300", "got 1e300"),
        ("material.poisson=1e308", "1e308 is outside"),
    ] {
        let o = solve(tmp.path(), &cfg, &[set]);
        let line = last_line(&o);
        assert_refused(&o, &[shown]);
        assert!(line.len() < 250, "{set}: {} characters: {line}", line.len());
    }
}
