//! Pieces of a Gwyddion `.gwy` file, for tests that build files by hand.

/// A component key: its name, a NUL and its one-byte type (`i`, `q`, `d`, `o`, `D`, ...).
pub fn key(k: &str, t: u8) -> Vec<u8> {
    let mut v = k.as_bytes().to_vec();
    v.push(0);
    v.push(t);
    v
}

/// An object: its type name, a NUL, the body's length (u32, little-endian) and the body.
pub fn obj(name: &str, body: &[u8]) -> Vec<u8> {
    let mut v = name.as_bytes().to_vec();
    v.push(0);
    v.extend_from_slice(&(body.len() as u32).to_le_bytes());
    v.extend_from_slice(body);
    v
}
