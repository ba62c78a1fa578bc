//! Coarser grids at depth (physics.md section 14): at depth `z` a mode's
//! stress is `exp(-t)` times a polynomial `a + b t` of `t = |q| z`
//! (`|a|, |b| <= 3`), so the modes with `t > BAND_CUT` carry less than
//! `3 exp(-50) 51 ~ 3e-20` of their surface amplitude. The modes kept,
//! `|kx| <= B_x`, `|ky| <= B_y` (`B = floor(BAND_CUT L / (2 pi z))`, every
//! mode outside the box has `t > BAND_CUT`), make rates band-limited at
//! `B` and their squares at `2 B`: a grid of `M >= 4 B + 1` points per
//! axis samples them without aliasing, and the density's spectrum there
//! is its spectrum on the full grid, zero beyond `2 B` (exact
//! trigonometric interpolation). The cut leaves eight orders of magnitude
//! below the 1e-12 the planned density is pinned to for the rates' growth
//! with `|w|` and the pressure spectrum's spread between the modes kept
//! and those dropped.

use num_complex::Complex64;

use crate::operator::signed_index;

/// The largest `t = |q| z` kept on a coarse grid.
pub(super) const BAND_CUT: f64 = 50.0;

/// The smallest `m >= n` (at least 2) of the form `2^a 3^b 5^c`.
pub(super) fn friendly(n: usize) -> usize {
    let mut m = n.max(2);
    loop {
        let mut r = m;
        for p in [2, 3, 5] {
            while r % p == 0 {
                r /= p;
            }
        }
        if r == 1 {
            return m;
        }
        m += 1;
    }
}

/// The band `B` kept at depth `z` along an axis of period `length`, and the
/// coarse size `M` that holds `2 B`; `None` when `M` would not be smaller
/// than the grid's `n` (or `z` is not positive).
pub(super) fn coarse_axis(n: usize, length: f64, z: f64) -> Option<(usize, usize)> {
    let b = (BAND_CUT * length / (std::f64::consts::TAU * z)).floor();
    if !(b.is_finite() && b >= 0.0) || b >= n as f64 {
        return None;
    }
    let b = b as usize;
    let m = friendly(4 * b + 1);
    (m < n).then_some((b, m))
}

/// `full += scale * coarse`: the half spectrum (`height_fft` layout) of an
/// `mx x my` field placed at the same signed wavenumbers of the `nx x ny`
/// half spectrum `full` (`mx < nx`, `my < ny`); the coarse grid's Nyquist
/// modes (round-off: the field's band is below them) are left out.
pub(super) fn pad_into(
    coarse: &[Complex64],
    (mx, my): (usize, usize),
    full: &mut [Complex64],
    (nx, ny): (usize, usize),
    scale: f64,
) {
    debug_assert!(mx < nx && my < ny);
    for (j, col) in coarse.chunks(mx).enumerate() {
        if my % 2 == 0 && 2 * j == my {
            continue;
        }
        for (i, v) in col.iter().enumerate() {
            let (kx, nyq) = signed_index(i, mx);
            if nyq {
                continue;
            }
            let i_full = (kx as isize).rem_euclid(nx as isize) as usize;
            full[j * nx + i_full] += v * scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn friendly_sizes() {
        let got: Vec<usize> = [1, 2, 7, 11, 13, 17, 97, 457, 917]
            .iter()
            .map(|&n| friendly(n))
            .collect();
        assert_eq!(got, [2, 2, 8, 12, 15, 18, 100, 480, 960]);
    }

    /// Every mode outside the kept box has `t > BAND_CUT`, and the coarse
    /// size holds twice the band.
    #[test]
    fn band_and_size() {
        let (n, length) = (1024, 1.0);
        for z in [0.01, 0.03, 0.1, 0.5, 2.0] {
            if let Some((b, m)) = coarse_axis(n, length, z) {
                let q_out = std::f64::consts::TAU * (b + 1) as f64 / length;
                assert!(q_out * z > BAND_CUT, "z {z}: b {b}");
                assert!(m > 4 * b && m < n, "z {z}: m {m} b {b}");
            } else {
                assert!(z < 0.05, "z {z} left on the full grid");
            }
        }
    }
}
