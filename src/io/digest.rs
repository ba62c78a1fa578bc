//! MD5 digests in hex: of bytes (an x3p's checksum, a study's pin) and of
//! a file read in blocks (the files a study pins).

use std::io::Read;
use std::path::Path;

use md5::{Digest, Md5};

/// The digest of `hasher` as lower-case hex.
fn hex(hasher: Md5) -> String {
    hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The MD5 of `bytes`, in hex.
pub(crate) fn md5_hex(bytes: &[u8]) -> String {
    let mut hasher = Md5::new();
    hasher.update(bytes);
    hex(hasher)
}

/// The MD5 of the file at `path`, in hex, read in blocks of 1 MiB.
pub(crate) fn md5_file_hex(path: &Path) -> std::io::Result<String> {
    let mut file = std::fs::File::open(path)?;
    let mut hasher = Md5::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
    }
    Ok(hex(hasher))
}

#[cfg(test)]
mod tests {
    /// RFC 1321's test vector, and a file the same as its bytes.
    #[test]
    fn digests_are_rfc_1321s() {
        assert_eq!(super::md5_hex(b"abc"), "900150983cd24fb0d6963f7d28e17f72");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f");
        std::fs::write(&path, b"abc").unwrap();
        assert_eq!(super::md5_file_hex(&path).unwrap(), super::md5_hex(b"abc"));
    }
}
