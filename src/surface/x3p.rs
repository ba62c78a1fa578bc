//! ISO 25178-72 XML 3D surface profile (`.x3p`) files, read and write.
//!
//! An x3p file is a zip archive holding `main.xml` (the description:
//! `Record1` axes, `Record2` provenance, `Record3` the matrix size and where
//! the data are, `Record4` the name of the checksum file), the binary point
//! data (little endian, x index fastest: point `(i, j)` at `i + nx j`), an
//! optional valid-points mask (one bit per point, least significant bit
//! first, 1 = valid) and `md5checksum.hex`, the MD5 of `main.xml` (written
//! so; read against whichever member it names, see `verify_checksum_file`).
//!
//! Supported, as the standard allows for a surface (`FeatureType` `SUR`):
//! incremental x and y axes (`AxisType` `I`, `Increment` \[m\]), an absolute
//! z axis of data type `I` (int16), `L` (int32), `F` (float32) or `D`
//! (float64), scaled by the optional z `Increment` and `Offset`
//! (`z = raw * Increment + Offset`); point data in a linked binary file or
//! inline (`DataList`). All lengths are in metres, as the standard fixes.
//! Invalid points (NaN in float data, a 0 bit in the mask) become `NaN`.
//! Every MD5 checksum present (point data, valid points, `main.xml`) is
//! verified; a mismatch is an error.
//!
//! Over 600 lines: one file format, its reader (zip, XML, MD5 checks) and
//! its writer, kept together so that the round-trip conventions (axes, data
//! types, checksums) live in one place.

use std::collections::HashMap;
use std::io::{Cursor, Read, Write};
use std::path::Path;

use crate::io::digest::md5_hex;
use quick_xml::events::Event;
use serde::{Deserialize, Serialize};

use super::{SurfaceError, Topography};

/// Data type of the z axis when writing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum X3pType {
    /// float64 (`D`), bit-exact.
    #[default]
    F64,
    /// float32 (`F`), heights rounded to the nearest f32.
    F32,
    /// int32 (`L`) with a z increment of `max|h| / 2e9` m: heights rounded
    /// to that step.
    I32,
}

fn fail(name: &str, why: impl std::fmt::Display) -> SurfaceError {
    SurfaceError::File {
        path: name.to_string(),
        why: why.to_string(),
    }
}

/// Leaves of an XML document: `(path, text)` with the path of element
/// local names below the root, joined by `/`, in document order.
fn xml_leaves(text: &str) -> Result<Vec<(String, String)>, String> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut stack: Vec<String> = Vec::new();
    let mut buf = String::new();
    let mut out = Vec::new();
    let path = |stack: &[String]| stack.get(1..).unwrap_or(&[]).join("/");
    loop {
        match reader.read_event().map_err(|e| {
            format!(
                "main.xml is not well-formed XML at byte {}: {e}",
                reader.error_position()
            )
        })? {
            Event::Start(e) => {
                stack.push(String::from_utf8_lossy(e.local_name().as_ref()).into_owned());
                buf.clear();
            }
            Event::Empty(e) => {
                stack.push(String::from_utf8_lossy(e.local_name().as_ref()).into_owned());
                out.push((path(&stack), String::new()));
                stack.pop();
            }
            Event::Text(t) => {
                buf.push_str(&t.decode().map_err(|e| format!("main.xml: {e}"))?);
            }
            Event::CData(t) => buf.push_str(&String::from_utf8_lossy(&t.into_inner())),
            Event::GeneralRef(r) => {
                let name = r.decode().map_err(|e| format!("main.xml: {e}"))?;
                let s = match name.as_ref() {
                    "amp" => "&".to_string(),
                    "lt" => "<".into(),
                    "gt" => ">".into(),
                    "quot" => "\"".into(),
                    "apos" => "'".into(),
                    other => other
                        .strip_prefix("#x")
                        .and_then(|h| u32::from_str_radix(h, 16).ok())
                        .or_else(|| other.strip_prefix('#').and_then(|d| d.parse().ok()))
                        .and_then(char::from_u32)
                        .map(String::from)
                        .unwrap_or_default(),
                };
                buf.push_str(&s);
            }
            Event::End(_) => {
                let t = buf.trim();
                if !t.is_empty() {
                    out.push((path(&stack), t.to_string()));
                }
                buf.clear();
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if out.is_empty() && stack.is_empty() {
        return Err("main.xml holds no XML elements".into());
    }
    Ok(out)
}

struct Doc<'a> {
    name: &'a str,
    map: HashMap<&'a str, &'a str>,
}

impl<'a> Doc<'a> {
    fn new(name: &'a str, leaves: &'a [(String, String)]) -> Self {
        let mut map = HashMap::new();
        for (p, t) in leaves {
            map.entry(p.as_str()).or_insert(t.as_str());
        }
        Self { name, map }
    }
    fn get(&self, key: &str) -> Option<&'a str> {
        self.map.get(key).copied()
    }
    fn need(&self, key: &str) -> Result<&'a str, SurfaceError> {
        self.get(key)
            .ok_or_else(|| fail(self.name, format!("main.xml has no <{key}>")))
    }
    fn number<T: std::str::FromStr>(&self, key: &str) -> Result<Option<T>, SurfaceError> {
        self.get(key)
            .map(|s| {
                s.trim().parse::<T>().map_err(|_| {
                    fail(
                        self.name,
                        format!("main.xml: <{key}> = '{s}' is not a valid number"),
                    )
                })
            })
            .transpose()
    }
}

