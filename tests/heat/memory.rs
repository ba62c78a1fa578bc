//! Heated work too large for the memory available is refused in one line
//! before it starts, naming what needs the memory (the volume source's
//! depth layers) and what would fit (the surface source): the heated
//! solve before its first isothermal solve, `viscoslide heat --from-run`
//! before the source is computed. The machine's memory is stated with
//! `VISCOSLIDE_TEST_FAULT=available-BYTES`.

use std::path::Path;
use std::process::{Command, Output};

use crate::common::heating::HEATED_CELL;

fn viscoslide(args: &[&str], available: Option<u64>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
    c.args(args).env_remove("VISCOSLIDE_TEST_FAULT");
    if let Some(bytes) = available {
        c.env("VISCOSLIDE_TEST_FAULT", format!("available-{bytes}"));
    }
    c.output().unwrap()
}

/// The byte count stated after `label` in `text` ("needs 123 bytes").
fn stated(text: &str, label: &str) -> u64 {
    let rest = &text[text
        .find(label)
        .unwrap_or_else(|| panic!("{label}: {text}"))
        + label.len()..];
    let digits: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.parse().unwrap_or_else(|_| panic!("{label}: {text}"))
}

/// The one error line of a refused run; nothing written at `out`.
fn refusal(o: &Output, out: &Path) -> String {
    assert!(
        !o.status.success(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    let stderr = String::from_utf8_lossy(&o.stderr);
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    errors[0].to_string()
}

#[test]
fn a_heated_solve_too_large_for_memory_is_refused_before_solving() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("heated.toml");
    std::fs::write(&cfg, HEATED_CELL.replace("n = 32", "n = 128")).unwrap();
    let out = dir.path().join("out");
    let solve = |available: u64, sets: &[&str]| {
        let mut args = vec![
            "solve",
            cfg.to_str().unwrap(),
            "--backend",
            "cpu",
            "--out",
            out.to_str().unwrap(),
        ];
        for s in sets {
            args.extend(["--set", s]);
        }
        viscoslide(&args, Some(available))
    };
    // What the isothermal solve alone needs, from its own refusal.
    let line = refusal(&solve(1, &[]), &out);
    assert!(line.contains("128 x 128 grid"), "{line}");
    let isothermal = stated(&line, "needs");

    // Enough for the isothermal solve, not for the heated one: refused
    // before the first solve, nothing written.
    let line = refusal(&solve(isothermal, &[]), &out);
    for part in [
        "[heating] a heated solve of 128 x 128 cells",
        "the volume source's density and layer spectra",
        "source = \"surface\" needs",
    ] {
        assert!(line.contains(part), "{part}: {line}");
    }
    let volume = stated(&line, "layer spectra");
    let heated = stated(&line, ") needs");
    let surface = stated(&line, "source = \"surface\" needs");
    assert!(
        isothermal < surface && surface < heated && volume < heated,
        "{isothermal} {surface} {volume} {heated}"
    );
    // The density and the layer spectra of every depth layer: more than
    // 16 bytes per cell and layer of the full grid, at least 20 layers.
    assert!(volume > 20 * 16 * 128 * 128, "{volume}");

    // Exactly the stated memory is enough: the surface source with what
    // the refusal says it needs, the volume source with its own need.
    let o = solve(surface, &["heating.source=\"surface\""]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::remove_dir_all(&out).unwrap();
    let o = solve(heated, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["heating"]["source"], "volume");
}

#[test]
fn heat_from_a_run_refuses_a_volume_source_too_large_for_memory() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("cell.toml");
    std::fs::write(
        &cfg,
        HEATED_CELL
            .replace("n = 32", "n = 96")
            .replace("[heating]", "[heating]\nenabled = false"),
    )
    .unwrap();
    let run = dir.path().join("run");
    let o = viscoslide(
        &[
            "solve",
            cfg.to_str().unwrap(),
            "--backend",
            "cpu",
            "--out",
            run.to_str().unwrap(),
        ],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("heat");
    let heat = |available: Option<u64>| {
        viscoslide(
            &[
                "heat",
                "--from-run",
                run.to_str().unwrap(),
                "--conductivity",
                "0.25",
                "--diffusivity",
                "1e-7",
                "--block-length",
                "0.05",
                "--out",
                out.to_str().unwrap(),
            ],
            available,
        )
    };
    // Room for the planned heat problem (64 bytes a cell), not for the
    // source's layers.
    let line = refusal(&heat(Some(96 * 96 * 100)), &out);
    assert!(
        line.contains("volume source of 96 x 96 cells on") && line.contains("depth layers needs"),
        "{line}"
    );
    let o = heat(None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
