//! NumPy `.npy` files (format versions 1.0-3.0): little- and big-endian
//! `f4`/`f8`, C or Fortran order. Arrays are returned in C order; for height
//! maps and result maps axis 0 is x, the sliding direction.
//!
//! Kept hand-written rather than built on the `npyz` crate, measured
//! against it (npyz 0.9.1): it would add 13 crates to the build (a Python
//! literal parser on `pest` and its derive macro, and `psm`, which compiles
//! assembly through a C toolchain), about 20 s of CPU to a clean build, and
//! the wrapper would still have to convert float32 and Fortran order (npyz
//! returns raw memory order and refuses `<f4` as f64) and to name the file
//! in errors (a truncated file gives npyz's bare "failed to fill whole
//! buffer"). `tests/surface/npy_format.rs` pins the behaviour.

use std::path::Path;

/// Errors reading or writing `.npy` data; each names what to fix.
#[derive(Debug, thiserror::Error)]
pub enum NpyError {
    #[error("{path}: not a .npy file (bad magic string)")]
    BadMagic { path: String },
    #[error("{path}: truncated .npy file: {what}")]
    Truncated { path: String, what: String },
    #[error("{path}: malformed .npy header: {what}")]
    BadHeader { path: String, what: String },
    #[error("{path}: unsupported dtype '{dtype}' (use float64 '<f8' or float32 '<f4')")]
    UnsupportedDtype { path: String, dtype: String },
    #[error("{path}: expected a {expected}-D array, found shape {found:?}")]
    WrongRank {
        path: String,
        expected: usize,
        found: Vec<usize>,
    },
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// Element type stored in a `.npy` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NpyDtype {
    F32,
    F64,
}

/// A decoded array, in C (row-major) order.
#[derive(Debug, Clone, PartialEq)]
pub struct NpyArray {
    pub shape: Vec<usize>,
    pub dtype: NpyDtype,
    pub data: Vec<f64>,
}

const MAGIC: &[u8] = b"\x93NUMPY";

