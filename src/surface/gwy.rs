//! Gwyddion native files (`.gwy`), read: the first data field.
//!
//! Format (Gwyddion's "GWYP" serialisation, little endian): the magic
//! `GWYP`, then one object `name\0 u32-size components`; a component is
//! `key\0 type value` with type `b` bool (1 byte), `c` char (1 byte), `i`
//! int32, `q` int64, `d` double, `s` NUL-terminated string, `o` object, and
//! the upper-case letters for arrays (`u32` count, then the items). The
//! container's keys `/N/data` hold `GwyDataField` objects (`xres`, `yres`,
//! `xreal`, `yreal`, `data` with row `r` = y index, column = x index,
//! `si_unit_xy` and `si_unit_z` as `GwySIUnit { unitstr }`). The field with
//! the smallest `N` is read; `xreal`, `yreal` and the heights are converted
//! to metres from their units (`m` with an SI prefix, e.g. `um`, `nm`).

use std::path::Path;

use super::length_unit::metres_per;
use super::{SurfaceError, Topography};

fn fail(name: &str, why: impl std::fmt::Display) -> SurfaceError {
    SurfaceError::File {
        path: name.to_string(),
        why: why.to_string(),
    }
}

#[derive(Debug)]
enum Value {
    Int(i64),
    Double(f64),
    Str(String),
    Object(Object),
    Doubles(Vec<f64>),
    Other,
}

#[derive(Debug)]
struct Object {
    name: String,
    items: Vec<(String, Value)>,
}

impl Object {
    fn get(&self, key: &str) -> Option<&Value> {
        self.items.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }
}

struct Cur<'a> {
    b: &'a [u8],
    pos: usize,
}

impl<'a> Cur<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.b.len())
            .ok_or_else(|| format!("truncated at byte {}", self.pos))?;
        let s = &self.b[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn cstr(&mut self) -> Result<String, String> {
        let rest = &self.b[self.pos..];
        let len = rest
            .iter()
            .position(|&c| c == 0)
            .ok_or_else(|| format!("unterminated string at byte {}", self.pos))?;
        let s = String::from_utf8_lossy(&rest[..len]).into_owned();
        self.pos += len + 1;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }
    fn object(&mut self, depth: usize) -> Result<Object, String> {
        if depth > 64 {
            return Err("objects nested too deep".into());
        }
        let name = self.cstr()?;
        let size = self.u32()? as usize;
        let end = self
            .pos
            .checked_add(size)
            .filter(|&e| e <= self.b.len())
            .ok_or_else(|| format!("object {name} runs past the end of the file"))?;
        let mut items = Vec::new();
        while self.pos < end {
            let key = self.cstr()?;
            let t = self.take(1)?[0];
            let v = self.value(t, depth)?;
            items.push((key, v));
        }
        if self.pos != end {
            return Err(format!("object {name} overruns its size"));
        }
        Ok(Object { name, items })
    }
    fn value(&mut self, t: u8, depth: usize) -> Result<Value, String> {
        Ok(match t {
            b'b' | b'c' => Value::Int(self.take(1)?[0] as i64),
            b'i' => Value::Int(i32::from_le_bytes(self.take(4)?.try_into().expect("4")) as i64),
            b'q' => Value::Int(i64::from_le_bytes(self.take(8)?.try_into().expect("8"))),
            b'd' => Value::Double(f64::from_le_bytes(self.take(8)?.try_into().expect("8"))),
            b's' => Value::Str(self.cstr()?),
            b'o' => Value::Object(self.object(depth + 1)?),
            b'C' | b'B' => {
                let n = self.u32()? as usize;
                self.take(n)?;
                Value::Other
            }
            b'I' => {
                let n = self.u32()? as usize;
                self.take(n.checked_mul(4).ok_or("array too large")?)?;
                Value::Other
            }
            b'Q' => {
                let n = self.u32()? as usize;
                self.take(n.checked_mul(8).ok_or("array too large")?)?;
                Value::Other
            }
            b'D' => {
                let n = self.u32()? as usize;
                let raw = self.take(n.checked_mul(8).ok_or("array too large")?)?;
                Value::Doubles(
                    raw.chunks_exact(8)
                        .map(|c| f64::from_le_bytes(c.try_into().expect("8")))
                        .collect(),
                )
            }
            b'S' => {
                let n = self.u32()? as usize;
                for _ in 0..n {
                    self.cstr()?;
                }
                Value::Other
            }
            b'O' => {
                let n = self.u32()? as usize;
                for _ in 0..n {
                    self.object(depth + 1)?;
                }
                Value::Other
            }
            other => return Err(format!("unknown component type '{}'", other as char)),
        })
    }
}

