//! `viscoslide gpu plan`: the traffic model of the GPU matvec, printed
//! without a device (issue #20's targets at 4096^2 on an adapter with 48 KiB
//! of workgroup memory, an H100 under Vulkan).

use std::process::Command;

/// The `viscoslide` executable: the one named by `VISCOSLIDE_BIN` when set
/// (a test executable run from a copy of the repository, as
/// `scripts/gpu-run` does), else the one built with the tests.
pub(crate) fn viscoslide_bin() -> std::path::PathBuf {
    match std::env::var_os("VISCOSLIDE_BIN") {
        Some(bin) if !bin.is_empty() => std::path::PathBuf::from(bin),
        _ => std::path::PathBuf::from(env!("CARGO_BIN_EXE_viscoslide")),
    }
}

fn plan(args: &[&str]) -> String {
    let out = Command::new(viscoslide_bin())
        .args(["gpu", "plan"])
        .args(args)
        .output()
        .expect("viscoslide runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

#[test]
fn plan_json_meets_the_traffic_targets_at_4096() {
    let v: serde_json::Value = serde_json::from_str(&plan(&["--n", "4096", "--json"])).unwrap();
    let bytes = |k: &str| v[k]["bytes"].as_u64().unwrap();
    let (new, old, floor) = (bytes("default"), bytes("radix2"), bytes("floor"));
    println!("4096^2: default {new} B, radix-2 {old} B, floor {floor} B");
    assert_eq!(v["padded"], serde_json::json!([8192, 8192]));
    assert!(4 * new <= old && new <= 3 * floor);
    assert_eq!(v["default"]["dispatches"], 5);
    // 2 GB at 3 TB/s.
    let ms = v["default"]["predicted_ms"].as_f64().unwrap();
    assert!((ms - new as f64 / 3e9).abs() < 1e-9, "{ms}");
}

#[test]
fn plan_table_lists_both_paths_the_floor_and_the_steps() {
    let text = plan(&["--n", "512", "--shared-kib", "32", "--steps"]);
    for want in ["radix-2 passes", "default", "floor", "fft_radix_product"] {
        assert!(text.contains(want), "{want} missing from:\n{text}");
    }
    // A 512^2 grid is one block per transform: rows, columns, rows.
    assert_eq!(text.matches("  fft_radix").count(), 3, "{text}");
}

/// The plan states how the arrays sit in the adapter's bindings (default
/// lavapipe's 128 MiB binding, 2 GiB buffer): at 2048^2 one binding each;
/// at 4096^2 the `8192 x 4097` complex work buffers and spectrum (268 MB)
/// in three windows; at 8192^2 (1.07 GB) in nine and the grid vectors (268
/// MB) in two; at 8193^2 the work buffers (4.3 GB) exceed one buffer. The
/// radix-2 fallback (2 KiB of workgroup memory) splits as well: at 4096^2
/// its `8192 x 8192` complex work buffers (537 MB) in four windows.
#[test]
fn plan_states_how_arrays_are_split() {
    let arrays = |n: &str| {
        let v: serde_json::Value =
            serde_json::from_str(&plan(&["--n", n, "--shared-kib", "32", "--json"])).unwrap();
        v["arrays"].clone()
    };
    let a = arrays("2048");
    assert_eq!(a["fft_buffer_windows"], 1, "{a}");
    assert_eq!(a["vector_windows"], 1, "{a}");
    let a = arrays("4096");
    assert_eq!(a["fft_buffer_bytes"], 8 * 8192 * 4097, "{a}");
    assert_eq!(a["fft_buffer_windows"], 3, "{a}");
    assert_eq!(a["window_bytes"], 128 << 20, "{a}");
    assert!(a["text"].as_str().unwrap().contains("3 windows"), "{a}");
    let a = arrays("8192");
    assert_eq!(a["fft_buffer_windows"], 9, "{a}");
    assert_eq!(a["vector_windows"], 2, "{a}");
    let a = arrays("8193");
    assert!(a["fft_buffer_windows"].is_null(), "{a}");
    assert!(a["text"].as_str().unwrap().contains("per buffer"), "{a}");
    let v: serde_json::Value =
        serde_json::from_str(&plan(&["--n", "4096", "--shared-kib", "2", "--json"])).unwrap();
    assert_eq!(v["path"], "Radix2", "{v}");
    let a = &v["arrays"];
    assert_eq!(a["fft_buffer_bytes"], 8 * 8192 * 8192, "{a}");
    assert_eq!(a["fft_buffer_windows"], 4, "{a}");
    assert!(a["text"].as_str().unwrap().contains("4 windows"), "{a}");
    let text = plan(&["--n", "4096", "--binding-mib", "1024"]);
    assert!(text.contains("in one binding; grid vectors"), "{text}");
}