/// The largest ratio of inflated to deflated size (RFC 1951: a 258-byte
/// match in about two bits).
const MAX_DEFLATE_RATIO: u64 = 1032;

fn read_entry<R: Read + std::io::Seek>(
    zip: &mut zip::ZipArchive<R>,
    entry: &str,
    name: &str,
) -> Result<Vec<u8>, SurfaceError> {
    read_entry_sized(zip, entry, name, None)
}

/// The bytes of `entry`, inflated only after its declared size is checked
/// against `expected` (when the caller knows it) and against the memory
/// available; no more than the declared size is ever inflated, so an entry
/// whose header understates its data is an error, not an allocation.
fn read_entry_sized<R: Read + std::io::Seek>(
    zip: &mut zip::ZipArchive<R>,
    entry: &str,
    name: &str,
    expected: Option<(u64, &str)>,
) -> Result<Vec<u8>, SurfaceError> {
    let f = zip.by_name(entry).map_err(|e| match e {
        zip::result::ZipError::FileNotFound => fail(name, format!("the archive has no '{entry}'")),
        other => fail(
            name,
            format!("cannot open '{entry}' in the archive: {other}"),
        ),
    })?;
    let declared = f.size();
    // Deflate expands at most 1032-fold: a larger declared size is a lie.
    let inflatable = f.compressed_size().saturating_mul(MAX_DEFLATE_RATIO);
    if declared > inflatable.max(f.compressed_size()) {
        return Err(fail(
            name,
            format!(
                "'{entry}' declares {declared} bytes, more than its {} compressed bytes can hold",
                f.compressed_size()
            ),
        ));
    }
    if let Some((need, what)) = expected {
        if declared != need {
            return Err(fail(
                name,
                format!("'{entry}' holds {declared} bytes; {what} need {need}"),
            ));
        }
    }
    crate::io::memory::check_fits(|| format!("'{entry}' of {declared} bytes"), declared)
        .map_err(|e| fail(name, e))?;
    let mut bytes = Vec::with_capacity(declared as usize);
    f.take(declared.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| fail(name, format!("cannot read '{entry}' from the archive: {e}")))?;
    if bytes.len() as u64 != declared {
        return Err(fail(
            name,
            format!("'{entry}' does not inflate to the {declared} bytes its header declares"),
        ));
    }
    Ok(bytes)
}

