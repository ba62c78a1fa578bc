//! What the tests of study directories share: tiny configurations of a
//! sweep and of a magnification or refinement study, the command line run
//! with no fault injected, and the names in a directory.

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

/// A sweep of 6 points (3 speeds, the static one included, x 2 seeds) on
/// 32 x 32 cells.
pub const SWEEP: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3333333333333335e6
glassy_modulus = 1.0e7
creep_time = 0.01

[surface.generate]
n = 32
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 1

[loading]
normal_load = 0.30
xi = 1e-2

[analysis]
enabled = false

[sweep]
xi = [1e-3, 1e-2]
seeds = [1, 2]
"#;

/// A problem for magnification (`--scales 2,4,8`: up to 8 scales) and
/// refinement studies (`--levels 16,32`), solved in milliseconds.
pub const STUDY: &str = r#"
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
"#;

/// The command line, no fault injected.
pub fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_viscoslide"));
    c.env_remove("VISCOSLIDE_TEST_FAULT");
    c
}

/// The command line with every point's write slowed by half a second.
pub fn start_slow(args: &[&str]) -> Child {
    bin()
        .args(args)
        .env("VISCOSLIDE_TEST_FAULT", "slow-point")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

pub fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `text` written as `dir/case.toml`; its path.
pub fn config(dir: &Path, text: &str) -> String {
    let p = dir.join("case.toml");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

pub fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The names in `dir` (hidden ones included), sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}
