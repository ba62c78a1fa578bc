//! Robustness of the readers as a test: a seeded mutator of valid files
//! (bytes flipped, numbers of headers replaced by extreme ones, truncation,
//! duplication) over `.npy`, `.x3p` (zip and XML), `.gwy` and text, and of
//! configuration values. Every mutant must give `Ok` or an error: no
//! panic, no abort, and no allocation beyond a small multiple of the
//! input's size (counted by the allocator of this test binary). Bounded in
//! time: a fixed number of mutants per format (about a second each).

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::{Cursor, Write};
use std::sync::atomic::{AtomicUsize, Ordering};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use viscoslide::surface::{decode_gwy, decode_x3p, encode_x3p, parse_text, Topography, X3pType};

/// Counts the bytes live and the peak since the last [`reset_peak`].
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// The tests of this file run one at a time: the allocator's counts are
/// process-wide.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Run `f` on `input`; return the peak bytes allocated above those live
/// before, and whether it panicked.
fn measured(input: &[u8], f: &dyn Fn(&[u8])) -> (usize, bool) {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(input))).is_err();
    (PEAK.load(Ordering::Relaxed).saturating_sub(base), panicked)
}

/// Numbers that break careless size arithmetic.
const EXTREMES: &[&str] = &[
    "0",
    "1",
    "-1",
    "2147483648",
    "4294967296",
    "4294967297",
    "3037000500",
    "9223372036854775807",
    "18446744073709551615",
    "99999999999999999999999",
    "1e308",
    "nan",
    "-0",
];

/// One mutant of `valid`.
fn mutate(valid: &[u8], rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut b = valid.to_vec();
    for _ in 0..rng.random_range(1..4) {
        match rng.random_range(0..5) {
            // Flip bytes.
            0 => {
                for _ in 0..rng.random_range(1..8) {
                    let k = rng.random_range(0..b.len().max(1));
                    if let Some(x) = b.get_mut(k) {
                        *x ^= 1 << rng.random_range(0..8);
                    }
                }
            }
            // Replace a run of digits by an extreme number.
            1 => {
                let starts: Vec<usize> = (0..b.len())
                    .filter(|&k| b[k].is_ascii_digit() && (k == 0 || !b[k - 1].is_ascii_digit()))
                    .collect();
                if !starts.is_empty() {
                    let s = starts[rng.random_range(0..starts.len())];
                    let e = (s..b.len())
                        .find(|&k| !b[k].is_ascii_digit())
                        .unwrap_or(b.len());
                    let x = EXTREMES[rng.random_range(0..EXTREMES.len())];
                    b.splice(s..e, x.bytes());
                }
            }
            // Overwrite 4 or 8 bytes with an extreme little-endian integer.
            2 => {
                let v: u64 = match rng.random_range(0..4) {
                    0 => u64::MAX,
                    1 => 1 << 32,
                    2 => u32::MAX as u64,
                    _ => 1 << 62,
                };
                let w = if rng.random_bool(0.5) { 4 } else { 8 };
                if b.len() > w {
                    let k = rng.random_range(0..b.len() - w);
                    b[k..k + w].copy_from_slice(&v.to_le_bytes()[..w]);
                }
            }
            // Truncate.
            3 => {
                let k = rng.random_range(0..=b.len());
                b.truncate(k);
            }
            // Duplicate a slice.
            _ => {
                if b.len() > 2 {
                    let s = rng.random_range(0..b.len() - 1);
                    let e = rng.random_range(s + 1..b.len());
                    let piece = b[s..e].to_vec();
                    let at = rng.random_range(0..b.len());
                    b.splice(at..at, piece);
                }
            }
        }
    }
    b
}

/// Mutants of `valid` through `read`: none panics, none allocates more than
/// `ratio` times its size plus 1 MiB.
fn fuzz(name: &str, valid: &[u8], ratio: usize, count: usize, read: &dyn Fn(&[u8])) {
    let (_, panicked) = measured(valid, read);
    assert!(!panicked, "{name}: the valid file panics");
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed ^ name.len() as u64);
    let t0 = std::time::Instant::now();
    for k in 0..count {
        let m = mutate(valid, &mut rng);
        let (peak, panicked) = measured(&m, read);
        assert!(!panicked, "{name}: mutant {k} panics");
        let bound = ratio * m.len() + (1 << 20);
        assert!(
            peak <= bound,
            "{name}: mutant {k} of {} bytes allocated {peak} bytes (bound {bound})",
            m.len()
        );
    }
    eprintln!(
        "{name}: {count} mutants in {:.2} s",
        t0.elapsed().as_secs_f64()
    );
}

fn topo() -> Topography {
    let (nx, ny) = (6, 5);
    let h: Vec<f64> = (0..nx * ny)
        .map(|k| 1e-7 * (k as f64 * 0.37).sin())
        .collect();
    Topography::new(nx, ny, 1e-6, 2e-6, h, "t").unwrap()
}