fn check_md5(
    doc: &Doc,
    key: &str,
    bytes: &[u8],
    what: &str,
    name: &str,
) -> Result<(), SurfaceError> {
    if let Some(expected) = doc.get(key) {
        let expected = expected.trim().to_ascii_lowercase();
        let got = md5_hex(bytes);
        if expected != got {
            return Err(fail(
                name,
                format!("MD5 checksum of the {what} is {got}, main.xml says {expected}: the file is corrupted"),
            ));
        }
    }
    Ok(())
}

/// Verify the checksum file `sum_file` (text `text`, `md5sum` format:
/// `<hex> *<member>` or `<hex>  <member>`, or a bare `<hex>`, hex digits in
/// either case) against the member it names: `main.xml` per ISO 25178-72
/// (also when no member is named), or another member of the archive
/// (SurfaceTopography names `bindata/data.bin`). A checksum file that
/// holds no 32-digit checksum, a checksum that does not match its member,
/// or one that names a member the archive lacks, is an error naming them.
fn verify_checksum_file<R: Read + std::io::Seek>(
    zip: &mut zip::ZipArchive<R>,
    sum_file: &str,
    text: &[u8],
    xml_bytes: &[u8],
    name: &str,
) -> Result<(), SurfaceError> {
    let text = String::from_utf8_lossy(text);
    let line = text
        .trim_start_matches('\u{feff}')
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("");
    let (expected, member) = match line.split_once(char::is_whitespace) {
        Some((hex, rest)) => (hex, rest.trim().trim_start_matches('*').trim()),
        None => (line, ""),
    };
    if expected.len() != 32 || !expected.bytes().all(|b| b.is_ascii_hexdigit()) {
        let shown: String = expected.chars().take(40).collect();
        return Err(fail(
            name,
            format!("{sum_file} holds '{shown}', not an MD5 checksum (32 hex digits): the file is corrupted"),
        ));
    }
    let expected = expected.to_ascii_lowercase();
    let member = if member.is_empty() {
        "main.xml"
    } else {
        member
    };
    let got = if member == "main.xml" {
        md5_hex(xml_bytes)
    } else {
        if zip.index_for_name(member).is_none() {
            return Err(fail(
                name,
                format!("{sum_file} holds the checksum of '{member}', which the archive does not have: the file is corrupted"),
            ));
        }
        md5_hex(&read_entry(zip, member, name)?)
    };
    if expected != got {
        return Err(fail(
            name,
            format!("MD5 checksum of {member} is {got}, {sum_file} says {expected}: the file is corrupted"),
        ));
    }
    Ok(())
}

/// Read an `.x3p` file.
pub fn read_x3p(path: &Path) -> Result<Topography, SurfaceError> {
    let bytes = std::fs::read(path).map_err(|source| SurfaceError::Io {
        path: path.display().to_string(),
        source,
    })?;
    decode_x3p(&bytes, &path.display().to_string())
}

