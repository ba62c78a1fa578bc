//! Surface files and PSD tables read as what they state: a text matrix's
//! size header (orientation, sides, height unit), point lists and decimal
//! commas refused, a PSD table's header units, statistics that overflow, and
//! the side a file fixes named by the option that gave it. Each refusal is
//! one line on stderr with exit status 1 and nothing written.

use std::path::{Path, PathBuf};
use std::process::Output;

use viscoslide::io::npy;

use super::messages::{assert_refused, viscoslide};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `surface convert FILE out.npy ARGS`: the array written, or the refusal
/// (and then no out.npy).
fn convert(dir: &Path, file: &Path, args: &[&str]) -> Result<npy::NpyArray, Output> {
    let out = dir.join("out.npy");
    let _ = std::fs::remove_file(&out);
    let mut all = vec!["surface", "convert", s(file), s(&out)];
    all.extend(args);
    let o = viscoslide(&all);
    if o.status.success() {
        Ok(npy::read(&out).unwrap())
    } else {
        assert!(!out.exists(), "a refused convert wrote {}", out.display());
        Err(o)
    }
}

/// A 4 x 3 map (x by y) whose every element tells x from y.
fn truth(i: usize, j: usize) -> f64 {
    (10 * i + j) as f64 + 0.25
}

/// The file SurfaceTopography's `Topography.to_matrix` writes for `truth`
/// in micrometres: the size header, then one row per y.
fn st_matrix() -> String {
    let mut t = String::from("# Width: 320.0 um\n# Height: 240.0 um\n# Value units: um\n");
    for j in 0..3 {
        let row: Vec<String> = (0..4).map(|i| format!("{:.18e}", truth(i, j))).collect();
        t.push_str(&row.join(" "));
        t.push('\n');
    }
    t
}

#[test]
fn a_size_header_gives_the_orientation_the_sides_and_the_height_unit() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let f = write(d, "st_um.txt", &st_matrix());
    for args in [&[][..], &["--length", "320e-6"], &["--length-y", "2.4e-4"]] {
        let a = convert(d, &f, args).unwrap_or_else(|o| panic!("{args:?}: {o:?}"));
        assert_eq!(a.shape, [4, 3], "axis 0 = x");
        for i in 0..4 {
            for j in 0..3 {
                assert_eq!(a.data[i * 3 + j], truth(i, j) * 1e-6, "[{i}, {j}]");
            }
        }
    }
    let o = viscoslide(&["surface", "stats", s(&f), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rel = |k: &str, want: f64| (v["stats"][k].as_f64().unwrap() / want - 1.0).abs() < 1e-12;
    assert!(rel("length_x", 320e-6) && rel("length_y", 240e-6), "{v}");
    // A side given that disagrees with the header: named with its option.
    let o = convert(d, &f, &["--length", "1e-3"]).unwrap_err();
    assert_refused(&o, &["3.200000e-4", "1.000000e-3", "along x", "--length"]);
    let o = convert(d, &f, &["--length-y", "1e-3"]).unwrap_err();
    assert_refused(&o, &["2.400000e-4", "along y", "`--length-y`"]);
    // A unit that is not a length is named.
    let bad = write(
        d,
        "volts.txt",
        &st_matrix().replace("Value units: um", "Value units: V"),
    );
    assert_refused(&convert(d, &bad, &[]).unwrap_err(), &["'V'", "heights"]);
}

#[test]
fn point_lists_and_decimal_commas_are_refused_and_csv_still_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let mut xyz = String::new();
    for y in 0..16 {
        for x in 0..16 {
            let z = ((x * 7 + y * 3) % 11) as f64 * 1e-7;
            xyz.push_str(&format!(
                "{:e} {:e} {z:e}\n",
                x as f64 * 1e-6,
                y as f64 * 1e-6
            ));
        }
    }
    for name in ["scan.xyz", "scan.txt"] {
        let f = write(d, name, &xyz);
        let o = convert(d, &f, &["--length", "1e-4"]).unwrap_err();
        assert_refused(&o, &[name, "point list", "height matrix"]);
    }
    let f = write(d, "comma.txt", "0,000125730 -0,000132105\n0,5 1,25\n");
    let o = convert(d, &f, &["--length", "1e-4"]).unwrap_err();
    assert_refused(&o, &["line 1", "'0,000125730'", "decimal comma"]);
    for (name, text) in [
        ("spaced.csv", "1.0, 2.0\n3.0, 4.0\n"),
        ("tight.csv", "1.0,2.0\n3.0,4.0\n"),
        ("bom.txt", "\u{feff}1.0 2.0\n3.0 4.0\n"),
    ] {
        let f = write(d, name, text);
        let a = convert(d, &f, &["--length", "1e-4"]).unwrap_or_else(|o| panic!("{name}: {o:?}"));
        assert_eq!(
            (a.shape, a.data),
            (vec![2, 2], vec![1.0, 2.0, 3.0, 4.0]),
            "{name}"
        );
    }
}

