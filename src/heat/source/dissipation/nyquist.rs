//! The Nyquist modes of the dissipation density (module docs of
//! `dissipation`): a Nyquist mode samples both signs of its Nyquist
//! components; its main field takes the mean of its multiplier over them,
//! and the odd parts over the signs, whose fields at the grid points are
//! `(-1)^i` times a one-dimensional transform, add their squares
//! (physics.md section 14: the grid sum of `D` is the Fourier sum).

use num_complex::Complex64;

use super::super::stress::{dissipation_form, mode_stress, ModeStress};
use super::{component, Dissipation, RateFn};
use crate::operator::{nyquist_signs, signed_index};

/// The parts of one mode's multiplier over the signs of its Nyquist
/// components: the mean (the main field) and the odd parts along x, y and
/// both (zero where the component is not Nyquist).
#[derive(Clone, Copy, Default)]
pub(super) struct Parts {
    pub mean: ModeStress,
    pub odd_x: ModeStress,
    pub odd_y: ModeStress,
    pub odd_xy: ModeStress,
}

pub(super) fn scaled(s: &ModeStress, c: Complex64) -> ModeStress {
    ModeStress {
        dev: s.dev.map(|d| d * c),
        trace: s.trace * c,
    }
}

pub(super) fn add(a: &mut ModeStress, b: &ModeStress) {
    for (x, y) in a.dev.iter_mut().zip(&b.dev) {
        *x += y;
    }
    a.trace += b.trace;
}

/// The Nyquist modes' parts at one depth for one multiplier: the
/// x-Nyquist row (`i = nx / 2`, by `j`) and the y-Nyquist column (`j = ny
/// / 2`, by `i`), empty where the size is odd.
pub(super) struct NyquistParts {
    pub row: Vec<Parts>,
    pub column: Vec<Parts>,
}

impl Dissipation {
    /// The parts of the multiplier of mode `(i, j)` (`j <= ny / 2`) for the
    /// stress-rate multiplier `rate` at depth `z`, times the pressure's
    /// coefficient; `None` for `q = 0`.
    pub(super) fn parts(&self, i: usize, j: usize, rate: &RateFn, z: f64) -> Option<Parts> {
        if i == 0 && j == 0 {
            return None;
        }
        let (kx, nyq_x) = signed_index(i, self.nx);
        let (ky, nyq_y) = signed_index(j, self.ny);
        let tau2 = std::f64::consts::TAU;
        let (qx, qy) = (tau2 * kx / self.length.0, tau2 * ky / self.length.1);
        let sx = nyquist_signs(nyq_x);
        let sy = nyquist_signs(nyq_y);
        let count = (sx.len() * sy.len()) as f64;
        let p = self.spectrum[j * self.nx + i];
        let mut parts = Parts::default();
        for &a in sx {
            for &b in sy {
                let q = (a * qx, b * qy);
                let w = -self.speed * (q.0 * self.e.0 + q.1 * self.e.1);
                let m = scaled(&mode_stress(q, z, self.nu), rate.at(w) * p / count);
                add(&mut parts.mean, &m);
                add(&mut parts.odd_x, &scaled(&m, Complex64::new(a, 0.0)));
                add(&mut parts.odd_y, &scaled(&m, Complex64::new(b, 0.0)));
                add(&mut parts.odd_xy, &scaled(&m, Complex64::new(a * b, 0.0)));
            }
        }
        // The odd parts of a real field are imaginary over a sign pair:
        // `-i` makes their grid fields real (same squares).
        let minus_i = Complex64::new(0.0, -1.0);
        parts.odd_x = if nyq_x {
            scaled(&parts.odd_x, minus_i)
        } else {
            ModeStress::default()
        };
        parts.odd_y = if nyq_y {
            scaled(&parts.odd_y, minus_i)
        } else {
            ModeStress::default()
        };
        if !(nyq_x && nyq_y) {
            parts.odd_xy = ModeStress::default();
        }
        Some(parts)
    }

    pub(super) fn nyquist_parts(&self, rate: &RateFn, z: f64) -> NyquistParts {
        let (nx, ny) = (self.nx, self.ny);
        let row = if nx % 2 == 0 {
            (0..=ny / 2)
                .map(|j| self.parts(nx / 2, j, rate, z).unwrap_or_default())
                .collect()
        } else {
            Vec::new()
        };
        let column = if ny % 2 == 0 {
            (0..nx)
                .map(|i| self.parts(i, ny / 2, rate, z).unwrap_or_default())
                .collect()
        } else {
            Vec::new()
        };
        NyquistParts { row, column }
    }