/// Decode the bytes of an `.x3p` file; `name` labels errors.
pub fn decode_x3p(bytes: &[u8], name: &str) -> Result<Topography, SurfaceError> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| fail(name, format!("not a readable x3p (zip) archive: {e}")))?;
    let xml_bytes = read_entry(&mut zip, "main.xml", name)?;
    let xml =
        std::str::from_utf8(&xml_bytes).map_err(|_| fail(name, "main.xml is not UTF-8 text"))?;
    let leaves = xml_leaves(xml).map_err(|e| fail(name, e))?;
    let doc = Doc::new(name, &leaves);

    // md5checksum.hex (Record4) against the member it names. The writers
    // that name it (the openGPS reference library, SurfaceTopography, R's
    // x3ptools, viscoslide) all put it into the archive: named but absent,
    // the archive is damaged.
    if let Some(sum_file) = doc.get("Record4/ChecksumFile") {
        if zip.index_for_name(sum_file).is_none() {
            return Err(fail(
                name,
                format!("main.xml names the checksum file '{sum_file}' (Record4), which the archive does not have: the file is corrupted"),
            ));
        }
        let text = read_entry(&mut zip, sum_file, name)?;
        verify_checksum_file(&mut zip, sum_file, &text, &xml_bytes, name)?;
    }

    if let Some(ft) = doc.get("Record1/FeatureType") {
        if ft.trim() != "SUR" {
            return Err(fail(
                name,
                format!("feature type '{ft}' is not a surface (SUR); profiles and point clouds are not supported"),
            ));
        }
    }
    let mut inc = [0.0; 2];
    for (k, axis) in ["CX", "CY"].iter().enumerate() {
        let t = doc.need(&format!("Record1/Axes/{axis}/AxisType"))?;
        if t.trim() != "I" {
            return Err(fail(
                name,
                format!("axis {axis} has AxisType '{t}'; only incremental (I) x and y axes are supported"),
            ));
        }
        let v: f64 = doc
            .number(&format!("Record1/Axes/{axis}/Increment"))?
            .ok_or_else(|| fail(name, format!("incremental axis {axis} has no <Increment>")))?;
        if !(v.is_finite() && v > 0.0) {
            return Err(fail(
                name,
                format!("axis {axis} increment {v} must be finite and > 0 (m)"),
            ));
        }
        inc[k] = v;
    }
    let zt = doc.need("Record1/Axes/CZ/AxisType")?;
    if zt.trim() != "A" {
        return Err(fail(
            name,
            format!("axis CZ has AxisType '{zt}'; the standard requires absolute (A)"),
        ));
    }
    let dtype = doc.need("Record1/Axes/CZ/DataType")?.trim();
    let width = match dtype {
        "I" => 2,
        "L" => 4,
        "F" => 4,
        "D" => 8,
        other => {
            return Err(fail(
                name,
                format!("z data type '{other}' is not one of I, L, F, D"),
            ))
        }
    };
    let z_inc: f64 = doc.number("Record1/Axes/CZ/Increment")?.unwrap_or(1.0);
    let z_off: f64 = doc.number("Record1/Axes/CZ/Offset")?.unwrap_or(0.0);
    if !(z_inc.is_finite() && z_inc != 0.0 && z_off.is_finite()) {
        return Err(fail(
            name,
            format!("z increment {z_inc} / offset {z_off} must be finite (increment non-zero)"),
        ));
    }
    let size = |k: &str| -> Result<usize, SurfaceError> {
        doc.number::<usize>(&format!("Record3/MatrixDimension/{k}"))?
            .ok_or_else(|| fail(name, format!("main.xml has no <MatrixDimension><{k}>")))
    };
    let (nx, ny, nz) = (size("SizeX")?, size("SizeY")?, size("SizeZ")?);
    if nz != 1 {
        return Err(fail(
            name,
            format!("SizeZ = {nz}: only single-layer surfaces (SizeZ = 1) are supported"),
        ));
    }
    if nx < 2 || ny < 2 {
        return Err(fail(
            name,
            format!("matrix {nx} x {ny} must be at least 2 x 2"),
        ));
    }
    // Checked sizes: a product that overflows is refused, not wrapped.
    let (n, need) = match nx.checked_mul(ny) {
        Some(n) => (n, (n as u64).checked_mul(width as u64)),
        None => (0, None),
    };
    let need = need.ok_or_else(|| {
        fail(
            name,
            format!("matrix {nx} x {ny} of type {dtype} needs more than 2^64 bytes"),
        )
    })?;

    // Raw values in file order (x fastest).
    let raw: Vec<f64> = if let Some(link) = doc.get("Record3/DataLink/PointDataLink") {
        let what = format!("{nx} x {ny} points of type {dtype}");
        let data = read_entry_sized(&mut zip, link.trim(), name, Some((need, &what)))?;
        check_md5(
            &doc,
            "Record3/DataLink/MD5ChecksumPointData",
            &data,
            "point data",
            name,
        )?;
        let c = data.chunks_exact(width);
        match dtype {
            "I" => c.map(|b| i16::from_le_bytes([b[0], b[1]]) as f64).collect(),
            "L" => c
                .map(|b| i32::from_le_bytes(b.try_into().expect("4 bytes")) as f64)
                .collect(),
            "F" => c
                .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")) as f64)
                .collect(),
            _ => c
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect(),
        }
    } else {
        let list: Vec<&str> = leaves
            .iter()
            .filter(|(p, _)| p == "Record3/DataList/Datum")
            .map(|(_, t)| t.as_str())
            .collect();
        if list.is_empty() {
            return Err(fail(
                name,
                "main.xml has neither <DataLink><PointDataLink> nor <DataList>",
            ));
        }
        if list.len() != n {
            return Err(fail(
                name,
                format!("<DataList> holds {} values; {nx} x {ny} needed", list.len()),
            ));
        }
        list.iter()
            .map(|s| {
                let s = s.trim();
                if s.is_empty() {
                    Ok(f64::NAN)
                } else {
                    s.parse::<f64>()
                        .map_err(|_| fail(name, format!("<Datum> '{s}' is not a number")))
                }
            })
            .collect::<Result<_, _>>()?
    };
    let mut valid = vec![true; n];
    if let Some(link) = doc.get("Record3/DataLink/ValidPointsLink") {
        let bits = read_entry(&mut zip, link.trim(), name)?;
        check_md5(
            &doc,
            "Record3/DataLink/MD5ChecksumValidPoints",
            &bits,
            "valid-points mask",
            name,
        )?;
        if bits.len() < n.div_ceil(8) {
            return Err(fail(
                name,
                format!(
                    "valid-points mask '{link}' holds {} bytes; {} needed",
                    bits.len(),
                    n.div_ceil(8)
                ),
            ));
        }
        for (k, v) in valid.iter_mut().enumerate() {
            *v = bits[k / 8] >> (k % 8) & 1 == 1;
        }
    }
    let mut heights = vec![0.0; n];
    for j in 0..ny {
        for i in 0..nx {
            let k = i + nx * j;
            let mut z = raw[k];
            if z_inc != 1.0 {
                z *= z_inc;
            }
            if z_off != 0.0 {
                z += z_off;
            }
            heights[i * ny + j] = if valid[k] { z } else { f64::NAN };
        }
    }
    Topography::new(nx, ny, inc[0], inc[1], heights, name)
}

