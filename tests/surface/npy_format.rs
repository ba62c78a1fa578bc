//! The `.npy` reader and writer: byte orders, memory orders, dtypes, header
//! versions and the wording of its errors (what a user sees).

use viscoslide::io::npy::{self, NpyDtype};

/// A `.npy` file built by hand: `descr`, `fortran`, `shape` and raw data.
fn npy_file(version: u8, descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
    let dict = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
        if fortran { "True" } else { "False" }
    );
    let pre = if version == 1 { 10 } else { 12 };
    let mut header = dict.into_bytes();
    while (pre + header.len() + 1) % 64 != 0 {
        header.push(b' ');
    }
    header.push(b'\n');
    let mut out = b"\x93NUMPY".to_vec();
    out.extend_from_slice(&[version, 0]);
    if version == 1 {
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    }
    out.extend_from_slice(&header);
    out.extend_from_slice(data);
    out
}

#[test]
fn big_endian_float64_and_float32() {
    let v = [1.5f64, -2.25, 3.0e-7, 4.0, 5.5, 6.0];
    let be8: Vec<u8> = v.iter().flat_map(|x| x.to_be_bytes()).collect();
    let a = npy::decode(&npy_file(1, ">f8", false, "(2, 3)", &be8), "be8").unwrap();
    assert_eq!(a.shape, vec![2, 3]);
    assert_eq!(a.dtype, NpyDtype::F64);
    assert_eq!(a.data, v.to_vec());
    let be4: Vec<u8> = v.iter().flat_map(|x| (*x as f32).to_be_bytes()).collect();
    let a = npy::decode(&npy_file(1, ">f4", false, "(3, 2)", &be4), "be4").unwrap();
    assert_eq!(a.dtype, NpyDtype::F32);
    assert_eq!(
        a.data,
        v.iter().map(|x| *x as f32 as f64).collect::<Vec<_>>()
    );
}

#[test]
fn fortran_order_float32_and_version_2_header() {
    // numpy.asfortranarray([[1, 2, 3], [4, 5, 6]], dtype='<f4').
    let d: Vec<u8> = [1.0f32, 4.0, 2.0, 5.0, 3.0, 6.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let a = npy::decode(&npy_file(2, "<f4", true, "(2, 3)", &d), "f").unwrap();
    assert_eq!(a.shape, vec![2, 3]);
    assert_eq!(a.data, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    // Round trip of the writer, bit for bit.
    let v: Vec<f64> = (0..12).map(|i| (i as f64 * 0.37).exp() * 1e-9).collect();
    let back = npy::decode(&npy::encode_f64(&[4, 3], &v), "w").unwrap();
    assert_eq!(back.data, v);
}

#[test]
fn errors_name_the_file_and_what_to_fix() {
    let ok = vec![0u8; 32];
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (
            b"hello world".to_vec(),
            "m.npy: not a .npy file (bad magic string)",
        ),
        (
            npy_file(1, "<i8", false, "(2, 2)", &ok),
            "m.npy: unsupported dtype '<i8' (use float64 '<f8' or float32 '<f4')",
        ),
        (
            npy_file(1, "<f8", false, "(2, 2)", &ok[..20]),
            "m.npy: truncated .npy file",
        ),
        (b"\x93NUM".to_vec(), "m.npy: truncated .npy file"),
    ];
    for (bytes, want) in cases {
        let e = npy::decode(&bytes, "m.npy").unwrap_err().to_string();
        assert!(e.starts_with(want), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
}
