//! Love's rectangle integral far away (physics.md section 3: the closed form
//! loses digits like `eps (r/a)^2`): the library's value must stay within
//! 1e-12 relative of a reference out to 1e6 cells, and the switch from the
//! closed form to the multipole expansion must be seamless.
//!
//! Reference: a tensor Gauss-Legendre rule (24 x 24 nodes) on the rectangle
//! with compensated summation. Beyond 4 half-diagonals the integrand is
//! analytic in a Bernstein ellipse of parameter > 8 in each variable, so the
//! rule is exact to below 1e-20 and the sum carries ~1e-16 relative error.

use viscoslide::internals::kernel::love::{LoveRect, SWITCH};
use viscoslide::internals::kernel::quad::gauss_legendre;

fn reference(x: f64, y: f64, ax: f64, ay: f64) -> f64 {
    let (g, w) = gauss_legendre(24);
    let (hx, hy) = (0.5 * ax, 0.5 * ay);
    let mut s = 0.0;
    let mut c = 0.0;
    for i in 0..24 {
        for j in 0..24 {
            let v = w[i] * w[j] / (x - hx * g[i]).hypot(y - hy * g[j]);
            let t = s + v;
            c += if s.abs() >= v.abs() {
                (s - t) + v
            } else {
                (v - t) + s
            };
            s = t;
        }
    }
    (s + c) * hx * hy
}

#[test]
fn far_field_is_accurate_to_a_million_cells() {
    let mut worst = 0.0f64;
    for &(ax, ay) in &[(1.0, 1.0), (2.0, 0.5), (1e-3, 3e-3)] {
        let rect = LoveRect::new(ax, ay);
        let a = f64::max(ax, ay);
        for &r in &[3.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6] {
            for k in 0..13 {
                let ang = 0.1 + k as f64 * 0.5;
                let (x, y) = (r * a * ang.cos(), r * a * ang.sin());
                let got = rect.eval(x, y);
                let want = reference(x, y, ax, ay);
                let e = (got - want).abs() / want;
                worst = worst.max(e);
                assert!(
                    e < 1e-12,
                    "({ax},{ay}) r={r} ang={ang}: {got} vs {want} ({e:e})"
                );
            }
        }
    }
    println!("Love far field: max rel error {worst:e}");
}

#[test]
fn switch_between_closed_form_and_multipole_is_seamless() {
    let mut worst = 0.0f64;
    for &(ax, ay) in &[(1.0, 1.0), (3.0, 1.0)] {
        let rect = LoveRect::new(ax, ay);
        let rs = rect.switch_radius_sq().sqrt();
        assert!((rs - SWITCH * 0.5 * ax.hypot(ay)).abs() < 1e-12 * rs);
        for k in 0..24 {
            let ang = k as f64 * 0.2618;
            for f in [0.999_999, 1.0, 1.000_001, 1.1] {
                let (x, y) = (f * rs * ang.cos(), f * rs * ang.sin());
                let r2 = x * x + y * y;
                let near = rect.near(x, y);
                let far = rect.far(x, y, r2);
                let want = reference(x, y, ax, ay);
                let e = ((near - far).abs() / want)
                    .max((near - want).abs() / want)
                    .max((far - want).abs() / want);
                worst = worst.max(e);
                assert!(
                    e < 5e-14,
                    "({ax},{ay}) ang={ang} f={f}: {near} {far} {want}"
                );
            }
        }
    }
    println!("Love switch: max mismatch {worst:e}");
}

#[test]
fn naive_closed_form_does_lose_digits_far_away() {
    // Shows why the switch exists: at 1e5 cells the closed form alone is
    // wrong well beyond 1e-12.
    let rect = LoveRect::new(1.0, 1.0);
    let (x, y) = (1e5, 3.0);
    let e = (rect.near(x, y) - reference(x, y, 1.0, 1.0)).abs() / reference(x, y, 1.0, 1.0);
    assert!(e > 1e-12, "{e:e}");
}
