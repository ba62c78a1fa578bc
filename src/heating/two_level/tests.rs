//! Tests of the two-grid search: constructed S-curves whose coarse grid
//! differs from the full one, against the full-grid scan.

use super::*;
use crate::heating::branches::tests::search;

/// The S-curve of `branches.rs`'s test: roots near 22, 60 and 102 for
/// `T0 = 20`.
fn s_curve(t: f64) -> f64 {
    2.0 + 80.0 / (1.0 + (-(t - 60.0) / 4.0).exp())
}

/// `find_two_level` with `fine` and `coarse` as the two grids' `Theta`.
fn two(s: &BranchSearch, fine: impl Fn(f64) -> f64, coarse: impl Fn(f64) -> f64) -> TwoLevel {
    let mut theta = |level: Level, t: f64| {
        Ok::<_, String>(match level {
            Level::Full => fine(t),
            Level::Coarse => coarse(t),
        })
    };
    s.find_two_level(&mut theta).unwrap()
}

fn assert_same_roots(a: &[Branch], b: &[Branch], tol: f64) {
    assert_eq!(a.len(), b.len(), "{a:?} {b:?}");
    for (x, y) in a.iter().zip(b) {
        // Both within `tol` of zero on a g whose slope is at most
        // about -1 + 20 (the fold): the roots agree to 40 tol.
        assert!(
            (x.temperature - y.temperature).abs() <= 40.0 * tol,
            "{x:?} {y:?}"
        );
        assert_eq!(x.stable, y.stable);
    }
}

#[test]
fn a_coarse_grid_close_to_the_full_one_finds_the_full_scans_roots() {
    // The coarse grid's Theta: 0.7 times the full one's, plus a slow
    // drift of 1 %: after the calibration at T0 the grids differ by
    // about 1 %, far below the fold's depth.
    let s = search(20.0);
    let fine = |t: f64| s_curve(t);
    let coarse = |t: f64| 0.7 * s_curve(t) * (1.0 + 0.01 * ((t - 20.0) / 50.0).sin());
    let r = two(&s, fine, coarse);
    assert!(r.fallback.is_none(), "{:?}", r.fallback);
    let full = s.find(|t| Ok::<_, ()>(fine(t))).unwrap();
    assert_same_roots(&r.found.branches, &full.branches, s.tolerance);
    for b in &r.found.branches {
        assert!((20.0 + fine(b.temperature) - b.temperature).abs() <= s.tolerance);
    }
    assert!((r.scale - 1.0 / 0.7).abs() < 1e-12, "{}", r.scale);
    assert!(
        r.discrepancy > 0.0 && r.discrepancy < 0.03,
        "{}",
        r.discrepancy
    );
    // Every full-grid evaluation is listed once, and fewer of them
    // than the full-grid scan makes.
    let n = r.found.evaluations.len();
    assert!(
        n < full.evaluations.len(),
        "{n} vs {}",
        full.evaluations.len()
    );
}

#[test]
fn one_root_closes_in_few_full_grid_solves() {
    // A slowly falling rise (the paper experiment's shape): T0, the
    // coarse root and at most one step more on the full grid.
    let s = BranchSearch {
        tolerance: 1e-3,
        ..search(17.0)
    };
    let fine = |t: f64| 0.0288 * (-(t - 17.0) / 60.0).exp();
    let coarse = |t: f64| 0.0224 * (-(t - 17.0) / 55.0).exp();
    let r = two(&s, fine, coarse);
    assert!(r.fallback.is_none(), "{:?}", r.fallback);
    assert_eq!(r.found.branches.len(), 1);
    let b = r.found.branches[0];
    assert!((17.0 + fine(b.temperature) - b.temperature).abs() <= 1e-3);
    assert!(b.stable);
    assert!(r.found.evaluations.len() <= 3, "{:?}", r.found.evaluations);
}

#[test]
fn a_coarse_grid_that_changes_the_roots_falls_back_to_the_full_scan() {
    // The coarse grid's fold is half as high: its g stays negative
    // above its cold root, where the full grid's has its unstable and
    // hot roots; and its rise grows 0.1 K per K, 10 % off the full
    // grid's at the cold root. The deciding scan temperature 74 C
    // (coarse g = -7.5 K, within 3 x 10 % of its 47 K rise) is solved
    // on the full grid, its g is +26 K, and the full scan answers.
    let s = search(20.0);
    let fine = |t: f64| s_curve(t);
    let coarse = |t: f64| 2.0 + 0.1 * (t - 20.0) + 40.0 / (1.0 + (-(t - 60.0) / 4.0).exp());
    let r = two(&s, fine, coarse);
    assert!(r.fallback.is_some(), "{r:?}");
    let full = s.find(|t| Ok::<_, ()>(fine(t))).unwrap();
    assert_same_roots(&r.found.branches, &full.branches, s.tolerance);
    assert_eq!(r.found.branches.len(), 3);
    assert!(
        r.found.method.contains("on the full grid:"),
        "{}",
        r.found.method
    );
    // The full-grid solves made before the fallback are not repeated.
    let mut temps: Vec<f64> = r.found.evaluations.iter().map(|e| e.temperature).collect();
    let n = temps.len();
    temps.sort_by(f64::total_cmp);
    temps.dedup();
    assert_eq!(temps.len(), n);
}

#[test]
fn no_heating_needs_no_full_grid_scan() {
    let s = BranchSearch {
        tolerance: 1e-3,
        ..search(25.0)
    };
    let r = two(&s, |_| 1e-8, |_| 2e-8);
    assert!(r.fallback.is_none(), "{:?}", r.fallback);
    assert_eq!(r.found.branches.len(), 1, "{r:?}");
    assert!(r.found.branches[0].residual.abs() <= 1e-3);
    assert!(r.found.evaluations.len() <= 2, "{:?}", r.found.evaluations);
}