fn gwy_valid() -> Vec<u8> {
    use common::gwy::{key, obj};
    let mut f = Vec::new();
    for (k, v) in [("xres", 4i32), ("yres", 3)] {
        f.extend(key(k, b'i'));
        f.extend(v.to_le_bytes());
    }
    for k in ["xreal", "yreal"] {
        f.extend(key(k, b'd'));
        f.extend(1e-6f64.to_le_bytes());
    }
    let mut unit = key("unitstr", b's');
    unit.extend(b"um\0");
    f.extend(key("si_unit_z", b'o'));
    f.extend(obj("GwySIUnit", &unit));
    f.extend(key("data", b'D'));
    f.extend(12u32.to_le_bytes());
    for k in 0..12 {
        f.extend((k as f64 * 0.1).to_le_bytes());
    }
    let mut top = key("/0/data", b'o');
    top.extend(obj("GwyDataField", &f));
    let mut b = b"GWYP".to_vec();
    b.extend(obj("GwyContainer", &top));
    b
}

/// An `.x3p` whose `main.xml` is stored uncompressed, so that mutations
/// reach its XML (sizes, types) as well as the zip structure.
fn x3p_stored() -> Vec<u8> {
    let bytes = encode_x3p(&topo(), X3pType::F64, None).unwrap();
    let mut z = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
    let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for i in 0..z.len() {
        let mut e = z.by_index(i).unwrap();
        let mut data = Vec::new();
        std::io::Read::read_to_end(&mut e, &mut data).unwrap();
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        w.start_file(e.name(), opts).unwrap();
        w.write_all(&data).unwrap();
    }
    w.finish().unwrap().into_inner()
}

#[test]
fn mutated_files_neither_panic_nor_over_allocate() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let npy = viscoslide::io::npy::encode_f64(&[6, 5], &topo().heights);
    fuzz("npy", &npy, 16, 3000, &|b| {
        let _ = viscoslide::io::npy::decode(b, "m.npy");
    });
    fuzz("gwy", &gwy_valid(), 16, 3000, &|b| {
        let _ = decode_gwy(b, "m.gwy");
    });
    let text = "# heights\n1 2 3\n4,5,6\n7 8 9 # c\n";
    fuzz("text", text.as_bytes(), 64, 3000, &|b| {
        let _ = parse_text(&String::from_utf8_lossy(b), "m.txt", 0.01);
    });
    // Deflate may legitimately expand 1032-fold; the reader allows no more.
    let x3p = encode_x3p(&topo(), X3pType::F64, None).unwrap();
    fuzz("x3p (deflated)", &x3p, 1100, 1500, &|b| {
        let _ = decode_x3p(b, "m.x3p");
    });
    fuzz("x3p (stored)", &x3p_stored(), 1100, 1500, &|b| {
        let _ = decode_x3p(b, "m.x3p");
    });
}

/// Configuration values: each numeric value of a valid configuration
/// replaced by extreme ones; building the problem must give `Ok` or an
/// error. The grid side is kept (a valid large grid is real work).
#[test]
fn extreme_configuration_values_give_errors_not_panics() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    const CONFIG: &str = r#"
[material]
model = "sls"
relaxed_modulus = 3.3e6
glassy_modulus = 1.0e7
creep_time = 0.01
poisson = 0.5

[surface.generate]
n = 16
length = 0.01
hurst = 0.8
scales = 4
rms_slope = 0.02
seed = 1

[loading]
normal_load = 0.30
xi = 1e-2

[solver]
tolerance = 1e-8
restart = 30
"#;
    let doc: toml::Table = toml::from_str(CONFIG).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let values = [
        "0",
        "-1",
        "1e300",
        "-1e300",
        "1e-300",
        "nan",
        "inf",
        "9223372036854775807",
        "-0.0",
        "\"x\"",
    ];
    fn leaves(t: &toml::Table, at: &str, out: &mut Vec<String>) {
        for (k, v) in t {
            let path = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            match v.as_table() {
                Some(sub) => leaves(sub, &path, out),
                None if k != "n" && k != "model" => out.push(path),
                None => {}
            }
        }
    }
    let mut keys = Vec::new();
    leaves(&doc, "", &mut keys);
    let mut tried = 0;
    for key in &keys {
        {
            for v in values {
                let path = tmp.path().join("c.toml");
                std::fs::write(&path, CONFIG).unwrap();
                let set = format!("{key}={v}");
                let outcome = std::panic::catch_unwind(|| {
                    viscoslide::config::load(&path, std::slice::from_ref(&set))
                        .map_err(viscoslide::Error::from)
                        .and_then(|c| viscoslide::problem::Problem::from_config(&c))
                        .map(|_| ())
                });
                assert!(outcome.is_ok(), "--set {set} panics");
                tried += 1;
            }
        }
    }
    assert!(tried > 100, "{tried}");
}