/// Days since 1970-01-01 to a civil date (H. Hinnant's algorithm).
fn civil(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn now_iso() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (y, mo, d) = civil(secs.div_euclid(86_400));
    let s = secs.rem_euclid(86_400);
    format!(
        "{y:04}-{mo:02}-{d:02}T{:02}:{:02}:{:02}.0+00:00",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

/// The bytes of an `.x3p` file holding `topo` with z data of type `dtype`;
/// `comment` goes into `Record2/Comment` (a filled map says so there).
/// Missing points are written as NaN (float types) and as 0 bits in a
/// valid-points mask (all types).
pub fn encode_x3p(
    topo: &Topography,
    dtype: X3pType,
    comment: Option<&str>,
) -> Result<Vec<u8>, SurfaceError> {
    let (nx, ny) = (topo.nx, topo.ny);
    let n = nx * ny;
    let at = |k: usize| topo.heights[(k % nx) * ny + k / nx];
    let (code, z_inc) = match dtype {
        X3pType::F64 => ("D", None),
        X3pType::F32 => ("F", None),
        X3pType::I32 => {
            let max = topo
                .heights
                .iter()
                .filter(|h| h.is_finite())
                .fold(0.0f64, |m, h| m.max(h.abs()));
            ("L", Some(if max > 0.0 { max / 2e9 } else { 1e-9 }))
        }
    };
    let mut data = Vec::with_capacity(n * 8);
    for k in 0..n {
        let h = at(k);
        match dtype {
            X3pType::F64 => data.extend_from_slice(&h.to_le_bytes()),
            X3pType::F32 => data.extend_from_slice(&(h as f32).to_le_bytes()),
            X3pType::I32 => {
                let v = if h.is_nan() {
                    0
                } else {
                    (h / z_inc.unwrap_or(1.0)).round() as i32
                };
                data.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    let missing = topo.heights.iter().any(|h| h.is_nan());
    let mask = missing.then(|| {
        let mut bits = vec![0u8; n.div_ceil(8)];
        for k in 0..n {
            if !at(k).is_nan() {
                bits[k / 8] |= 1 << (k % 8);
            }
        }
        bits
    });
    let esc = |s: &str| quick_xml::escape::escape(s).into_owned();
    let axis = |tag: &str, inc: f64| {
        format!(
            "      <{tag}>\n        <AxisType>I</AxisType>\n        <DataType>D</DataType>\n        <Increment>{inc:e}</Increment>\n        <Offset>0</Offset>\n      </{tag}>\n"
        )
    };
    let date = now_iso();
    let version = esc(crate::version::VERSION);
    let mut xml = String::new();
    xml.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\" ?>\n");
    xml.push_str("<p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\" xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" xsi:schemaLocation=\"http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2_XML.xsd\">\n");
    xml.push_str("  <Record1>\n    <Revision>ISO5436 - 2000</Revision>\n    <FeatureType>SUR</FeatureType>\n    <Axes>\n");
    xml.push_str(&axis("CX", topo.dx));
    xml.push_str(&axis("CY", topo.dy));
    xml.push_str(&format!(
        "      <CZ>\n        <AxisType>A</AxisType>\n        <DataType>{code}</DataType>\n{}        <Offset>0</Offset>\n      </CZ>\n",
        z_inc
            .map(|v| format!("        <Increment>{v:e}</Increment>\n"))
            .unwrap_or_default()
    ));
    xml.push_str("    </Axes>\n  </Record1>\n");
    xml.push_str(&format!(
        "  <Record2>\n    <Date>{date}</Date>\n    <Creator>viscoslide {version}</Creator>\n    <Instrument>\n      <Manufacturer>viscoslide</Manufacturer>\n      <Model>viscoslide</Model>\n      <Serial>not available</Serial>\n      <Version>{version}</Version>\n    </Instrument>\n    <CalibrationDate>{date}</CalibrationDate>\n    <ProbingSystem>\n      <Type>Software</Type>\n      <Identification>viscoslide</Identification>\n    </ProbingSystem>\n    <Comment>{}</Comment>\n  </Record2>\n",
        esc(comment.unwrap_or("written by viscoslide"))
    ));
    xml.push_str(&format!(
        "  <Record3>\n    <MatrixDimension>\n      <SizeX>{nx}</SizeX>\n      <SizeY>{ny}</SizeY>\n      <SizeZ>1</SizeZ>\n    </MatrixDimension>\n    <DataLink>\n      <PointDataLink>bindata/data.bin</PointDataLink>\n      <MD5ChecksumPointData>{}</MD5ChecksumPointData>\n",
        md5_hex(&data)
    ));
    if let Some(bits) = &mask {
        xml.push_str(&format!(
            "      <ValidPointsLink>bindata/valid.bin</ValidPointsLink>\n      <MD5ChecksumValidPoints>{}</MD5ChecksumValidPoints>\n",
            md5_hex(bits)
        ));
    }
    xml.push_str("    </DataLink>\n  </Record3>\n  <Record4>\n    <ChecksumFile>md5checksum.hex</ChecksumFile>\n  </Record4>\n</p:ISO5436_2>\n");

    let zerr =
        |e: zip::result::ZipError| SurfaceError::Invalid(format!("cannot build x3p archive: {e}"));
    let ioerr = |e: std::io::Error| SurfaceError::Invalid(format!("cannot build x3p archive: {e}"));
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default());
    let mut entries: Vec<(&str, Vec<u8>)> = vec![
        ("main.xml", xml.as_bytes().to_vec()),
        ("bindata/data.bin", data),
    ];
    if let Some(bits) = mask {
        entries.push(("bindata/valid.bin", bits));
    }
    entries.push((
        "md5checksum.hex",
        format!("{} *main.xml\n", md5_hex(xml.as_bytes())).into_bytes(),
    ));
    for (entry, bytes) in entries {
        zip.start_file(entry, opts).map_err(zerr)?;
        zip.write_all(&bytes).map_err(ioerr)?;
    }
    Ok(zip.finish().map_err(zerr)?.into_inner())
}
