//! One mode's rises at the middles of a volume source's layers, in one
//! sweep down and one up ([`super::periodic::PeriodicPlan::volume_scan`];
//! physics.md section 14).
//!
//! For a mode of decay rate `m`, with `E_l = h_l phi1(m h_l) Q_l` (layer
//! `l`'s integral) and `e_l = exp(-m h_l / 2)`,
//! [`super::modes::layer_integral`] summed over the layers is, at the
//! middle `z_l`: the image `exp(-m z_l) I`, `I = sum_l' exp(-m a_l') E_l'`;
//! the layers above, `e_l` times `A_l = sum_{l' < l} exp(-m (a_l - b_l'))
//! E_l'`; those below, `e_l` times `B_l = sum_{l' > l} exp(-m (a_l' - b_l))
//! E_l'`; its own layer, `h_l phi1(m h_l / 2) Q_l`; at the surface `2 I`.
//! `A` follows from the sweep down (`A_{l+1} = E_l + exp(-m h_l) A_l`),
//! `B` and the sum from the sweep up, every exponent with a non-negative
//! real part: `O(L)` per mode for `L` layers.
//!
//! Each layer needs `e_l` and `phi1(m h_l / 2)`. Where a layer above is as
//! thick ([`Origin::Same`]) or half as thick ([`Origin::Double`], `exp(-2w)
//! = exp(-w)^2`, `phi1(2w) = phi1(w) (1 + exp(-w)) / 2`), they follow from
//! its pair without an exponential: geometric layers ([`super::DepthRule`],
//! boundaries doubling, Gauss shares of equal weight within a panel) need
//! one exponential per few panels and share. A chain of doublings restarts
//! from [`super::modes::exp_phi1`] after [`MAX_DOUBLINGS`]: squaring
//! doubles a relative error, so the pair stays within `2^4` roundings of
//! the direct one.

use num_complex::Complex64;

use super::modes::exp_phi1;

/// Doublings in a row before a layer's pair is computed afresh.
const MAX_DOUBLINGS: usize = 4;

/// Thicknesses that agree within this (relative) are taken as equal, or
/// as double: the rounding of boundaries `a + h s` (a few 1e-16), far
/// below it, changes the pair by `|m h| 1e-14` at most where it matters
/// (`Re(m h) / 2 <= 40`, beyond which `exp(-w)` is taken as 0).
const SAME_THICKNESS: f64 = 1e-14;

/// Where a layer's `(exp(-w), phi1(w))`, `w = m h / 2`, comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Origin {
    /// [`exp_phi1`] itself.
    Direct,
    /// Layer `j`'s, as thick.
    Same(usize),
    /// From layer `j`'s, half as thick.
    Double(usize),
}

/// The layers of one volume source, planned for every mode's sweep.
pub(super) struct SweepLayers {
    thickness: Vec<f64>,
    origin: Vec<Origin>,
}

impl SweepLayers {
    /// Plan the layers `bounds` (`(top, bottom)` \[m\], top to bottom).
    pub fn new(bounds: &[(f64, f64)]) -> Self {
        let thickness: Vec<f64> = bounds.iter().map(|(a, b)| b - a).collect();
        let mut origin = Vec::with_capacity(thickness.len());
        // Doublings since the last direct pair, per layer.
        let mut chain: Vec<usize> = Vec::with_capacity(thickness.len());
        for (l, &h) in thickness.iter().enumerate() {
            let close = |x: f64| (x - h).abs() <= SAME_THICKNESS * h;
            // The nearest layer above that is as thick, else the nearest
            // that is half as thick with a short enough chain.
            let same = (0..l).rev().find(|&j| close(thickness[j]));
            let double = (0..l)
                .rev()
                .find(|&j| close(2.0 * thickness[j]) && chain[j] < MAX_DOUBLINGS);
            let (o, c) = match (same, double) {
                (Some(j), _) => (Origin::Same(j), chain[j]),
                (None, Some(j)) => (Origin::Double(j), chain[j] + 1),
                (None, None) => (Origin::Direct, 0),
            };
            origin.push(o);
            chain.push(c);
        }
        Self { thickness, origin }
    }

