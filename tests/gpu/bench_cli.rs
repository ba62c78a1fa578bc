//! `viscoslide gpu` (adapters with their limits and features) and
//! `viscoslide gpu bench` (the coefficient table and the matvec timed on the
//! device), as `scripts/gpu-run` calls them: JSON that parses, device
//! answers within the conformance bounds of the host's f64 ones, and the
//! bytes of the plan that runs.

use std::process::Command;

use viscoslide::internals::backend::gpu;

use super::plan_cli::viscoslide_bin;

fn viscoslide(args: &[&str]) -> std::process::Output {
    Command::new(viscoslide_bin())
        .args(args)
        .current_dir(crate::common::source_dir())
        .output()
        .expect("viscoslide runs")
}

fn json_of(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn adapters_are_listed_with_limits_and_features() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let v = json_of(&viscoslide(&["gpu", "--json"]));
    let listed = v.as_array().expect("a list of adapters");
    let a = listed
        .iter()
        .find(|a| a["name"] == ctx.adapter.name.as_str())
        .unwrap_or_else(|| panic!("{} not among {v}", ctx.adapter.name));
    let limits = &a["limits"];
    // WebGPU's guaranteed minima: every adapter reports at least these.
    assert!(
        limits["max_compute_workgroup_storage_size"]
            .as_u64()
            .unwrap()
            >= 16384
    );
    assert!(
        limits["max_compute_invocations_per_workgroup"]
            .as_u64()
            .unwrap()
            >= 256
    );
    assert!(
        limits["max_storage_buffers_per_shader_stage"]
            .as_u64()
            .unwrap()
            >= 8
    );
    assert_eq!(
        limits["max_storage_buffer_binding_size"].as_u64().unwrap(),
        a["max_storage_binding"].as_u64().unwrap()
    );
    assert!(a["features"].is_array(), "{a}");
}

#[test]
fn bench_agrees_with_the_host_and_counts_the_plans_bytes() {
    let Some(ctx) = crate::common::gpu_context() else {
        return;
    };
    let n = 48;
    let v = json_of(&viscoslide(&[
        "gpu",
        "bench",
        "configs/default.toml",
        "--n",
        &n.to_string(),
        "--rounds",
        "3",
        "--batch",
        "2",
        "--json",
    ]));
    assert_eq!(v["adapter"]["name"], ctx.adapter.name.as_str());
    assert_eq!(v["n"], n);
    // The f32 table against the host's f64 coefficients (conformance: about
    // 4e-7 of the self coefficient) and the f32 matvec against the host's
    // f64 one (conformance bound 1e-5 relative L2).
    let table = v["table_max_error_vs_host"].as_f64().unwrap();
    let matvec = v["matvec_relative_l2_vs_host"].as_f64().unwrap();
    assert!(table < 1e-5, "table {table:e}");
    assert!(matvec < 1e-5, "matvec {matvec:e}");
    for key in ["table_seconds", "matvec_seconds", "host_matvec_seconds"] {
        let t = v[key].as_f64().unwrap();
        assert!(t.is_finite() && t > 0.0, "{key} {t}");
    }
    assert_eq!(v["table_seconds_all"].as_array().unwrap().len(), 3);
    assert_eq!(v["matvec_seconds_all"].as_array().unwrap().len(), 3);
    // The bytes the bench reports are the plan's for this adapter's
    // workgroup storage (`viscoslide gpu plan`).
    let kib = gpu::adapter_details()
        .into_iter()
        .find(|a| a.summary.name == ctx.adapter.name)
        .expect("adapter listed")
        .limits
        .max_compute_workgroup_storage_size
        / 1024;
    let plan = json_of(&viscoslide(&[
        "gpu",
        "plan",
        "--n",
        &n.to_string(),
        "--shared-kib",
        &kib.to_string(),
        "--json",
    ]));
    assert_eq!(v["bytes"], plan["default"]["bytes"], "{v}\n{plan}");
    assert_eq!(v["floor_bytes"], plan["floor"]["bytes"]);
    assert_eq!(v["dispatches"], plan["default"]["dispatches"]);
    assert_eq!(v["padded"], plan["padded"]);
}

#[test]
fn bench_refuses_an_empty_grid_in_one_line() {
    let out = viscoslide(&["gpu", "bench", "configs/default.toml", "--n", "0"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("--n 0"), "{err}");
}
