//! Height-map files and the `[surface]` config section.

use std::path::Path;

use viscoslide::io::npy::{self, NpyError};
use viscoslide::surface::{
    detrend, encode_npy, generate, load_npy, parse_text, read_height_map, save_npy, Detrend,
    GenerateParams, HeightMap, Normalisation, NpyPrecision, SurfaceConfig, SurfaceError,
    Topography, UpperCutoff,
};

fn small_map() -> HeightMap {
    generate(&GenerateParams {
        nx: 24,
        ny: 20,
        length: 2e-3,
        hurst: 0.7,
        upper: UpperCutoff::Scales(8.0),
        normalisation: Normalisation::RmsHeight(1e-6),
        seed: 3,
        ..GenerateParams::default()
    })
    .unwrap()
}

fn patch_header(bytes: &mut [u8], from: &[u8], to: &[u8]) {
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = &mut bytes[10..10 + hlen];
    let at = header.windows(from.len()).position(|w| w == from).unwrap();
    header[at..at + to.len()].copy_from_slice(to);
}

#[test]
fn npy_round_trip_f64_is_bit_exact() {
    let tmp = tempfile::tempdir().unwrap();
    let mut map = small_map();
    // Values that a lossy path would disturb.
    map.heights[0] = -0.0;
    map.heights[1] = f64::MIN_POSITIVE / 8.0; // subnormal
    map.heights[2] = 1.0 + f64::EPSILON;
    let p = tmp.path().join("h.npy");
    save_npy(&map, &p, NpyPrecision::F64).unwrap();
    let back = load_npy(&p, map.length_x()).unwrap();
    assert_eq!((back.nx, back.ny), (24, 20));
    assert_eq!(back.cell_size.to_bits(), map.cell_size.to_bits());
    assert!(back
        .heights
        .iter()
        .zip(&map.heights)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn npy_round_trip_f32_within_rounding() {
    let tmp = tempfile::tempdir().unwrap();
    let map = small_map();
    let p = tmp.path().join("h32.npy");
    save_npy(&map, &p, NpyPrecision::F32).unwrap();
    assert_eq!(npy::read(&p).unwrap().dtype, npy::NpyDtype::F32);
    let back = load_npy(&p, map.length_x()).unwrap();
    let mut worst: f64 = 0.0;
    for (a, b) in back.heights.iter().zip(&map.heights) {
        // Round to nearest f32: relative error at most 2^-24.
        assert_eq!(*a, *b as f32 as f64);
        worst = worst.max((a - b).abs() / b.abs());
    }
    eprintln!("f32 round trip: worst relative error {worst:.2e} (bound 5.96e-8)");
    assert!(worst <= 2f64.powi(-24));
}

#[test]
fn text_matrix_reads_rows_as_x() {
    let text = "# measured map\n1.0 2.0, 3.0\n\n4e-1,5,6   # trailing comment\n7 8 9\n";
    let m = parse_text(text, "t.txt", 3.0).unwrap();
    assert_eq!((m.nx, m.ny), (3, 3));
    assert_eq!(m.cell_size, 1.0);
    assert_eq!(m.at(1, 0), 0.4);
    assert_eq!(m.at(2, 2), 9.0);
}

/// Under a size header (SurfaceTopography's `to_matrix`) rows are y, and
/// the sides and heights are in the header's units.
#[test]
fn text_matrix_under_a_size_header_reads_rows_as_y() {
    let text = "# Width: 3 mm\n# Height: 4 mm\n# Value units: nm\n1 2 3\n4 5 6\n";
    let m = parse_text(text, "st.txt", 3e-3).unwrap();
    assert_eq!((m.nx, m.ny), (3, 2));
    assert!((m.cell_size / 1e-3 - 1.0).abs() < 1e-12, "{}", m.cell_size);
    assert!(
        (m.cell_size_y / 2e-3 - 1.0).abs() < 1e-12,
        "{}",
        m.cell_size_y
    );
    assert_eq!(m.at(2, 0), 3.0 * 1e-9);
    assert_eq!(m.at(0, 1), 4.0 * 1e-9);
    let e = parse_text(text, "st.txt", 1e-3).unwrap_err().to_string();
    assert!(
        e.contains("3.000000e-3") && e.contains("1.000000e-3"),
        "{e}"
    );
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// Every bad input has its own error variant and a one-line message naming
/// the file and what is wrong.
#[test]
fn bad_inputs_have_distinct_one_line_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let good = npy::encode_f64(&[3, 4], &[0.0; 12]);
    let mut nan = vec![0.0; 12];
    nan[6] = f64::NAN;
    let mut inf = vec![0.0; 12];
    inf[11] = f64::NEG_INFINITY;
    let mut int = good.clone();
    patch_header(&mut int, b"<f8", b"<i8");

    let cases: Vec<(std::path::PathBuf, f64, &str)> = vec![
        (
            write(d, "rank1.npy", &npy::encode_f64(&[12], &[0.0; 12])),
            1.0,
            "shape",
        ),
        (
            write(d, "rank3.npy", &npy::encode_f64(&[2, 2, 3], &[0.0; 12])),
            1.0,
            "shape",
        ),
        (
            write(d, "thin.npy", &npy::encode_f64(&[1, 12], &[0.0; 12])),
            1.0,
            "shape",
        ),
        (
            write(d, "nan.npy", &npy::encode_f64(&[3, 4], &nan)),
            1.0,
            "nan",
        ),
        (
            write(d, "inf.npy", &npy::encode_f64(&[3, 4], &inf)),
            1.0,
            "inf",
        ),
        (write(d, "int.npy", &int), 1.0, "dtype"),
        (
            write(d, "short.npy", &good[..good.len() - 5]),
            1.0,
            "truncated",
        ),
        (write(d, "magic.npy", b"not numpy at all"), 1.0, "magic"),
        (
            write(d, "ragged.txt", b"1 2 3\n4 5 6\n7 8\n"),
            1.0,
            "ragged",
        ),
        (write(d, "word.txt", b"1 2\n3 x\n"), 1.0, "number"),
        (write(d, "nan.txt", b"1 2\n3 nan\n"), 1.0, "nan"),
        (write(d, "ok.npy", &good), 0.0, "length"),
        (d.join("missing.npy"), 1.0, "io"),
    ];
    let mut messages = Vec::new();
    for (path, length, kind) in &cases {
        let e = read_height_map(path, *length).unwrap_err();
        let ok = match *kind {
            "shape" => matches!(e, SurfaceError::Shape { .. }),
            "nan" => matches!(e, SurfaceError::NonFinite { value, .. } if value.is_nan()),
            "inf" => matches!(e, SurfaceError::NonFinite { row: 2, col: 3, .. }),
            "dtype" => matches!(e, SurfaceError::Npy(NpyError::UnsupportedDtype { .. })),
            "truncated" => matches!(e, SurfaceError::Npy(NpyError::Truncated { .. })),
            "magic" => matches!(e, SurfaceError::Npy(NpyError::BadMagic { .. })),
            "ragged" => matches!(
                e,
                SurfaceError::Ragged {
                    line: 3,
                    expected: 3,
                    found: 2,
                    ..
                }
            ),
            "number" => matches!(e, SurfaceError::TextNumber { line: 2, .. }),
            "length" => matches!(e, SurfaceError::Parameter { name: "length", .. }),
            "io" => matches!(e, SurfaceError::Npy(NpyError::Io { .. })),
            _ => unreachable!(),
        };
        let msg = e.to_string();
        eprintln!("{kind:>9}: {msg}");
        assert!(ok, "{}: expected {kind}, got {e:?}", path.display());
        assert!(!msg.contains('\n'), "one line: {msg}");
        if *kind != "length" {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            assert!(msg.contains(&name), "names the file: {msg}");
        }
        messages.push(msg);
    }
    // The NaN error names the first bad index [row, col] = [1, 2].
    assert!(messages[3].contains("[1, 2]"), "{}", messages[3]);
}

fn config(dir: &Path, text: &str) -> SurfaceConfig {
    let p = dir.join("c.toml");
    std::fs::write(&p, text).unwrap();
    viscoslide::config::load(&p, &[])
        .unwrap()
        .config
        .surface
        .unwrap()
}

#[test]
fn config_file_or_generate() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::create_dir(d.join("maps")).unwrap();
    let map = small_map();
    std::fs::write(d.join("maps/h.npy"), encode_npy(&map, NpyPrecision::F64)).unwrap();

    // A file relative to the config directory: a scan loses its mean
    // plane by default (the one preprocessing rule) ...
    let c = config(d, "[surface]\nfile = \"maps/h.npy\"\nlength = 2e-3\n");
    let plane = detrend(&Topography::from_height_map(&map), Detrend::Plane)
        .to_height_map("h")
        .unwrap();
    assert_eq!(c.load(d).unwrap(), plane);
    // ... and is taken as it is when marked periodic or not detrended.
    for key in ["periodic = true", "detrend = \"none\""] {
        let c = config(
            d,
            &format!("[surface]\nfile = \"maps/h.npy\"\nlength = 2e-3\n{key}\n"),
        );
        assert_eq!(c.load(d).unwrap(), map, "{key}");
    }
    // `length` is required with `file`.
    let c = config(d, "[surface]\nfile = \"maps/h.npy\"\n");
    assert!(c.load(d).unwrap_err().to_string().contains("length"));

    // Generated: the same surface as the library call.
    let gen = "[surface.generate]\nn = 24\nny = 20\nlength = 2e-3\nhurst = 0.7\nscales = 8\nrms_height = 1e-6\nseed = 3\n";
    let c = config(d, &format!("[surface]\n{gen}"));
    assert_eq!(c.load(d).unwrap(), map);
    // `length` may come from [surface].
    let c = config(
        d,
        &gen.replace("length = 2e-3\n", "").replace(
            "[surface.generate]",
            "[surface]\nlength = 2e-3\n[surface.generate]",
        ),
    );
    assert_eq!(c.load(d).unwrap(), map);

    // Exactly one source.
    let c = config(
        d,
        &format!("[surface]\nfile = \"maps/h.npy\"\nlength = 2e-3\n{gen}"),
    );
    assert!(c.load(d).unwrap_err().to_string().contains("both"));
    let c = config(d, "[surface]\nlength = 2e-3\n");
    assert!(c.load(d).unwrap_err().to_string().contains("either"));
    // Exactly one of rms_height / rms_slope, and of scales / q1.
    let c = config(d, &format!("[surface]\n{gen}rms_slope = 0.1\n"));
    assert!(c.load(d).unwrap_err().to_string().contains("rms_slope"));
    let c = config(d, &format!("[surface]\n{gen}q1 = 1e4\n"));
    assert!(c.load(d).unwrap_err().to_string().contains("q1"));
    // Anisotropy table.
    let c = config(
        d,
        &format!("[surface]\n{gen}anisotropy = {{ ratio = 2.0, angle_deg = 30.0 }}\n"),
    );
    let p = c.generate_params().unwrap().unwrap();
    assert_eq!(p.anisotropy.unwrap().ratio, 2.0);

    // Unknown keys are rejected by the config loader.
    let p = d.join("bad.toml");
    std::fs::write(&p, format!("[surface]\n{gen}hurts = 0.5\n")).unwrap();
    let e = viscoslide::config::load(&p, &[]).unwrap_err().to_string();
    assert!(e.contains("hurts"), "{e}");
}
