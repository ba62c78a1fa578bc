//! Every WGSL file under `shaders/` parses and validates with naga, alone
//! (shared helpers) or with the shared prelude (kernels), and every kernel
//! file on disk is embedded in the library.

use std::path::Path;

use viscoslide::internals::backend::gpu::shaders;

fn wgsl_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            wgsl_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
}

#[test]
fn every_wgsl_file_validates() {
    let root = crate::common::source_dir().join("shaders");
    let mut files = Vec::new();
    wgsl_files(&root, &mut files);
    files.sort();
    assert!(files.len() >= 20, "found only {files:?}");
    let mut failures = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let source = if rel.starts_with("shared/") {
            // Shared files build on common.wgsl (Params, WG).
            let common = std::fs::read_to_string(root.join("shared/common.wgsl")).unwrap();
            let own = std::fs::read_to_string(f).unwrap();
            if rel == "shared/common.wgsl" {
                own
            } else {
                format!("{common}\n{own}")
            }
        } else {
            let on_disk = std::fs::read_to_string(f).unwrap();
            let embedded = shaders::KERNELS.iter().find(|(n, _)| *n == rel);
            match embedded {
                Some((_, src)) if *src == on_disk => {}
                Some(_) => failures.push(format!("{rel}: embedded copy differs from disk")),
                None => failures.push(format!("{rel}: not embedded in shaders::KERNELS")),
            }
            match shaders::compose(&rel) {
                Some(s) => s,
                None => continue,
            }
        };
        if let Err(e) = shaders::validate(&source) {
            failures.push(format!("{rel}:\n{e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn validation_rejects_a_broken_shader() {
    let bad = shaders::compose("axpy.wgsl")
        .unwrap()
        .replace("fma(", "fmaa(");
    assert!(shaders::validate(&bad).is_err());
}
