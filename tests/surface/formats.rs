//! Surface file formats: ISO 25178-72 `.x3p` (read/write), Gwyddion `.gwy`
//! (read), missing data, and `viscoslide surface convert`.

use std::io::{Cursor, Write};
use std::path::Path;
use std::process::Command;

use md5::{Digest, Md5};
use viscoslide::surface::{
    decode_gwy, decode_x3p, encode_x3p, read_topography, MissingData, ReadOptions, Topography,
    X3pType,
};

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_viscoslide"))
        .args(args)
        .output()
        .unwrap()
}

/// A non-square map with non-square pixels and values that exercise every
/// bit of an f64.
fn topo() -> Topography {
    let (nx, ny) = (7, 5);
    let h: Vec<f64> = (0..nx * ny)
        .map(|k| 1e-6 * ((k as f64 * 0.731).sin() + 1.0 / (k as f64 + 3.0)))
        .collect();
    Topography::new(nx, ny, 1.25e-7, 2.5e-7, h, "t").unwrap()
}

fn hex(bytes: &[u8]) -> String {
    Md5::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn zip_of(entries: &[(&str, &[u8])]) -> Vec<u8> {
    let mut z = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for (name, bytes) in entries {
        z.start_file(*name, zip::write::SimpleFileOptions::default())
            .unwrap();
        z.write_all(bytes).unwrap();
    }
    z.finish().unwrap().into_inner()
}

#[test]
fn x3p_round_trip_f64_is_bit_exact_with_missing_points() {
    let mut t = topo();
    t.heights[3] = f64::NAN;
    t.heights[0] = -0.0;
    let bytes = encode_x3p(&t, X3pType::F64, Some("a & b < c")).unwrap();
    let back = decode_x3p(&bytes, "t.x3p").unwrap();
    assert_eq!((back.nx, back.ny), (7, 5));
    assert_eq!(back.dx.to_bits(), t.dx.to_bits());
    assert_eq!(back.dy.to_bits(), t.dy.to_bits());
    for (a, b) in t.heights.iter().zip(&back.heights) {
        if a.is_nan() {
            assert!(b.is_nan());
        } else {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }
    assert_eq!(back.missing(), 1);
}

#[test]
fn x3p_round_trip_is_exact_to_the_type_for_f32_and_i32() {
    let t = topo();
    let back = decode_x3p(&encode_x3p(&t, X3pType::F32, None).unwrap(), "f").unwrap();
    for (a, b) in t.heights.iter().zip(&back.heights) {
        assert_eq!(*b, *a as f32 as f64);
    }
    // i32: the second round trip reproduces the first exactly.
    let mut t2 = t.clone();
    t2.heights[4] = f64::NAN;
    let once = decode_x3p(&encode_x3p(&t2, X3pType::I32, None).unwrap(), "i").unwrap();
    let twice = decode_x3p(&encode_x3p(&once, X3pType::I32, None).unwrap(), "i").unwrap();
    let max = t.heights.iter().fold(0.0f64, |m, h| m.max(h.abs()));
    for k in 0..t.heights.len() {
        if k == 4 {
            assert!(once.heights[k].is_nan() && twice.heights[k].is_nan());
            continue;
        }
        assert!((once.heights[k] - t.heights[k]).abs() <= max / 2e9);
        assert_eq!(once.heights[k], twice.heights[k]);
    }
}

/// A hand-written x3p: int16 data in nanometre steps (z increment 1e-9 m,
/// offset 2e-6 m), incremental axes with different increments, a
/// non-square 3 x 2 map, a valid-points mask, checksums.
fn handmade(data_md5: Option<&str>, with_record4: bool) -> Vec<u8> {
    handmade_summed(data_md5, with_record4, |xml, _| {
        format!("{} *main.xml\n", hex(xml))
    })
}

/// [`handmade`] with the line of `md5checksum.hex` made by `sum(main.xml,
/// bindata/data.bin)`.
fn handmade_summed(
    data_md5: Option<&str>,
    with_record4: bool,
    sum: impl Fn(&[u8], &[u8]) -> String,
) -> Vec<u8> {
    let raw: [i16; 6] = [1, 2, 3, -4, 5, 6]; // x fastest
    let data: Vec<u8> = raw.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mask = [0b0011_1011u8]; // point 2 (x = 2, y = 0) invalid
    let good = hex(&data);
    let xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
 <Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType>
  <Axes>
   <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>5.0E-7</Increment><Offset>0</Offset></CX>
   <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1.0E-6</Increment><Offset>0</Offset></CY>
   <CZ><AxisType>A</AxisType><DataType>I</DataType><Increment>1e-9</Increment><Offset>2e-6</Offset></CZ>
  </Axes></Record1>
 <Record3><MatrixDimension><SizeX>3</SizeX><SizeY>2</SizeY><SizeZ>1</SizeZ></MatrixDimension>
  <DataLink><PointDataLink>bindata/data.bin</PointDataLink><MD5ChecksumPointData>{}</MD5ChecksumPointData>
  <ValidPointsLink>bindata/valid.bin</ValidPointsLink></DataLink></Record3>
 {}
</p:ISO5436_2>"#,
        data_md5.unwrap_or(&good),
        if with_record4 {
            "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>"
        } else {
            ""
        }
    );
    let sum = sum(xml.as_bytes(), &data);
    zip_of(&[
        ("main.xml", xml.as_bytes()),
        ("bindata/data.bin", &data),
        ("bindata/valid.bin", &mask),
        ("md5checksum.hex", sum.as_bytes()),
    ])
}

#[test]
fn x3p_incremental_axes_non_square_integer_nanometres() {
    let t = decode_x3p(&handmade(None, true), "h.x3p").unwrap();
    assert_eq!((t.nx, t.ny), (3, 2));
    assert_eq!((t.dx, t.dy), (5e-7, 1e-6));
    assert!((t.length_x() - 1.5e-6).abs() < 1e-20 && (t.length_y() - 2e-6).abs() < 1e-20);
    // heights[i * ny + j] = raw[i + nx j] * 1e-9 + 2e-6; point (2, 0) masked.
    let want = |raw: f64| raw * 1e-9 + 2e-6;
    assert_eq!(t.heights[0], want(1.0)); // (0, 0)
    assert_eq!(t.heights[1], want(-4.0)); // (0, 1)
    assert_eq!(t.heights[2], want(2.0)); // (1, 0)
    assert!(t.heights[4].is_nan()); // (2, 0)
    assert_eq!(t.heights[5], want(6.0)); // (2, 1)
    assert_eq!(t.missing(), 1);
}

#[test]
fn bad_x3p_files_are_one_line_errors() {
    let good = handmade(None, true);
    let mut truncated = good.clone();
    truncated.truncate(good.len() / 2);
    let mut flipped = good.clone();
    let mid = flipped.len() / 3;
    for b in &mut flipped[mid..mid + 8] {
        *b ^= 0x5a;
    }
    let wrong_sum = handmade(Some("0123456789abcdef0123456789abcdef"), false);
    let no_xml = zip_of(&[("bindata/data.bin", &[0u8; 12])]);
    // main.xml edited after its checksum was written.
    let bad_xml_sum = {
        let x = "<p:ISO5436_2 xmlns:p=\"x\"><Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4></p:ISO5436_2>";
        zip_of(&[
            ("main.xml", x.as_bytes()),
            (
                "md5checksum.hex",
                b"0123456789abcdef0123456789abcdef *main.xml\n",
            ),
        ])
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("truncated", truncated, ""),
        ("flipped", flipped, ""),
        (
            "wrong checksum",
            wrong_sum,
            "MD5 checksum of the point data",
        ),
        ("no main.xml", no_xml, "no 'main.xml'"),
        ("main.xml checksum", bad_xml_sum, "MD5 checksum of main.xml"),
        (
            "not a zip",
            b"hello world, this is not a zip".to_vec(),
            "zip",
        ),
    ];
    for (what, bytes, want) in cases {
        let e = decode_x3p(&bytes, "s.x3p").expect_err(what).to_string();
        assert!(e.starts_with("s.x3p: "), "{what}: {e}");
        assert!(e.contains(want), "{what}: {e}");
        assert!(!e.contains('\n'), "{what}: {e}");
    }
}

/// SurfaceTopography writes the checksum of `bindata/data.bin` into
/// `md5checksum.hex` and names that member: it is verified against that
/// member; a wrong one is an error naming the member, as is a member the
/// archive lacks.
#[test]
fn x3p_checksum_file_is_verified_against_the_member_it_names() {
    let reference = decode_x3p(&handmade(None, true), "h.x3p").unwrap();
    let st = handmade_summed(None, true, |_, data| {
        format!("{} *bindata/data.bin\n", hex(data))
    });
    let t = decode_x3p(&st, "st.x3p").unwrap();
    assert_eq!((t.nx, t.ny, t.dx, t.dy), (3, 2, 5e-7, 1e-6));
    for (a, b) in t.heights.iter().zip(&reference.heights) {
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()));
    }
    // Two spaces (text mode of md5sum) and a bare checksum of main.xml.
    let text_mode = handmade_summed(None, true, |_, data| {
        format!("{}  bindata/data.bin\n", hex(data))
    });
    assert!(decode_x3p(&text_mode, "t.x3p").is_ok());
    let bare = handmade_summed(None, true, |xml, _| format!("{}\n", hex(xml)));
    assert!(decode_x3p(&bare, "b.x3p").is_ok());
    // The checksum of main.xml said to be that of data.bin: matches nothing.
    let wrong = handmade_summed(None, true, |xml, _| {
        format!("{} *bindata/data.bin\n", hex(xml))
    });
    let e = decode_x3p(&wrong, "w.x3p").unwrap_err().to_string();
    assert!(e.starts_with("w.x3p: "), "{e}");
    assert!(e.contains("MD5 checksum of bindata/data.bin"), "{e}");
    assert!(e.contains("md5checksum.hex"), "{e}");
    assert!(!e.contains('\n'), "{e}");
    let absent = handmade_summed(None, true, |_, data| {
        format!("{} *bindata/other.bin\n", hex(data))
    });
    let e = decode_x3p(&absent, "a.x3p").unwrap_err().to_string();
    assert!(
        e.starts_with("a.x3p: ") && e.contains("'bindata/other.bin'"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}

/// A checksum file that holds no 32-digit checksum (truncated, garbage,
/// empty) is a corrupted file, as is a checksum file main.xml names
/// (Record4) that the archive lacks; the forms writers use (upper-case hex
/// as SurfaceTopography writes, a BOM, CRLF) still verify.
#[test]
fn x3p_checksum_files_that_hold_no_checksum_or_are_missing_are_refused() {
    for (what, text) in [
        ("truncated", "0123456789abcdef0123 *main.xml\n".to_string()),
        ("garbage", "hello world\n".to_string()),
        ("empty", String::new()),
        ("33 digits", format!("{}0 *main.xml\n", "a".repeat(32))),
    ] {
        let bytes = handmade_summed(None, true, |_, _| text.clone());
        let e = decode_x3p(&bytes, "c.x3p").expect_err(what).to_string();
        assert!(e.starts_with("c.x3p: "), "{what}: {e}");
        assert!(
            e.contains("md5checksum.hex") && e.contains("not an MD5 checksum"),
            "{what}: {e}"
        );
        assert!(e.contains("corrupted") && !e.contains('\n'), "{what}: {e}");
    }
    let upper = handmade_summed(None, true, |_, data| {
        format!("{} *bindata/data.bin\n", hex(data).to_uppercase())
    });
    assert!(decode_x3p(&upper, "u.x3p").is_ok());
    let bom_crlf = handmade_summed(None, true, |xml, _| {
        format!("\u{feff}{} *main.xml\r\n", hex(xml))
    });
    assert!(decode_x3p(&bom_crlf, "b.x3p").is_ok());
    // Without Record4 the checksum file is not looked at.
    let unnamed = handmade_summed(None, false, |_, _| "garbage".into());
    assert!(decode_x3p(&unnamed, "n.x3p").is_ok());

    // Our own writer names md5checksum.hex: without it the archive is damaged.
    let ours = encode_x3p(&topo(), X3pType::F64, None).unwrap();
    let mut zin = zip::ZipArchive::new(Cursor::new(&ours)).unwrap();
    let mut kept: Vec<(String, Vec<u8>)> = Vec::new();
    for k in 0..zin.len() {
        let mut f = zin.by_index(k).unwrap();
        let mut b = Vec::new();
        std::io::Read::read_to_end(&mut f, &mut b).unwrap();
        if f.name() != "md5checksum.hex" {
            kept.push((f.name().to_string(), b));
        }
    }
    let entries: Vec<(&str, &[u8])> = kept
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    let e = decode_x3p(&zip_of(&entries), "m.x3p")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("m.x3p: ") && e.contains("'md5checksum.hex'") && e.contains("Record4"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}

/// A minimal Gwyddion file: one data field, xy in micrometres, z in nm.
fn gwy_bytes(xres: usize, yres: usize, data: &[f64]) -> Vec<u8> {
    fn obj(name: &str, body: &[u8]) -> Vec<u8> {
        let mut v = name.as_bytes().to_vec();
        v.push(0);
        v.extend_from_slice(&(body.len() as u32).to_le_bytes());
        v.extend_from_slice(body);
        v
    }
    fn key(k: &str, t: u8) -> Vec<u8> {
        let mut v = k.as_bytes().to_vec();
        v.push(0);
        v.push(t);
        v
    }
    let unit = |s: &str| {
        let mut b = key("unitstr", b's');
        b.extend_from_slice(s.as_bytes());
        b.push(0);
        obj("GwySIUnit", &b)
    };
    let mut f = Vec::new();
    f.extend(key("xres", b'i'));
    f.extend((xres as i32).to_le_bytes());
    f.extend(key("yres", b'i'));
    f.extend((yres as i32).to_le_bytes());
    f.extend(key("xreal", b'd'));
    f.extend(3.0f64.to_le_bytes());
    f.extend(key("yreal", b'd'));
    f.extend(2.0f64.to_le_bytes());
    f.extend(key("si_unit_xy", b'o'));
    f.extend(unit("µm"));
    f.extend(key("si_unit_z", b'o'));
    f.extend(unit("nm"));
    f.extend(key("data", b'D'));
    f.extend((data.len() as u32).to_le_bytes());
    for v in data {
        f.extend(v.to_le_bytes());
    }
    let field = obj("GwyDataField", &f);
    let mut c = key("/0/data/title", b's');
    c.extend_from_slice(b"Height\0");
    c.extend(key("/0/data", b'o'));
    c.extend(field);
    let mut out = b"GWYP".to_vec();
    out.extend(obj("GwyContainer", &c));
    out
}

#[test]
fn gwy_first_field_with_units() {
    // 3 columns (x) by 2 rows (y); Gwyddion stores rows along x.
    let data = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let t = decode_gwy(&gwy_bytes(3, 2, &data), "g.gwy").unwrap();
    assert_eq!((t.nx, t.ny), (3, 2));
    assert!((t.dx - 1e-6).abs() < 1e-18 && (t.dy - 1e-6).abs() < 1e-18);
    assert!((t.heights[1] - 4e-9).abs() < 1e-21); // x = 0, y = 1
    assert!((t.heights[2 * 2] - 3e-9).abs() < 1e-21); // x = 2, y = 0
    let e = decode_gwy(b"GWYPxx", "g.gwy").unwrap_err().to_string();
    assert!(e.starts_with("g.gwy: ") && !e.contains('\n'), "{e}");
    let e = decode_gwy(b"PK\x03\x04", "g.gwy").unwrap_err().to_string();
    assert!(e.contains("not a Gwyddion file"), "{e}");
}

#[test]
fn missing_points_error_by_default_and_fill_harmonically() {
    let tmp = tempfile::tempdir().unwrap();
    // A plane is harmonic: the fill must reproduce it.
    let (nx, ny) = (12, 9);
    let plane = |i: usize, j: usize| 1e-6 * (0.3 * i as f64 - 0.7 * j as f64 + 2.0);
    let mut h: Vec<f64> = (0..nx * ny).map(|k| plane(k / ny, k % ny)).collect();
    for &(i, j) in &[(3, 3), (3, 4), (4, 3), (4, 4), (5, 4), (1, 1), (10, 7)] {
        h[i * ny + j] = f64::NAN;
    }
    let p = tmp.path().join("holes.npy");
    std::fs::write(&p, viscoslide::io::npy::encode_f64(&[nx, ny], &h)).unwrap();
    let mut opts = ReadOptions {
        length: Some(1e-5),
        ..Default::default()
    };
    let e = read_topography(&p, &opts).unwrap_err().to_string();
    assert!(e.contains("6.481 % of the points (7 of 108)"), "{e}");
    assert!(e.contains("--fill-missing"), "{e}");
    opts.missing = MissingData::Fill;
    let t = read_topography(&p, &opts).unwrap();
    assert_eq!(t.filled, 7);
    for k in 0..nx * ny {
        let want = plane(k / ny, k % ny);
        assert!((t.heights[k] - want).abs() < 1e-9 * 1e-6, "{k}");
    }

    // The CLI: an error and nothing written; with the flag, the output
    // records the fill.
    let out = tmp.path().join("out.x3p");
    let o = viscoslide(&[
        "surface",
        "convert",
        p.to_str().unwrap(),
        out.to_str().unwrap(),
        "--length",
        "1e-5",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists());
    let o = viscoslide(&[
        "surface",
        "convert",
        p.to_str().unwrap(),
        out.to_str().unwrap(),
        "--length",
        "1e-5",
        "--fill-missing",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("filled by harmonic"));
    let bytes = std::fs::read(&out).unwrap();
    let mut z = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut z.by_name("main.xml").unwrap(), &mut xml).unwrap();
    assert!(
        xml.contains("filled by harmonic (Laplace) interpolation"),
        "{xml}"
    );
}

#[test]
fn convert_cli_round_trips_and_refuses_bad_input() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let t = topo();
    std::fs::write(d.join("a.x3p"), encode_x3p(&t, X3pType::F64, None).unwrap()).unwrap();
    let run = |args: &[&str]| {
        let o = viscoslide(args);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let p = |n: &str| d.join(n).display().to_string();
    // x3p -> npy -> text -> x3p keeps every bit (non-square pixels need --length-y).
    run(&["surface", "convert", &p("a.x3p"), &p("b.npy")]);
    run(&[
        "surface",
        "convert",
        &p("b.npy"),
        &p("c.txt"),
        "--length",
        &t.length_x().to_string(),
        "--length-y",
        &t.length_y().to_string(),
    ]);
    run(&[
        "surface",
        "convert",
        &p("c.txt"),
        &p("d.x3p"),
        "--length",
        &t.length_x().to_string(),
        "--length-y",
        &t.length_y().to_string(),
    ]);
    let back = read_topography(Path::new(&p("d.x3p")), &ReadOptions::default()).unwrap();
    assert_eq!(
        back.heights.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        t.heights.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert!((back.dy / t.dy - 1.0).abs() < 1e-12);
    // Format override: a .bin that is an x3p.
    std::fs::copy(d.join("a.x3p"), d.join("a.bin")).unwrap();
    run(&[
        "surface",
        "convert",
        &p("a.bin"),
        &p("e.npy"),
        "--format",
        "x3p",
    ]);

    // Bad inputs: one line, nothing written.
    std::fs::write(d.join("bad.x3p"), b"PK\x03\x04 broken").unwrap();
    for args in [
        vec!["surface", "convert", &p("bad.x3p"), &p("out1.npy")],
        vec!["surface", "convert", &p("b.npy"), &p("out2.x3p")], // no --length
        vec!["surface", "convert", &p("a.x3p"), &p("out3.gwy")], // cannot write gwy
        vec![
            "surface",
            "convert",
            &p("a.x3p"),
            &p("out4.npy"),
            "--length",
            "1",
        ], // disagrees
        vec!["surface", "stats", &p("bad.x3p")],
    ] {
        let o = viscoslide(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
    }
    for n in ["out1.npy", "out2.x3p", "out3.gwy", "out4.npy"] {
        assert!(!d.join(n).exists(), "{n}");
    }
}

#[test]
fn solver_config_reads_x3p_with_override_and_fill() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let (n, a) = (16, 1e-5);
    let mut h: Vec<f64> = (0..n * n).map(|k| 1e-7 * (k as f64 * 0.1).sin()).collect();
    let t = Topography::new(n, n, a, a, h.clone(), "t").unwrap();
    std::fs::write(d.join("s.x3p"), encode_x3p(&t, X3pType::F64, None).unwrap()).unwrap();
    std::fs::copy(d.join("s.x3p"), d.join("s.dat")).unwrap();
    let load = |text: &str| {
        let p = d.join("c.toml");
        std::fs::write(&p, text).unwrap();
        let cfg = viscoslide::config::load(&p, &[]).unwrap();
        cfg.config.surface.unwrap().load(d)
    };
    // A scan: its mean plane removed by default, the heights as read with
    // detrend = "none".
    let m = load("[surface]\nfile = \"s.x3p\"\n").unwrap();
    assert_eq!((m.nx, m.ny, m.cell_size), (n, n, a));
    let plane = viscoslide::surface::detrend(&t, viscoslide::surface::Detrend::Plane);
    assert_eq!(m.heights, plane.heights);
    let m = load("[surface]\nfile = \"s.x3p\"\ndetrend = \"none\"\n").unwrap();
    assert_eq!(m.heights, h);
    let m = load("[surface]\nfile = \"s.dat\"\nformat = \"x3p\"\ndetrend = \"none\"\n").unwrap();
    assert_eq!(m.heights, h);
    // Missing points: refused, or filled on request.
    h[40] = f64::NAN;
    let t = Topography::new(n, n, a, a, h, "t").unwrap();
    std::fs::write(d.join("m.x3p"), encode_x3p(&t, X3pType::F32, None).unwrap()).unwrap();
    let e = load("[surface]\nfile = \"m.x3p\"\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing") && e.contains("fill_missing"), "{e}");
    let m = load("[surface]\nfile = \"m.x3p\"\nfill_missing = true\n").unwrap();
    assert!(m.heights.iter().all(|v| v.is_finite()));
}
