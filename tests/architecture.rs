//! The import graph of `src/` (docs/ARCHITECTURE.md): every `use` and
//! every `crate::` path in code (comments and doc links excluded) must point
//! to the importing module's own layer or a lower one, and the files must
//! form no circle. A parent module declaring or re-exporting its children
//! is not an import; a child using its parent's items is.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Top-level modules from the bottom up; a module may import its own
/// layer's module and anything in a lower layer, nothing above.
const LAYERS: &[&[&str]] = &[
    &["version", "io", "plot", "gauss"],
    &["config"],
    &["material"],
    &["surface"],
    &["mesh"],
    &["response"],
    &["kernel"],
    &["operator"],
    &["heat"],
    &["backend"],
    &["solver"],
    &["analysis"],
    &["persson"],
    &["error"],
    &["problem"],
    &["heating"],
    &["sweep", "refine"],
    &["magnification"],
    &["cli", "internals"],
];

/// Root re-exports and the module they come from.
const ROOT_ALIASES: &[(&str, &str)] = &[("Error", "error"), ("Result", "error")];

fn layer_of(module: &str) -> usize {
    LAYERS
        .iter()
        .position(|l| l.contains(&module))
        .unwrap_or_else(|| panic!("module `{module}` is in no layer of tests/architecture.rs"))
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Module path of a file: `src/a/b.rs` and `src/a/b/mod.rs` are `[a, b]`.
fn module_path(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src()).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts
        .last()
        .is_some_and(|l| l == "mod" || l == "lib" || l == "main")
    {
        parts.pop();
    }
    parts
}

/// The code of a file without comments and string literals.
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if b[i] == b'\'' && b.get(i + 2) == Some(&b'\'') {
            // A char literal such as '{' or '/'.
            i += 3;
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    out
}

