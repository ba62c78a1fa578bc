//! `viscoslide material fit` and `material show`, end to end through the
//! built binary.

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_viscoslide");

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/data/sbr_like_dma.csv")
}

#[test]
fn fit_writes_three_files_loadable_by_file_model() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit");
    let run = Command::new(BIN)
        .args(["material", "fit"])
        .arg(data())
        .args(["--wlf", "8.86,101.6,17", "--temperature", "25", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for name in ["material.toml", "fit.csv", "fit.png"] {
        let p = out.join(name);
        assert!(
            p.metadata().map(|m| m.len() > 100).unwrap_or(false),
            "{name}"
        );
    }
    // Nothing else (no staging folder) is left behind.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 3);
    let png = std::fs::read(out.join("fit.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let csv = std::fs::read_to_string(out.join("fit.csv")).unwrap();
    // Header plus one row per data point (160).
    assert_eq!(csv.lines().count(), 161);
    let toml_text = std::fs::read_to_string(out.join("material.toml")).unwrap();
    assert!(toml_text.contains("[fit]") && toml_text.contains("temperature = 25.0"));

    // A config in another directory loads it with model = "file".
    let cfg = dir.path().join("run.toml");
    std::fs::write(
        &cfg,
        "[material]\nmodel = \"file\"\nfile = \"fit/material.toml\"\n",
    )
    .unwrap();
    let show = Command::new(BIN)
        .args(["material", "show"])
        .arg(&cfg)
        .args(["--points", "7"])
        .output()
        .unwrap();
    assert!(
        show.status.success(),
        "{}",
        String::from_utf8_lossy(&show.stderr)
    );
    let text = String::from_utf8(show.stdout).unwrap();
    assert!(
        text.contains("relaxed modulus E0") && text.contains("tan delta"),
        "{text}"
    );
    // 7 table rows after the table header.
    let rows = text
        .lines()
        .skip_while(|l| !l.contains("tan delta"))
        .count();
    assert_eq!(rows, 8, "{text}");
}

/// A failing `fit` prints exactly one `error:` line and writes nothing.
fn fails_cleanly(csv: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    std::fs::write(&path, csv).unwrap();
    let out = dir.path().join("out");
    let run = Command::new(BIN)
        .args(["material", "fit"])
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error:") && err.contains(needle), "{err}");
    assert!(!out.exists(), "output directory must not be created");
}

#[test]
fn bad_csv_gives_one_line_error_and_writes_nothing() {
    fails_cleanly("frequency_hz,e1_pa\n1,2\n2,3\n3,4\n", "e2_pa");
    fails_cleanly("e1_pa,e2_pa\n1,2\n2,3\n3,4\n", "frequency_hz");
    fails_cleanly(
        "# note\nomega_rad_s,e1_pa,e2_pa\n1,2e6,1e5\n10,abc,2e5\n100,3e6,3e5\n",
        "line 4",
    );
    fails_cleanly(
        "omega_rad_s,e1_pa,e2_pa\n1,2e6,1e5\n10,-2e6,2e5\n100,3e6,3e5\n",
        "positive",
    );
    // Several temperatures and no WLF constants.
    fails_cleanly(
        "temperature_c,omega_rad_s,e1_pa,e2_pa\n0,1,2e6,1e5\n20,10,2e6,2e5\n20,100,3e6,3e5\n",
        "--wlf",
    );
}
