//! `viscoslide gpu plan`: the traffic model of the GPU matvec, printed
//! without a device (issue #20's targets at 4096^2 on an adapter with 48 KiB
//! of workgroup memory, an H100 under Vulkan).

use std::process::Command;

fn plan(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_viscoslide"))
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