    /// The number of layers.
    pub fn count(&self) -> usize {
        self.thickness.len()
    }

    /// How many layers take an exponential ([`Origin::Direct`]).
    #[cfg(test)]
    fn direct(&self) -> usize {
        self.origin.iter().filter(|o| **o == Origin::Direct).count()
    }
}

/// One mode's sweep over the layers: the layers' coefficients `q`, the
/// rises at their middles summed over the calls since [`Sweep::clear`]
/// (the Nyquist variants of a mode), and scratch.
pub(super) struct Sweep {
    /// Layer `l`'s source coefficient `Q_l` of the mode.
    pub q: Vec<Complex64>,
    /// The rise at layer `l`'s middle.
    pub rise: Vec<Complex64>,
    /// `e_l = exp(-m h_l / 2)` and `phi1(m h_l / 2)`.
    half: Vec<(Complex64, Complex64)>,
    /// `E_l`.
    whole: Vec<Complex64>,
    /// The layer's own term and the layers above: `h_l phi1 Q_l + e_l A_l`.
    near: Vec<Complex64>,
    /// `exp(-m a_l) e_l = exp(-m z_l)`, the image's factor.
    image_at: Vec<Complex64>,
}

impl Sweep {
    /// Scratch for `layers` layers.
    pub fn new(layers: usize) -> Self {
        let zero = vec![Complex64::default(); layers];
        Self {
            q: zero.clone(),
            rise: zero.clone(),
            half: vec![(Complex64::default(), Complex64::default()); layers],
            whole: zero.clone(),
            near: zero.clone(),
            image_at: zero,
        }
    }

    /// Start a mode: no rise yet.
    pub fn clear(&mut self) {
        self.rise.iter_mut().for_each(|r| *r = Complex64::default());
    }

    /// Add the rises at the layers' middles under the decay rate `m`
    /// (module docs), for a conductivity `lam`; return the surface rise.
    pub fn add(&mut self, m: Complex64, layers: &SweepLayers, lam: f64) -> Complex64 {
        const ONE: Complex64 = Complex64::new(1.0, 0.0);
        let scale = m.inv() / (2.0 * lam);
        // The sweep down: A_l (`above`), I (`image`), exp(-m a_l) (`depth`).
        let (mut above, mut image, mut depth) = (Complex64::default(), Complex64::default(), ONE);
        for l in 0..layers.count() {
            let h = layers.thickness[l];
            let (e, p) = match layers.origin[l] {
                Origin::Direct => exp_phi1(m * (0.5 * h)),
                Origin::Same(j) => self.half[j],
                Origin::Double(j) => {
                    let (e, p) = self.half[j];
                    (e * e, p * (ONE + e) * 0.5)
                }
            };
            self.half[l] = (e, p);
            let e2 = e * e;
            let own = p * self.q[l] * h;
            // phi1(2 w) = phi1(w) (1 + exp(-w)) / 2.
            let whole = own * (ONE + e) * 0.5;
            self.whole[l] = whole;
            self.near[l] = own + e * above;
            self.image_at[l] = depth * e;
            image += depth * whole;
            above = whole + e2 * above;
            depth *= e2;
        }
        // The sweep up: B_l (`below`), and each layer's sum.
        let mut below = Complex64::default();
        for l in (0..layers.count()).rev() {
            let (e, _) = self.half[l];
            let sum = self.near[l] + self.image_at[l] * image + e * below;
            self.rise[l] += scale * sum;
            below = self.whole[l] + e * e * below;
        }
        2.0 * scale * image
    }
}

#[cfg(test)]
mod tests {
    use super::super::modes::layer_integral;
    use super::*;
    use crate::heat::DepthRule;
    use crate::response::Grid;