/// Read the first data field of a `.gwy` file.
pub fn read_gwy(path: &Path) -> Result<Topography, SurfaceError> {
    let bytes = std::fs::read(path).map_err(|source| SurfaceError::Io {
        path: path.display().to_string(),
        source,
    })?;
    decode_gwy(&bytes, &path.display().to_string())
}

/// Decode the bytes of a `.gwy` file; `name` labels errors.
pub fn decode_gwy(bytes: &[u8], name: &str) -> Result<Topography, SurfaceError> {
    if bytes.len() < 4 || &bytes[..4] != b"GWYP" {
        return Err(fail(
            name,
            "not a Gwyddion file (no 'GWYP' magic; the old GWYO format is not supported)",
        ));
    }
    let mut cur = Cur { b: bytes, pos: 4 };
    let top = cur
        .object(0)
        .map_err(|e| fail(name, format!("cannot parse: {e}")))?;
    let mut best: Option<(u64, &Object)> = None;
    for (k, v) in &top.items {
        let id = k
            .strip_prefix('/')
            .and_then(|r| r.strip_suffix("/data"))
            .and_then(|n| n.parse::<u64>().ok());
        if let (Some(id), Value::Object(o)) = (id, v) {
            if o.name == "GwyDataField" && best.is_none_or(|(b, _)| id < b) {
                best = Some((id, o));
            }
        }
    }
    let (_, field) = best.ok_or_else(|| fail(name, "holds no data field (/N/data)"))?;
    let int = |k: &str| match field.get(k) {
        Some(Value::Int(v)) => Ok(*v),
        _ => Err(fail(name, format!("data field has no integer '{k}'"))),
    };
    let dbl = |k: &str| match field.get(k) {
        Some(Value::Double(v)) => Ok(*v),
        _ => Err(fail(name, format!("data field has no '{k}'"))),
    };
    let unit = |k: &str| -> Result<f64, SurfaceError> {
        let s = match field.get(k) {
            Some(Value::Object(o)) => match o.get("unitstr") {
                Some(Value::Str(s)) => s.clone(),
                _ => String::new(),
            },
            _ => "m".to_string(),
        };
        metres_per(s.trim()).ok_or_else(|| {
            fail(
                name,
                format!("{k} = '{s}' is not a length unit (m with an SI prefix)"),
            )
        })
    };
    let (xres, yres) = (int("xres")?, int("yres")?);
    if xres < 2 || yres < 2 {
        return Err(fail(
            name,
            format!("data field {xres} x {yres} must be at least 2 x 2"),
        ));
    }
    let (xres, yres) = (xres as usize, yres as usize);
    let (sxy, sz) = (unit("si_unit_xy")?, unit("si_unit_z")?);
    let (xreal, yreal) = (dbl("xreal")? * sxy, dbl("yreal")? * sxy);
    let data = match field.get("data") {
        Some(Value::Doubles(d)) => d,
        _ => return Err(fail(name, "data field has no 'data' array")),
    };
    // Checked: sizes whose product wraps must not match a short array.
    if xres.checked_mul(yres) != Some(data.len()) {
        return Err(fail(
            name,
            format!(
                "data field holds {} values, {xres} x {yres} needed",
                data.len()
            ),
        ));
    }
    // Gwyddion rows run along y: value (col = x, row = y) at row * xres + col.
    let (nx, ny) = (xres, yres);
    let mut heights = vec![0.0; nx * ny];
    for r in 0..ny {
        for c in 0..nx {
            heights[c * ny + r] = data[r * nx + c] * sz;
        }
    }
    Topography::new(nx, ny, xreal / nx as f64, yreal / ny as f64, heights, name)
}
