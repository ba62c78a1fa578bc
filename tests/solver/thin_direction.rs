//! The friction inside the thin-layer band (`h < a`, `kernel/thin_band.rs`)
//! swept over the sliding direction: the law's grid continuation on the
//! grid axes and off them (`kernel/thin_oblique.rs`; physics.md sections
//! 3 and 5).

use super::thin_step::bonded_pad_with;
use viscoslide::internals::solver;
use viscoslide::problem::Executor;

/// `(mu, mu by dissipation, contact cells)` of the `n^2` bonded pad of
/// [`super::thin_step::bonded_pad`] at `h`, `xi`, sliding at `deg`.
fn solve(n: usize, h: f64, xi: f64, deg: f64, formulation: &str) -> (f64, f64, usize) {
    let set = vec![format!("loading.direction_deg={deg:e}")];
    let problem = bonded_pad_with(n, h, xi, formulation, &set);
    let s = problem.solve(&Executor::Cpu, &mut solver::Silent).unwrap();
    (
        s.friction_coefficient,
        s.friction_coefficient_dissipation,
        s.stats.contact_cells,
    )
}

/// The sliding direction swept at two thicknesses inside the band on the
/// 64^2 pad (xi = 1.17e-2). Off the axes the continuation of
/// `kernel/thin_oblique.rs` is the on-axis one's limit: 0.01 degrees off
/// the axis it gives the axis' friction to 8e-5 (the stencil across `e_v`
/// enters with `sin 0.01 deg`; asserted 1e-3); before, the resolved cell
/// integral took over there: 9.52e-3 against 4.76e-3 at h = 0.2 a. The
/// trend with the direction against the periodic formulation's (the
/// exact layer's multiplier, each direction cheap), `mu(theta) /
/// mu(0)` of each: measured at most 10.4 % apart (h = 0.2 a, 45 deg).
/// Of that the continuation's own direction-dependent error, by
/// refinement to 256^2 / 512^2 (BENCHMARKS.md "Thin-layer switches"), is
/// at most 7.5 %, and the periodic pad's trend differs from the refined
/// finite pad's by up to 5.9 % (no pad edge): asserted 15 %.
#[test]
fn friction_is_continuous_in_the_sliding_direction_inside_the_band() {
    let a = 0.01 / 64.0;
    let xi = 1.17e-2;
    for r in [0.2, 0.5] {
        let (mu0, _, _) = solve(64, r * a, xi, 0.0, "non_periodic");
        let (p0, _, _) = solve(64, r * a, xi, 0.0, "periodic");
        for deg in [0.01, 10.0, 45.0, 90.0] {
            let (mu, mu_d, cells) = solve(64, r * a, xi, deg, "non_periodic");
            let (p, _, _) = solve(64, r * a, xi, deg, "periodic");
            let (trend, trend_p) = (mu / mu0, p / p0);
            eprintln!(
                "h/a = {r}, {deg} deg: mu {mu:.4e} (dissipation {mu_d:.4e}, {cells} cells), mu/mu(0) {trend:.4}, periodic {trend_p:.4}"
            );
            if deg == 0.01 {
                assert!((trend - 1.0).abs() < 1e-3, "h/a = {r}: {mu:e} vs {mu0:e}");
            }
            assert!(
                (trend / trend_p - 1.0).abs() < 0.15,
                "h/a = {r}, {deg} deg: {trend} vs periodic {trend_p}"
            );
        }
    }
}

/// Whole turns of the sliding direction are the same direction, however
/// many: `90 + 360 k` degrees is the thin layer's grid axis (its local
/// limit needs one; 3600090 degrees was refused as off the axes), and
/// `1e300` degrees, a whole number of turns, is `+x` (it was solved at
/// -131.7 degrees, `1e300 pi / 180` rounded).
#[test]
fn whole_turns_of_the_direction_are_the_same_direction() {
    let a = 0.01 / 32.0;
    let mu = |h: f64, deg: &str| {
        let set = vec![
            format!("loading.direction_deg={deg}"),
            "surface.generate.scales=8".into(),
        ];
        let problem = bonded_pad_with(32, h, 1.17e-2, "non_periodic", &set);
        problem
            .solve(&Executor::Cpu, &mut solver::Silent)
            .unwrap()
            .friction_coefficient
    };
    for h in [5e-3 * a, 1e3] {
        let axis = mu(h, "90.0");
        for turns in ["3600090.0", "-3599910.0", "450.0"] {
            assert_eq!(mu(h, turns), axis, "h = {h}, {turns} deg");
        }
        assert_eq!(mu(h, "1e300"), mu(h, "0.0"), "h = {h}");
    }
}