    /// The rises at the layers' middles and at the surface, against the
    /// closed forms of every layer at every middle
    /// ([`layer_integral`], `O(L^2)`, an exponential each), for the
    /// default and refined rules' layers and uneven ones (no pairs), for
    /// decay rates from the Taylor range of `exp_phi1` to beyond its cut,
    /// on both sides of the sliding axis. The default rule's 45 layers
    /// take 6 exponentials (two in the first panel, two wherever a chain
    /// of doublings restarts).
    #[test]
    fn the_sweep_matches_the_closed_forms() {
        let grid = Grid::square(1024, 1024, 2.5e-4 / 1024.0)
            .unwrap()
            .periodic();
        let default = DepthRule::default().layers(&grid).unwrap();
        let refined = DepthRule::refined().layers(&grid).unwrap();
        let uneven: Vec<(f64, f64)> = (0..12)
            .map(|l| {
                (
                    1e-7 * (l * l) as f64,
                    1e-7 * ((l + 1) * (l + 1)) as f64 * 1.1,
                )
            })
            .map(|(a, b)| (a, b.max(a * 1.0001)))
            .scan(0.0, |top, (_, b)| {
                let pair = (*top, *top + b);
                *top += b;
                Some(pair)
            })
            .collect();
        let cases: Vec<Vec<(f64, f64)>> =
            vec![default.iter().collect(), refined.iter().collect(), uneven];
        let plan = SweepLayers::new(&cases[0]);
        assert_eq!((plan.count(), plan.direct()), (45, 6));
        let lam = 0.25;
        for bounds in &cases {
            let layers = SweepLayers::new(bounds);
            let mut sweep = Sweep::new(bounds.len());
            for (l, q) in sweep.q.iter_mut().enumerate() {
                *q = Complex64::new(1.0 + l as f64, 0.5 - 0.1 * l as f64);
            }
            for k in [2.5e4, 4e5, 3e6, 1.3e7] {
                for (re, im) in [(1.0, 0.0), (1.0, 0.7), (0.8, -1.5), (1.0, 1e-3)] {
                    let m = Complex64::new(k * re, k * im);
                    sweep.clear();
                    let surface = sweep.add(m, &layers, lam);
                    let scale = m.inv() / (2.0 * lam);
                    let at = |z: f64| -> Complex64 {
                        bounds
                            .iter()
                            .zip(&sweep.q)
                            .map(|(&b, q)| scale * layer_integral(m, b, z) * q)
                            .sum()
                    };
                    let want: Vec<Complex64> =
                        bounds.iter().map(|(a, b)| at(0.5 * (a + b))).collect();
                    let peak = want.iter().map(|w| w.norm()).fold(0.0, f64::max);
                    for (l, (got, want)) in sweep.rise.iter().zip(&want).enumerate() {
                        assert!(
                            (got - want).norm() <= 1e-13 * peak,
                            "m {m}, layer {l}: {got} against {want} (peak {peak})"
                        );
                    }
                    let top = at(0.0);
                    assert!(
                        (surface - top).norm() <= 1e-13 * top.norm(),
                        "m {m}: surface {surface} against {top}"
                    );
                }
            }
        }
    }

    /// Chains of doublings restart: no layer's pair is more than
    /// `MAX_DOUBLINGS` squarings from a direct one, and a layer as thick
    /// as one above takes its pair.
    #[test]
    fn doubling_chains_are_bounded() {
        let bounds: Vec<(f64, f64)> = (0..20)
            .map(|k| (2f64.powi(k) - 1.0, 2f64.powi(k + 1) - 1.0))
            .collect();
        let layers = SweepLayers::new(&bounds);
        let mut chain = vec![0; bounds.len()];
        for (l, o) in layers.origin.iter().enumerate() {
            chain[l] = match *o {
                Origin::Direct => 0,
                Origin::Same(j) => chain[j],
                Origin::Double(j) => chain[j] + 1,
            };
            assert!(chain[l] <= MAX_DOUBLINGS, "{l}: {:?}", layers.origin);
        }
        assert_eq!(layers.direct(), 4, "{:?}", layers.origin);
        let same = SweepLayers::new(&[(0.0, 1.0), (1.0, 2.0), (2.0, 3.5)]);
        assert_eq!(
            same.origin,
            [Origin::Direct, Origin::Same(0), Origin::Direct]
        );
    }
}