#[test]
fn statistics_that_overflow_are_refused_naming_the_height_scale() {
    let tmp = tempfile::tempdir().unwrap();
    let h: Vec<f64> = (0..32 * 32)
        .map(|k| ((k * 37 % 101) as f64 - 50.0) * 1e158)
        .collect();
    let f = tmp.path().join("huge.npy");
    std::fs::write(&f, npy::encode_f64(&[32, 32], &h)).unwrap();
    let out = tmp.path().join("stats");
    let o = viscoslide(&[
        "surface",
        "stats",
        s(&f),
        "--length",
        "0.01",
        "--json",
        "--out",
        s(&out),
    ]);
    assert_refused(&o, &["huge.npy", "overflow", "e159 m"]);
    assert!(o.stdout.is_empty() && !out.exists());
}

#[test]
fn a_psd_table_in_other_units_is_refused_naming_the_column() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let rows = "1e5,1e-30\n2e5,1e-31\n4e5,1e-32\n8e5,1e-33\n";
    let out = d.join("gen");
    let generate = |table: &Path| {
        viscoslide(&[
            "surface",
            "generate",
            "--psd",
            s(table),
            "--n",
            "32",
            "--length",
            "1e-4",
            "--seed",
            "1",
            "--out",
            s(&out),
        ])
    };
    let um = write(d, "um.csv", &format!("q_1_per_um,C_um4\n{rows}"));
    assert_refused(&generate(&um), &["um.csv", "'q_1_per_um'", "1/um", "1/m"]);
    let line = write(d, "line.csv", &format!("q_per_m,c1_m3\n{rows}"));
    assert_refused(&generate(&line), &["'c1_m3'", "m^3", "m^4"]);
    assert!(!out.exists());
    for (name, text) in [
        ("ours.csv", format!("q_per_m,c_radial_m4,modes\n{rows}")),
        ("bare.csv", rows.to_string()),
    ] {
        let f = write(d, name, &text);
        let o = generate(&f);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        std::fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn a_y_side_the_file_fixes_is_named_as_length_y() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let h: Vec<f64> = (0..16 * 16)
        .map(|k| (k as f64 * 0.37).sin() * 1e-6)
        .collect();
    let f = d.join("h.npy");
    std::fs::write(&f, npy::encode_f64(&[16, 16], &h)).unwrap();
    let x3p = d.join("h.x3p");
    let o = viscoslide(&["surface", "convert", s(&f), s(&x3p), "--length", "0.01"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = viscoslide(&["surface", "stats", s(&x3p), "--length-y", "0.02"]);
    assert_refused(
        &o,
        &["along y", "2.000000e-2", "`--length-y`", "`length_y`"],
    );
    assert!(!String::from_utf8_lossy(&o.stderr).contains("drop `--length` "));
    let cfg = write(
        d,
        "c.toml",
        "[material]\nmodel = \"sls\"\nrelaxed_modulus = 3.3e6\nglassy_modulus = 1e7\ncreep_time = 0.01\npoisson = 0.5\n\
         [surface]\nfile = \"h.x3p\"\nlength_y = 0.02\n\
         [loading]\nnormal_load = 0.3\nxi = 1.17e-2\n",
    );
    let out = d.join("out");
    let o = viscoslide(&["solve", s(&cfg), "--backend", "cpu", "--out", s(&out)]);
    assert_refused(&o, &["h.x3p", "along y", "`length_y`"]);
    assert!(!out.exists());
}