    /// `density += weight` times the squares of the odd parts of the
    /// Nyquist modes ([`Dissipation::odd_forms`]).
    pub(super) fn add_nyquist(&self, parts: &NyquistParts, weight: f64, density: &mut [f64]) {
        self.odd_forms(parts).add_to(weight, density, self.ny);
    }

    /// The squares of the odd parts of the Nyquist modes (module docs):
    /// along y for the x-Nyquist row, along x for the y-Nyquist column, a
    /// constant for the corner.
    pub(super) fn odd_forms(&self, parts: &NyquistParts) -> OddForms {
        let (nx, ny) = (self.nx, self.ny);
        let nu = self.nu;
        // x-Nyquist row: the field is (-1)^i g(y_j), g the inverse
        // transform along y of the odd parts (Hermitian in ky).
        let along_y: Vec<f64> = if nx % 2 == 0 {
            let mut comps = Vec::with_capacity(6);
            for c in 0..6 {
                let mut g = vec![Complex64::default(); ny];
                for j in 0..=ny / 2 {
                    let v = component(&parts.row[j].odd_x, c);
                    g[j] = v;
                    if j > 0 && j < ny - j {
                        g[ny - j] = v.conj();
                    }
                }
                self.line_y.process(&mut g);
                comps.push(g.iter().map(|v| v.re).collect::<Vec<f64>>());
            }
            (0..ny).map(|j| form_of(&comps, j, nu)).collect()
        } else {
            Vec::new()
        };
        // y-Nyquist column: (-1)^j h(x_i), h along x.
        let along_x: Vec<f64> = if ny % 2 == 0 {
            let mut comps = Vec::with_capacity(6);
            for c in 0..6 {
                let mut h: Vec<Complex64> = parts
                    .column
                    .iter()
                    .map(|p| component(&p.odd_y, c))
                    .collect();
                self.line_x.process(&mut h);
                comps.push(h.iter().map(|v| v.re).collect::<Vec<f64>>());
            }
            (0..nx).map(|i| form_of(&comps, i, nu)).collect()
        } else {
            Vec::new()
        };
        let corner = if nx % 2 == 0 && ny % 2 == 0 {
            let p = &parts.column[nx / 2].odd_xy;
            let comps: Vec<Vec<f64>> = (0..6).map(|c| vec![component(p, c).re]).collect();
            form_of(&comps, 0, nu)
        } else {
            0.0
        };
        OddForms {
            along_y,
            along_x,
            corner,
        }
    }
}

/// The squares of the Nyquist modes' odd parts (module docs): a function
/// of y (the x-Nyquist row's, empty for odd `nx`), one of x (the
/// y-Nyquist column's, empty for odd `ny`) and a constant (the corner's).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct OddForms {
    pub along_y: Vec<f64>,
    pub along_x: Vec<f64>,
    pub corner: f64,
}

impl OddForms {
    /// `self += other` (forms of the same grid, or `self` empty).
    pub fn add(&mut self, other: &OddForms) {
        for (mine, theirs) in [
            (&mut self.along_y, &other.along_y),
            (&mut self.along_x, &other.along_x),
        ] {
            mine.resize(theirs.len(), 0.0);
            mine.iter_mut().zip(theirs).for_each(|(a, b)| *a += b);
        }
        self.corner += other.corner;
    }

    /// The forms at `(x, y)`.
    pub fn at(&self, x: usize, y: usize) -> f64 {
        self.along_y.get(y).copied().unwrap_or(0.0)
            + self.along_x.get(x).copied().unwrap_or(0.0)
            + self.corner
    }

    /// `density += weight` times the forms on the grid of `ny` points
    /// along y (C order, axis 0 = x).
    fn add_to(&self, weight: f64, density: &mut [f64], ny: usize) {
        for (i, row) in density.chunks_mut(ny).enumerate() {
            for (j, d) in row.iter_mut().enumerate() {
                *d += weight * self.at(i, j);
            }
        }
    }
}

/// The dissipation form at index `n` of six component arrays.
fn form_of(comps: &[Vec<f64>], n: usize, nu: f64) -> f64 {
    let dev = [
        comps[0][n],
        comps[1][n],
        comps[2][n],
        comps[3][n],
        comps[4][n],
    ];
    dissipation_form(&dev, comps[5][n], nu)
}
