//! The grid of a magnification level (physics.md section 12): the
//! smallest FFT-friendly size that gives `K` cells per shortest wavelength
//! `2 pi / q1` and lets the solver's coarse-to-fine cascade halve it down.

use std::f64::consts::TAU;

use crate::response::gcd;

/// Whether `n` has no prime factor above 5 (a size the FFTs handle with
/// their fastest radices).
fn smooth(mut n: usize) -> bool {
    for p in [2, 3, 5] {
        while n % p == 0 {
            n /= p;
        }
    }
    n == 1
}

/// Whether the solver's coarse-to-fine cascade, which halves a grid while
/// its side is even and the half at least 64 cells, reaches a grid of
/// fewer than 128 cells from `n` (a 4050 grid stops at 2025 and solves
/// most of its contact there: several times slower than 4096).
fn cascades_down(mut n: usize) -> bool {
    while n % 2 == 0 && n / 2 >= 64 {
        n /= 2;
    }
    n < 128
}

/// The grid `(nx, ny)` of a level: the smallest FFT-friendly `nx` (no
/// prime factor above 5, halving down to fewer than 128 cells for the
/// solver's cascade; any multiple of the aspect's denominator when no such
/// size is one) with at least `cells` cells per shortest wavelength
/// `2 pi / q1` on a side `length`, and `ny` keeping the configuration's
/// side along y exactly (`ny / nx` of the configuration), both at least 8.
pub(crate) fn level_grid(
    cells: f64,
    q1: f64,
    length: f64,
    nx0: usize,
    ny0: usize,
) -> (usize, usize) {
    // A hair below the exact count so that round-off in K q1 L / (2 pi)
    // does not add a cell.
    let need = (cells * q1 * length / TAU * (1.0 - 1e-12)).ceil().max(8.0) as usize;
    let g = gcd(nx0, ny0);
    let (p, q) = (ny0 / g, nx0 / g);
    let ny_of = |n: usize| n.checked_mul(p).map(|m| m / q).unwrap_or(usize::MAX);
    let fits = |n: usize| n >= need && n % q == 0 && ny_of(n) >= 8;
    // Every size with both properties is c 2^k with c < 128 5-smooth.
    let n = (1..128usize)
        .filter(|&c| smooth(c))
        .flat_map(|c| (0..48u32).filter_map(move |k| c.checked_mul(1usize << k)))
        .filter(|&n| fits(n) && cascades_down(n) && cascades_down(ny_of(n)))
        .min()
        .unwrap_or_else(|| need.div_ceil(q).max(8usize.div_ceil(p.max(1))) * q);
    (n, ny_of(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_fft_friendly_and_resolve_k_cells() {
        // Paper experiment: L = 2 pi / 2.51e4.
        let l = 2.5032990e-4;
        for (q1, want) in [(2.51e5, 45), (2.82e6, 480), (6.31e6, 1024)] {
            let (n, ny) = level_grid(4.0, q1, l, 1024, 1024);
            assert_eq!((n, ny), (want, want), "q1 = {q1}");
            assert!(TAU / q1 / (l / n as f64) >= 4.0);
        }
        // Exactly 40 cells needed: no extra cell from round-off.
        let q1 = 40.0 * TAU / l / 4.0;
        assert_eq!(level_grid(4.0, q1, l, 64, 64).0, 40);
        // 16 cells at the experiment's q1: 4096, not 4050 (= 2 x 2025).
        assert_eq!(level_grid(16.0, 6.31e6, l, 64, 64).0, 4096);
        assert!(cascades_down(4096) && cascades_down(120) && !cascades_down(4050));
        // Aspect 3:2 kept exactly.
        let (n, ny) = level_grid(4.0, 2.51e5, l, 96, 64);
        assert_eq!(n * 2, ny * 3);
        assert!(smooth(n) && n >= 40);
        assert!(smooth(1024) && smooth(450) && !smooth(14));
    }
}
