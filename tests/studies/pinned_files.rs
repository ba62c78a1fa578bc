//! A study directory pins the content of every file its configuration
//! reads (a height map, a material file, a PSD table): a file replaced
//! between two shards or runs is refused by name before any point is
//! solved, and leaves the directory as it was; a merge after the change
//! draws Persson's theory from the points' own values, saying why.

use crate::refusals::snapshot;
use std::path::Path;

use super::support::{run, s, text};

const MATERIAL: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01
"#;

const REST: &str = r#"
[loading]
normal_load = 0.30
speed = 1e-2

[analysis]
enabled = false

[sweep]
speed = [1e-3, 1e-2, 1e-1, 1.0]
include_static = false
"#;

/// A 16 x 16 text height map of waves of the given phase \[m\].
fn height_map(phase: f64) -> String {
    let mut out = String::new();
    for i in 0..16 {
        let row: Vec<String> = (0..16)
            .map(|j| {
                let (x, y) = (i as f64, j as f64);
                format!(
                    "{:e}",
                    1e-6 * ((0.7 * x + phase).sin() + (0.9 * y - phase).cos())
                )
            })
            .collect();
        out.push_str(&row.join(" "));
        out.push('\n');
    }
    out
}

/// Run `args` and expect a one-line refusal containing `needle` that
/// leaves `dir` as it was.
fn refused(args: &[&str], dir: &Path, needle: &str) {
    let before = snapshot(dir);
    let out = run(args);
    let err = text(&out.stderr);
    assert!(!out.status.success(), "{err}");
    let line = err.lines().find(|l| l.starts_with("error:")).unwrap_or("");
    assert!(line.contains(needle), "{err}");
    assert!(line.contains("use another --out directory"), "{err}");
    assert!(!err.contains("solved now"), "{err}");
    assert_eq!(snapshot(dir), before, "a refused run writes nothing");
}

/// A sweep config in `dir` reading the height map `surf.txt` (written
/// there, `height_map(0.0)`): the map's path, the config's and the
/// output directory's.
fn surface_file_case(dir: &Path) -> (std::path::PathBuf, String, std::path::PathBuf) {
    let map = dir.join("surf.txt");
    std::fs::write(&map, height_map(0.0)).unwrap();
    let cfg = dir.join("case.toml");
    std::fs::write(
        &cfg,
        format!("{MATERIAL}\n[surface]\nfile = \"surf.txt\"\nlength = 0.01\n{REST}"),
    )
    .unwrap();
    (map, s(&cfg), dir.join("out"))
}

#[test]
fn a_surface_file_replaced_between_shards_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let (map, cfg, out) = surface_file_case(tmp.path());
    let o = s(&out);
    let first = run(&["sweep", &cfg, "--out", &o, "--shard", "0/2"]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    std::fs::write(&map, height_map(1.0)).unwrap();
    let needle = "surface.file = \"surf.txt\" has changed since the sweep";
    refused(
        &["sweep", &cfg, "--out", &o, "--shard", "1/2"],
        &out,
        needle,
    );
    refused(&["sweep", &cfg, "--out", &o], &out, needle);
    // The content the points were solved with is accepted again.
    std::fs::write(&map, height_map(0.0)).unwrap();
    let second = run(&["sweep", &cfg, "--out", &o, "--shard", "1/2"]);
    assert!(second.status.success(), "{}", text(&second.stderr));
    assert!(
        text(&second.stdout).contains("0 already done, 2 solved now"),
        "{}",
        text(&second.stdout)
    );
    // A merge after the file changed does not take Persson's theory from
    // the new file.
    std::fs::write(&map, height_map(1.0)).unwrap();
    let merged = run(&["merge", &o]);
    assert!(merged.status.success(), "{}", text(&merged.stderr));
    assert!(
        text(&merged.stderr).contains(
            "Persson's theory drawn from the points' own values (surface.file = \"surf.txt\" has changed"
        ),
        "{}",
        text(&merged.stderr)
    );
}

#[test]
fn an_edited_material_file_is_refused_on_a_rerun() {
    let tmp = tempfile::tempdir().unwrap();
    let material = tmp.path().join("mat.toml");
    std::fs::write(&material, MATERIAL).unwrap();
    let cfg = tmp.path().join("case.toml");
    std::fs::write(
        &cfg,
        format!(
            "[material]\nmodel = \"file\"\nfile = \"mat.toml\"\n\n[surface.generate]\nn = 32\nlength = 0.01\nhurst = 0.8\nscales = 4\nrms_slope = 0.02\nseed = 1\n{REST}"
        ),
    )
    .unwrap();
    let (cfg, out) = (s(&cfg), tmp.path().join("out"));
    let o = s(&out);
    let first = run(&["sweep", &cfg, "--out", &o, "--limit", "1"]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    std::fs::write(&material, MATERIAL.replace("1.0e7", "2.0e7")).unwrap();
    refused(
        &["sweep", &cfg, "--out", &o],
        &out,
        "material.file = \"mat.toml\" has changed since the sweep",
    );
}

#[test]
fn a_psd_table_changed_between_magnification_shards_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let q_l = 2.0 * std::f64::consts::PI / 0.01;
    let table = |scale: f64| {
        let mut csv = String::from("q,C\n");
        for q in [300.0, 1.0e3, 3.0e3, 8.0 * q_l] {
            csv.push_str(&format!(
                "{q:e},{:e}\n",
                scale * 1e-16 * (q / q_l).powf(-3.6)
            ));
        }
        csv
    };
    let psd = tmp.path().join("table.csv");
    std::fs::write(&psd, table(1.0)).unwrap();
    let cfg = tmp.path().join("case.toml");
    std::fs::write(
        &cfg,
        format!(
            "{MATERIAL}\n[surface.generate]\nn = 64\nlength = 0.01\npsd = \"table.csv\"\nseed = 3\n\n[loading]\nmean_pressure = 3.0e3\nspeed = 0.01\n\n[solver]\nformulation = \"periodic\"\n"
        ),
    )
    .unwrap();
    let (cfg, out) = (s(&cfg), tmp.path().join("out"));
    let o = s(&out);
    let study = |shard: &'static str| {
        vec![
            "magnification".to_string(),
            cfg.clone(),
            "--scales".into(),
            "4,8".into(),
            "--backend".into(),
            "cpu".into(),
            "--out".into(),
            o.clone(),
            "--shard".into(),
            shard.into(),
        ]
    };
    let args = study("0/2");
    let first = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(first.status.success(), "{}", text(&first.stderr));
    std::fs::write(&psd, table(2.0)).unwrap();
    let args = study("1/2");
    refused(
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
        &out,
        "surface.generate.psd = \"table.csv\" has changed since the magnification study",
    );
}

/// A directory whose pin does not record the files (made by an earlier
/// version) cannot vouch for them: refused, saying so.
#[test]
fn a_pin_without_the_files_content_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, cfg, out) = surface_file_case(tmp.path());
    let o = s(&out);
    let first = run(&["sweep", &cfg, "--out", &o, "--limit", "1"]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let pin = out.join("sweep.toml");
    let mut pinned: toml::Table = std::fs::read_to_string(&pin).unwrap().parse().unwrap();
    assert!(
        pinned.remove("pinned_files").is_some(),
        "the pin records the file"
    );
    std::fs::write(&pin, toml::to_string(&pinned).unwrap()).unwrap();
    refused(
        &["sweep", &cfg, "--out", &o],
        &out,
        "started by an earlier version, which did not record the content of surface.file = \"surf.txt\"",
    );
}