/// Encode `data` (C order, `shape`) as a version-1.0 `.npy` file of float64.
pub fn encode_f64(shape: &[usize], data: &[f64]) -> Vec<u8> {
    assert_eq!(
        shape.iter().product::<usize>(),
        data.len(),
        "shape mismatch"
    );
    let mut out = header("<f8", shape);
    out.reserve(data.len() * 8);
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Encode `data` (C order, `shape`) as a version-1.0 `.npy` file of float32.
pub(crate) fn encode_f32(shape: &[usize], data: &[f32]) -> Vec<u8> {
    assert_eq!(
        shape.iter().product::<usize>(),
        data.len(),
        "shape mismatch"
    );
    let mut out = header("<f4", shape);
    out.reserve(data.len() * 4);
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

fn header(descr: &str, shape: &[usize]) -> Vec<u8> {
    let shape_txt = match shape.len() {
        1 => format!("({},)", shape[0]),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut dict =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape_txt}, }}");
    // Pad so that magic(6) + version(2) + len(2) + dict + '\n' is a multiple of 64.
    let unpadded = MAGIC.len() + 2 + 2 + dict.len() + 1;
    let pad = (64 - unpadded % 64) % 64;
    dict.extend(std::iter::repeat_n(' ', pad));
    dict.push('\n');
    let mut out = Vec::with_capacity(10 + dict.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out
}

/// A `.npy` header: the dtype's text, the order, the shape and where the
/// data start.
struct Header {
    descr: String,
    fortran: bool,
    shape: Vec<usize>,
    data_start: usize,
}

/// Where the header text of the `.npy` bytes starting `bytes` lies:
/// `(start, length)`, from the magic string, the version and the length
/// field (the first 10 or 12 bytes).
fn header_span(bytes: &[u8], name: &str) -> Result<(usize, usize), NpyError> {
    let path = name.to_string();
    if bytes.len() < 8 || &bytes[..6] != MAGIC {
        if bytes.len() < 6 && MAGIC.starts_with(bytes) {
            return Err(NpyError::Truncated {
                path,
                what: "file ends inside the magic string".into(),
            });
        }
        return Err(NpyError::BadMagic { path });
    }
    let major = bytes[6];
    let (hlen, hstart) = match major {
        1 => {
            if bytes.len() < 10 {
                return Err(NpyError::Truncated {
                    path,
                    what: "file ends inside the header length".into(),
                });
            }
            (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10)
        }
        2 | 3 => {
            if bytes.len() < 12 {
                return Err(NpyError::Truncated {
                    path,
                    what: "file ends inside the header length".into(),
                });
            }
            (
                u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
                12,
            )
        }
        v => {
            return Err(NpyError::BadHeader {
                path,
                what: format!("unknown format version {v}"),
            })
        }
    };
    Ok((hstart, hlen))
}

/// The header at the start of `bytes` (which need not hold the data).
fn parse_header(bytes: &[u8], name: &str) -> Result<Header, NpyError> {
    let path = name.to_string();
    let (hstart, hlen) = header_span(bytes, name)?;
    if bytes.len() < hstart + hlen {
        return Err(NpyError::Truncated {
            path,
            what: format!("header announces {hlen} bytes, file has fewer"),
        });
    }
    let dict =
        std::str::from_utf8(&bytes[hstart..hstart + hlen]).map_err(|_| NpyError::BadHeader {
            path: path.clone(),
            what: "header is not text".into(),
        })?;
    let descr = dict_value(dict, "descr").ok_or_else(|| NpyError::BadHeader {
        path: path.clone(),
        what: "no 'descr' key".into(),
    })?;
    let descr = descr
        .trim()
        .trim_matches(|c| c == '\'' || c == '"')
        .to_string();
    let fortran = dict_value(dict, "fortran_order")
        .map(|v| v.trim().starts_with("True"))
        .ok_or_else(|| NpyError::BadHeader {
            path: path.clone(),
            what: "no 'fortran_order' key".into(),
        })?;
    let shape_txt = dict_value(dict, "shape").ok_or_else(|| NpyError::BadHeader {
        path: path.clone(),
        what: "no 'shape' key".into(),
    })?;
    let shape = parse_shape(&shape_txt).ok_or_else(|| NpyError::BadHeader {
        path: path.clone(),
        what: format!("cannot read shape {shape_txt}"),
    })?;
    Ok(Header {
        descr,
        fortran,
        shape,
        data_start: hstart + hlen,
    })
}

/// The shape a `.npy` file's header announces, read without its data, so
/// that a grid can be refused before the file is read.
pub fn read_shape(path: impl AsRef<Path>) -> Result<Vec<usize>, NpyError> {
    use std::io::Read;
    let path = path.as_ref();
    let name = path.display().to_string();
    let io = |source| NpyError::Io {
        path: name.clone(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(io)?;
    let mut prefix = Vec::new();
    (&mut file).take(12).read_to_end(&mut prefix).map_err(io)?;
    let (hstart, hlen) = header_span(&prefix, &name)?;
    let more = (hstart + hlen).saturating_sub(prefix.len()) as u64;
    (&mut file)
        .take(more)
        .read_to_end(&mut prefix)
        .map_err(io)?;
    parse_header(&prefix, &name).map(|h| h.shape)
}

/// Decode a `.npy` byte buffer; `name` is used in error messages.
pub fn decode(bytes: &[u8], name: &str) -> Result<NpyArray, NpyError> {
    let path = name.to_string();
    let Header {
        descr,
        fortran,
        shape,
        data_start,
    } = parse_header(bytes, name)?;
    let (dtype, little, width) = match descr.as_str() {
        "<f8" | "=f8" | "f8" | "<d" => (NpyDtype::F64, true, 8),
        ">f8" | ">d" => (NpyDtype::F64, false, 8),
        "<f4" | "=f4" | "f4" | "<f" => (NpyDtype::F32, true, 4),
        ">f4" | ">f" => (NpyDtype::F32, false, 4),
        _ => return Err(NpyError::UnsupportedDtype { path, dtype: descr }),
    };
    // The shape is checked against the bytes present, with checked
    // arithmetic, before anything is allocated for it.
    let body = &bytes[data_start..];
    let need = shape
        .iter()
        .try_fold(width, |acc: usize, &d| acc.checked_mul(d));
    let Some(need) = need.filter(|&n| n <= body.len()) else {
        let need = need.map_or("more than 2^64".to_string(), |n| n.to_string());
        return Err(NpyError::Truncated {
            path,
            what: format!(
                "shape {shape:?} needs {need} data bytes, file has {}",
                body.len()
            ),
        });
    };
    if body.len() > need {
        // More data than the shape holds: the shape edited, or another
        // array appended; reading the first `need` bytes would take a
        // part of the file for the whole without a word.
        return Err(NpyError::BadHeader {
            path,
            what: format!(
                "shape {shape:?} holds {need} data bytes, the file has {} after its header (another array appended, or the shape not the data's)",
                body.len()
            ),
        });
    }
    let mut data: Vec<f64> = body[..need]
        .chunks_exact(width)
        .map(|c| match (width, little) {
            (8, true) => f64::from_le_bytes(c.try_into().unwrap()),
            (8, false) => f64::from_be_bytes(c.try_into().unwrap()),
            (4, true) => f32::from_le_bytes(c.try_into().unwrap()) as f64,
            _ => f32::from_be_bytes(c.try_into().unwrap()) as f64,
        })
        .collect();
    if fortran && shape.len() > 1 {
        data = fortran_to_c(&data, &shape);
    }
    Ok(NpyArray { shape, dtype, data })
}

/// Read a `.npy` file.
pub fn read(path: impl AsRef<Path>) -> Result<NpyArray, NpyError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| NpyError::Io {
        path: path.display().to_string(),
        source,
    })?;
    decode(&bytes, &path.display().to_string())
}

/// Read a 2-D `.npy` file: `(rows, cols, data in C order)`.
pub fn read_2d(path: impl AsRef<Path>) -> Result<(usize, usize, Vec<f64>), NpyError> {
    let path = path.as_ref();
    let a = read(path)?;
    if a.shape.len() != 2 {
        return Err(NpyError::WrongRank {
            path: path.display().to_string(),
            expected: 2,
            found: a.shape,
        });
    }
    Ok((a.shape[0], a.shape[1], a.data))
}

fn fortran_to_c(data: &[f64], shape: &[usize]) -> Vec<f64> {
    // Column-major strides -> row-major.
    let n = data.len();
    let rank = shape.len();
    let mut out = vec![0.0; n];
    let mut idx = vec![0usize; rank];
    for (c_pos, slot) in out.iter_mut().enumerate() {
        let mut rem = c_pos;
        for d in (0..rank).rev() {
            idx[d] = rem % shape[d];
            rem /= shape[d];
        }
        let mut f_pos = 0;
        let mut stride = 1;
        for d in 0..rank {
            f_pos += idx[d] * stride;
            stride *= shape[d];
        }
        *slot = data[f_pos];
    }
    out
}

fn dict_value(dict: &str, key: &str) -> Option<String> {
    let pat1 = format!("'{key}'");
    let pat2 = format!("\"{key}\"");
    let start = dict
        .find(&pat1)
        .map(|i| i + pat1.len())
        .or_else(|| dict.find(&pat2).map(|i| i + pat2.len()))?;
    let rest = dict[start..].trim_start();
    let rest = rest.strip_prefix(':')?.trim_start();
    if rest.starts_with('(') {
        let end = rest.find(')')?;
        Some(rest[..=end].to_string())
    } else {
        let end = rest.find(',').unwrap_or(rest.len());
        Some(rest[..end].to_string())
    }
}

fn parse_shape(txt: &str) -> Option<Vec<usize>> {
    let inner = txt.trim().strip_prefix('(')?.strip_suffix(')')?;
    inner
        .split(',')
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .map(|s| s.trim_end_matches('L').parse().ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch_header(bytes: &mut [u8], from: &[u8], to: &[u8]) {
        assert_eq!(from.len(), to.len());
        let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let header = &mut bytes[10..10 + hlen];
        let at = header.windows(from.len()).position(|w| w == from).unwrap();
        header[at..at + to.len()].copy_from_slice(to);
    }

    #[test]
    fn round_trip_f64_bit_exact() {
        let data: Vec<f64> = (0..12)
            .map(|i| (i as f64).sin() * 1e-7 + f64::EPSILON * i as f64)
            .collect();
        let bytes = encode_f64(&[3, 4], &data);
        assert_eq!(bytes.len() % 64, 12 * 8 % 64);
        let a = decode(&bytes, "t").unwrap();
        assert_eq!(a.shape, vec![3, 4]);
        assert_eq!(a.dtype, NpyDtype::F64);
        for (x, y) in a.data.iter().zip(&data) {
            assert_eq!(x.to_bits(), y.to_bits());
        }
    }

    #[test]
    fn round_trip_f32() {
        let data: Vec<f32> = (0..6).map(|i| i as f32 * 0.25).collect();
        let a = decode(&encode_f32(&[2, 3], &data), "t").unwrap();
        assert_eq!(a.dtype, NpyDtype::F32);
        assert_eq!(a.data, data.iter().map(|&v| v as f64).collect::<Vec<_>>());
    }

    #[test]
    fn fortran_order_is_transposed_to_c() {
        // numpy.asfortranarray([[1,2,3],[4,5,6]]) stores 1,4,2,5,3,6.
        let mut bytes = encode_f64(&[2, 3], &[1.0, 4.0, 2.0, 5.0, 3.0, 6.0]);
        patch_header(&mut bytes, b"False", b"True ");
        let a = decode(&bytes, "t").unwrap();
        assert_eq!(a.data, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }

    #[test]
    fn bad_inputs_have_their_own_errors() {
        let good = encode_f64(&[2, 2], &[1.0, 2.0, 3.0, 4.0]);
        assert!(matches!(
            decode(b"hello world", "t"),
            Err(NpyError::BadMagic { .. })
        ));
        assert!(matches!(
            decode(&good[..good.len() - 3], "t"),
            Err(NpyError::Truncated { .. })
        ));
        assert!(matches!(
            decode(&good[..9], "t"),
            Err(NpyError::Truncated { .. })
        ));
        // A shape smaller than the data (edited, or an array appended).
        let mut small = good.clone();
        patch_header(&mut small, b"(2, 2)", b"(2, 1)");
        let e = decode(&small, "t").unwrap_err();
        assert!(
            matches!(e, NpyError::BadHeader { .. })
                && e.to_string().contains("another array appended"),
            "{e}"
        );
        let mut two = good.clone();
        two.extend_from_slice(&good);
        assert!(matches!(decode(&two, "t"), Err(NpyError::BadHeader { .. })));
        let mut int = good.clone();
        patch_header(&mut int, b"<f8", b"<i8");
        assert!(matches!(
            decode(&int, "t"),
            Err(NpyError::UnsupportedDtype { .. })
        ));
    }
}