/// Expand `a::{b, c::{d, e}}` into `a::b`, `a::c::d`, `a::c::e`.
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let t = tree.split(" as ").next().unwrap().trim();
        return if t.is_empty() {
            vec![]
        } else {
            vec![t.to_string()]
        };
    };
    let prefix = tree[..open].trim_end_matches("::").trim();
    let inner = &tree[open + 1..tree.rfind('}').unwrap()];
    let mut items = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (k, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&inner[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    items.push(&inner[start..]);
    items
        .into_iter()
        .flat_map(expand)
        .map(|s| {
            if s == "self" {
                prefix.to_string()
            } else {
                format!("{prefix}::{s}")
            }
        })
        .collect()
}

/// Every path a file names: its `use` trees expanded, and every `crate::`
/// or `super::` path elsewhere in its code.
fn paths_of(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    let mut plain = String::new();
    while let Some(k) = rest.find("use ") {
        let before = &rest[..k];
        let at_word = before
            .chars()
            .last()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
        plain.push_str(before);
        if !at_word {
            plain.push_str("use ");
            rest = &rest[k + 4..];
            continue;
        }
        let end = rest[k..].find(';').map_or(rest.len(), |e| k + e);
        out.extend(expand(&rest[k + 4..end]));
        rest = &rest[end..];
    }
    plain.push_str(rest);
    for prefix in ["crate::", "super::"] {
        let mut s = plain.as_str();
        while let Some(k) = s.find(prefix) {
            let tail = &s[k..];
            let end = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(tail.len());
            out.push(tail[..end].trim_end_matches(':').to_string());
            s = &s[k + prefix.len()..];
        }
    }
    out
}

/// The module a path names, relative to the module `here` (`None` for
/// external crates and `std`).
fn resolve(path: &str, here: &[String], is_mod_file: bool) -> Option<Vec<String>> {
    let mut parts: Vec<&str> = path.split("::").map(str::trim).collect();
    let mut base: Vec<String> = match parts[0] {
        "crate" => {
            parts.remove(0);
            vec![]
        }
        "super" | "self" => {
            // `super` in a.rs and in a/mod.rs both name a's parent.
            let mut b = here.to_vec();
            let _ = is_mod_file;
            while parts.first() == Some(&"super") {
                b.pop();
                parts.remove(0);
            }
            if parts.first() == Some(&"self") {
                parts.remove(0);
            }
            b
        }
        _ => return None,
    };
    if base.is_empty() {
        if let Some(first) = parts.first() {
            if let Some((_, m)) = ROOT_ALIASES.iter().find(|(a, _)| a == first) {
                return Some(vec![m.to_string()]);
            }
        }
    }
    base.extend(parts.iter().map(|p| p.to_string()));
    Some(base)
}

/// The deepest module file that exists along `path`.
fn module_file(path: &[String], files: &BTreeMap<Vec<String>, PathBuf>) -> Option<Vec<String>> {
    (0..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|p| files.contains_key(p))
}

struct Graph {
    /// Module path -> file.
    files: BTreeMap<Vec<String>, PathBuf>,
    /// File module -> the file modules it imports.
    edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
}

fn graph() -> Graph {
    let mut all = Vec::new();
    rust_files(&src(), &mut all);
    all.retain(|p| !p.ends_with("main.rs"));
    let files: BTreeMap<Vec<String>, PathBuf> =
        all.iter().map(|p| (module_path(p), p.clone())).collect();
    let mut edges = BTreeMap::new();
    for (module, file) in &files {
        let text = std::fs::read_to_string(file).unwrap();
        // Unit tests are not part of the layering.
        let text = match text.find("#[cfg(test)]") {
            Some(k) => &text[..k],
            None => &text[..],
        };
        let is_mod = file.ends_with("mod.rs") || file.ends_with("lib.rs");
        let mut to = BTreeSet::new();
        for p in paths_of(&code_of(text)) {
            let Some(target) = resolve(&p, module, is_mod) else {
                continue;
            };
            let Some(target) = module_file(&target, &files) else {
                continue;
            };
            // A parent naming its own children declares or re-exports them.
            let is_child = target.len() > module.len() && target.starts_with(module);
            if target != *module && !is_child {
                to.insert(target);
            }
        }
        edges.insert(module.clone(), to);
    }
    Graph { files, edges }
}

#[test]
fn imports_point_down_the_layers() {
    let g = graph();
    let mut upward = Vec::new();
    for (from, tos) in &g.edges {
        let Some(from_top) = from.first() else {
            continue;
        };
        for to in tos {
            // The crate root (lib.rs) declares every layer: it is the top.
            let Some(to_top) = to.first() else {
                upward.push(format!("{} -> the crate root", from.join("::")));
                continue;
            };
            if to_top == from_top {
                continue;
            }
            if layer_of(to_top) >= layer_of(from_top) {
                upward.push(format!("{} -> {}", from.join("::"), to.join("::")));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that do not point to a lower layer:\n{}",
        upward.join("\n")
    );
    // Every top-level module has a layer.
    for m in g.files.keys().filter_map(|k| k.first()) {
        layer_of(m);
    }
}

/// The code of every library file below the front ends (unit tests
/// excluded), with its module path.
fn engine_files() -> Vec<(Vec<String>, String)> {
    graph()
        .files
        .into_iter()
        .filter(|(m, _)| m.first().is_some_and(|t| t != "cli"))
        .map(|(m, f)| {
            let text = std::fs::read_to_string(f).unwrap();
            let text = match text.find("#[cfg(test)]") {
                Some(k) => text[..k].to_string(),
                None => text,
            };
            (m, code_of(&text))
        })
        .collect()
}

/// The operator layer and the executors take the sliding response and the
/// grid (`response`), never the material: the response is combined in one
/// place (docs/ARCHITECTURE.md).
#[test]
fn operators_and_executors_take_the_response_not_the_material() {
    let g = graph();
    let mut wrong = Vec::new();
    for (from, tos) in &g.edges {
        let top = from.first().map(String::as_str);
        let below_material_users =
            matches!(top, Some("kernel" | "operator" | "backend" | "solver"));
        let friction = from.starts_with(&["analysis".to_string(), "friction".to_string()]);
        if !(below_material_users || friction) {
            continue;
        }
        for to in tos {
            if to.first().is_some_and(|t| t == "material") {
                wrong.push(format!("{} -> {}", from.join("::"), to.join("::")));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "take a `response::SlidingResponse` instead of the material:\n{}",
        wrong.join("\n")
    );
}

/// One constructor of the sliding response: `SlidingResponse { .. }` is
/// written only in `src/response/`, and the sliding direction is turned into
/// `e_v` (`sin_cos` of a direction) nowhere else below the front ends.
#[test]
fn the_sliding_response_has_one_constructor() {
    let mut elsewhere = Vec::new();
    for (module, code) in engine_files() {
        if module.first().is_some_and(|t| t == "response") {
            continue;
        }
        for line in code.lines() {
            // A struct literal, not a return type or an impl block.
            let literal = line.contains("SlidingResponse {")
                && !line.contains("->")
                && !line.contains("impl ");
            let direction =
                line.contains("direction_rad.sin_cos()") || line.contains("direction_rad.cos()");
            if literal || direction {
                elsewhere.push(format!("{}: {}", module.join("::"), line.trim()));
            }
        }
    }
    assert!(elsewhere.is_empty(), "{}", elsewhere.join("\n"));
}

/// The seam between the operator layer and the executors: `problem`
/// describes each grid's operator (`operator::OperatorDescription`) and
/// only `problem/executor.rs` turns a description into a backend, so no
/// other file of `problem` names an executor's concrete backend, its
/// device types or its module (the solve, the cascade, the refinement and
/// the smooth pad are written against `Executes` and `Backend`).
#[test]
fn only_the_executor_module_of_problem_names_the_executors() {
    let mut found = Vec::new();
    for (module, code) in engine_files() {
        let in_problem = module.first().is_some_and(|t| t == "problem");
        if !in_problem || module.get(1).is_some_and(|m| m == "executor") {
            continue;
        }
        for needle in [
            "CpuBackend",
            "GpuBackend",
            "GpuLevelTables",
            "Engine",
            "backend::cpu",
            "backend::gpu",
        ] {
            if code.contains(needle) {
                found.push(format!("{}: {needle}", module.join("::")));
            }
        }
    }
    assert!(
        found.is_empty(),
        "build backends in problem/executor.rs from an OperatorDescription:\n{}",
        found.join("\n")
    );
}

/// Progress, warnings and notes reach the front ends through observers
/// (`solver::Observer`, `sweep::SweepObserver`, `kernel::progress`, ...):
/// nothing below the command line names `clap` or `indicatif` or prints.
#[test]
fn nothing_below_the_front_ends_prints_or_parses_arguments() {
    let mut found = Vec::new();
    for (module, code) in engine_files() {
        for needle in ["clap", "indicatif", "eprintln!", "println!", "eprint!("] {
            if code.contains(needle) {
                found.push(format!("{}: {needle}", module.join("::")));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn the_files_form_no_circle() {
    let g = graph();
    // Depth-first search with colours; report the first circle found.
    fn visit(
        n: &Vec<String>,
        g: &Graph,
        state: &mut BTreeMap<Vec<String>, u8>,
        stack: &mut Vec<Vec<String>>,
    ) -> Option<Vec<Vec<String>>> {
        state.insert(n.clone(), 1);
        stack.push(n.clone());
        for m in g.edges.get(n).into_iter().flatten() {
            match state.get(m).copied().unwrap_or(0) {
                1 => {
                    let k = stack.iter().position(|s| s == m).unwrap();
                    let mut c = stack[k..].to_vec();
                    c.push(m.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(m, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in g.edges.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, &g, &mut state, &mut Vec::new()) {
                let names: Vec<String> = c.iter().map(|m| m.join("::")).collect();
                panic!("import circle: {}", names.join(" -> "));
            }
        }
    }
}

/// The checker itself: a made-up circle and an upward import are found.
#[test]
fn the_checker_sees_circles_and_upward_imports() {
    assert_eq!(
        expand("crate::a::{b, c::{d as e, self}}"),
        vec!["crate::a::b", "crate::a::c::d", "crate::a::c"]
    );
    let code =
        code_of("// use crate::cli;\nuse crate::config::Config;\nfn f() { crate::io::x(); }\n");
    let paths = paths_of(&code);
    assert_eq!(paths, vec!["crate::config::Config", "crate::io::x"]);
    assert!(layer_of("config") < layer_of("problem"));
    let here = vec!["analysis".to_string(), "fields".to_string()];
    assert_eq!(
        resolve("super::report::AnalysisReport", &here, false),
        Some(vec![
            "analysis".into(),
            "report".into(),
            "AnalysisReport".into()
        ])
    );
}

/// What the Python extension (`python/src/`) may name of the library: the
/// API modules whole (the engine types they take or return are re-exported
/// by `problem`), never `internals` (docs/ARCHITECTURE.md, "The Python
/// package").
const PYTHON_MAY_USE: &[(&str, &[&str])] = &[
    ("problem", &[]),
    ("config", &[]),
    ("material", &[]),
    ("surface", &[]),
    ("response", &[]),
    ("persson", &[]),
    ("heat", &[]),
    ("heating", &[]),
    ("magnification", &[]),
    ("sweep", &[]),
    ("Error", &[]),
    ("Result", &[]),
    ("VERSION", &[]),
];

/// Every `viscoslide::` path a file of the extension names: its `use`
/// trees expanded, and the paths in its other statements.
fn library_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    for statement in code.split(';') {
        let s = statement.trim();
        let tree = s
            .strip_prefix("pub use ")
            .or_else(|| s.strip_prefix("use "));
        if let Some(tree) = tree {
            out.extend(
                expand(tree)
                    .into_iter()
                    .filter(|p| p.starts_with("viscoslide::")),
            );
            continue;
        }
        let mut rest = s;
        while let Some(k) = rest.find("viscoslide::") {
            let tail = &rest[k..];
            let end = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(tail.len());
            out.push(tail[..end].trim_end_matches(':').to_string());
            rest = &rest[k + "viscoslide::".len()..];
        }
    }
    out
}

#[test]
fn the_python_extension_uses_only_the_library_api() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("python")
        .join("src");
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    assert!(!files.is_empty(), "no files under {}", dir.display());
    let mut bad = Vec::new();
    for file in &files {
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        for path in library_paths(&code) {
            let parts: Vec<&str> = path.split("::").collect();
            let allowed = PYTHON_MAY_USE.iter().find(|(m, _)| parts.get(1) == Some(m));
            let ok = match allowed {
                Some((_, [])) => true,
                Some((_, items)) => parts.get(2).is_some_and(|i| items.contains(i)),
                None => false,
            };
            if !ok {
                bad.push(format!("{}: {path}", file.display()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "the extension reaches below the library API:\n{}",
        bad.join("\n")
    );
    // The checker itself.
    let code = code_of(
        "use viscoslide::solver::{Observer, solve};\nfn f() { viscoslide::operator::x(); }",
    );
    assert_eq!(
        library_paths(&code),
        vec![
            "viscoslide::solver::Observer",
            "viscoslide::solver::solve",
            "viscoslide::operator::x"
        ]
    );
}

/// Small files with one job: no file of `src/` is over 600 lines unless
/// its header says why in one line (`//! Over 600 lines: ...`), and the
/// files of a solve (`problem/solve/`) stay under 250 lines each (issue
/// #39: the solve split by job, no formulation x executor matrix).
#[test]
fn files_stay_small_or_say_why() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut long = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let lines = text.lines().count();
        let rel = file.strip_prefix(src()).unwrap().display().to_string();
        let reason = text
            .lines()
            .take_while(|l| l.starts_with("//!") || l.trim().is_empty())
            .any(|l| l.starts_with("//! Over 600 lines"));
        if lines > 600 && !reason {
            long.push(format!(
                "{rel}: {lines} lines, no `//! Over 600 lines: ...` reason"
            ));
        }
        if rel.starts_with("problem/solve/") && lines > 250 {
            long.push(format!(
                "{rel}: {lines} lines, the solve's files stay under 250"
            ));
        }
    }
    assert!(long.is_empty(), "{}", long.join("\n"));
}
