//! CPU executor: f64 vectors, rayon-parallel kernels, the operator applied by
//! [`crate::operator::GridOperator`] (FFT or dense). With an operator whose
//! transforms run in f32 the Krylov products and the preconditioner are
//! f32 and [`Backend::apply`] is the operator's f64 product (mixed
//! precision, [`Backend::refines`]). This is the reference
//! path; the GPU executor implements the same [`Backend`] trait.

use rayon::prelude::*;

use super::Backend;
use crate::operator::{GridOperator, GridWork};

/// Vectors below this length are processed serially (rayon overhead).
const PAR_MIN: usize = 1 << 14;

/// The CPU backend around a grid operator.
pub struct CpuBackend<Op: GridOperator> {
    op: Op,
    n: usize,
    /// Work vectors of operators without set products of their own
    /// ([`GridOperator::apply_set`]); empty for the FFT operators.
    work: GridWork,
}

impl<Op: GridOperator> CpuBackend<Op> {
    pub fn new(op: Op) -> Self {
        let (nx, ny) = op.shape();
        Self {
            op,
            n: nx * ny,
            work: GridWork::default(),
        }
    }

    /// The wrapped operator.
    pub fn operator_mut(&mut self) -> &mut Op {
        &mut self.op
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    if a.len() < PAR_MIN {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    } else {
        a.par_chunks(4096)
            .zip(b.par_chunks(4096))
            .map(|(x, y)| x.iter().zip(y).map(|(u, v)| u * v).sum::<f64>())
            .sum()
    }
}

/// Set every cell's flag to `rule(was in, p, gap)`; returns `(changes,
/// size of the new set)`.
fn update_mask(
    mask: &mut [u8],
    p: &[f64],
    gap: &[f64],
    rule: impl Fn(bool, f64, f64) -> bool + Sync,
) -> (usize, usize) {
    mask.par_iter_mut()
        .with_min_len(PAR_MIN)
        .zip(p.par_iter().zip(gap.par_iter()))
        .map(|(m, (&pi, &gi))| {
            let was = *m != 0;
            let now = rule(was, pi, gi);
            *m = u8::from(now);
            (usize::from(was != now), usize::from(now))
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

impl<Op: GridOperator> Backend for CpuBackend<Op> {
    type Vector = Vec<f64>;
    type Index = Vec<usize>;
    /// One byte per cell (1: in the set).
    type Mask = Vec<u8>;

    fn name(&self) -> String {
        format!("cpu ({} threads)", rayon::current_num_threads())
    }

    fn grid_len(&self) -> usize {
        self.n
    }

    fn reserve(&mut self, count: usize, len: usize) -> Result<(), String> {
        let bytes = (count as u64).saturating_mul(len as u64).saturating_mul(8);
        crate::io::memory::check_fits(|| format!("set of {count} vectors of {len} values"), bytes)
            .map_err(|e| e.to_string())
    }

    fn zeros(&mut self, len: usize) -> Vec<f64> {
        vec![0.0; len]
    }

    fn resize(&mut self, v: &mut Vec<f64>, len: usize) {
        v.resize(len, 0.0);
    }

    fn upload(&mut self, host: &[f64], dst: &mut Vec<f64>) {
        dst.copy_from_slice(host);
    }

    fn download(&mut self, src: &Vec<f64>, host: &mut [f64]) {
        host.copy_from_slice(src);
    }

    fn adopt(&mut self, host: Vec<f64>) -> Vec<f64> {
        host
    }

    fn take_host(&mut self, v: Vec<f64>) -> Vec<f64> {
        v
    }

    fn mask_from(&mut self, host: &[f64]) -> Vec<u8> {
        host.par_iter()
            .with_min_len(PAR_MIN)
            .map(|&m| u8::from(m > 0.5))
            .collect()
    }

    fn copy(&mut self, src: &Vec<f64>, dst: &mut Vec<f64>) {
        dst.copy_from_slice(src);
    }

    fn apply(&mut self, x: &Vec<f64>, y: &mut Vec<f64>) {
        self.op.apply_exact(x, y);
    }

    fn refines(&self) -> bool {
        self.op.epsilon() > f64::EPSILON
    }

    fn has_preconditioner(&self) -> bool {
        self.op.has_preconditioner()
    }

    fn set_contact_fraction(&mut self, fraction: f64) {
        self.op.set_contact_fraction(fraction);
    }

    fn precondition(&mut self, x: &Vec<f64>, y: &mut Vec<f64>) {
        self.op.precondition(x, y);
    }

    fn apply_set(&mut self, index: &Vec<usize>, x: &Vec<f64>, y: &mut Vec<f64>) {
        self.op.apply_set(index, x, y, &mut self.work);
    }

    fn apply_set_exact(&mut self, index: &Vec<usize>, x: &Vec<f64>, y: &mut Vec<f64>) {
        self.op.apply_set_exact(index, x, y, &mut self.work);
    }

    fn precondition_set(&mut self, index: &Vec<usize>, x: &Vec<f64>, y: &mut Vec<f64>) {
        self.op.precondition_set(index, x, y, &mut self.work);
    }

    fn dot(&mut self, a: &Vec<f64>, b: &Vec<f64>) -> f64 {
        dot(a, b)
    }

    fn dots(&mut self, basis: &[Vec<f64>], w: &Vec<f64>, out: &mut [f64]) {
        if w.len() < PAR_MIN {
            for (o, v) in out.iter_mut().zip(basis) {
                *o = dot(v, w);
            }
        } else {
            out.par_iter_mut()
                .zip(basis.par_iter())
                .for_each(|(o, v)| *o = dot(v, w));
        }
    }

    fn axpy(&mut self, alpha: f64, x: &Vec<f64>, y: &mut Vec<f64>) {
        y.par_iter_mut()
            .with_min_len(PAR_MIN)
            .zip(x.par_iter())
            .for_each(|(yi, xi)| *yi += alpha * xi);
    }

    fn combine(&mut self, coeffs: &[f64], basis: &[Vec<f64>], y: &mut Vec<f64>) {
        y.par_chunks_mut(4096).enumerate().for_each(|(c, ys)| {
            let off = c * 4096;
            for (k, &a) in coeffs.iter().enumerate() {
                let v = &basis[k][off..off + ys.len()];
                for (yi, vi) in ys.iter_mut().zip(v) {
                    *yi += a * vi;
                }
            }
        });
    }

    fn scale(&mut self, alpha: f64, x: &mut Vec<f64>) {
        x.par_iter_mut()
            .with_min_len(PAR_MIN)
            .for_each(|v| *v *= alpha);
    }

    fn add_scalar(&mut self, alpha: f64, x: &mut Vec<f64>) {
        x.par_iter_mut()
            .with_min_len(PAR_MIN)
            .for_each(|v| *v += alpha);
    }

    fn sum(&mut self, x: &Vec<f64>) -> f64 {
        x.par_chunks(4096).map(|c| c.iter().sum::<f64>()).sum()
    }

    fn index_of(&mut self, mask: &Vec<u8>) -> Vec<usize> {
        mask.iter()
            .enumerate()
            .filter(|(_, &m)| m != 0)
            .map(|(i, _)| i)
            .collect()
    }

    fn index_len(&self, index: &Vec<usize>) -> usize {
        index.len()
    }

    fn gather(&mut self, index: &Vec<usize>, full: &Vec<f64>, short: &mut Vec<f64>) {
        short
            .par_iter_mut()
            .with_min_len(PAR_MIN)
            .zip(index.par_iter())
            .for_each(|(s, &i)| *s = full[i]);
    }

    fn scatter(&mut self, index: &Vec<usize>, short: &Vec<f64>, full: &mut Vec<f64>) {
        full.par_iter_mut()
            .with_min_len(PAR_MIN)
            .for_each(|v| *v = 0.0);
        for (&i, &s) in index.iter().zip(short) {
            full[i] = s;
        }
    }

    fn gap(&mut self, g: &Vec<f64>, u: &Vec<f64>, delta: f64, out: &mut Vec<f64>) {
        out.par_iter_mut()
            .with_min_len(PAR_MIN)
            .zip(g.par_iter().zip(u.par_iter()))
            .for_each(|(o, (gi, ui))| *o = gi - delta + ui);
    }

    fn to_gap(&mut self, g: &Vec<f64>, delta: f64, x: &mut Vec<f64>) {
        x.par_iter_mut()
            .with_min_len(PAR_MIN)
            .zip(g.par_iter())
            .for_each(|(xi, gi)| *xi += gi - delta);
    }

    fn update_active_set(
        &mut self,
        p: &Vec<f64>,
        gap: &Vec<f64>,
        mask: &mut Vec<u8>,
    ) -> (usize, usize) {
        update_mask(
            mask,
            p,
            gap,
            |was, pi, gi| if was { pi > 0.0 } else { gi < 0.0 },
        )
    }

    fn newton_set(
        &mut self,
        p: &Vec<f64>,
        gap: &Vec<f64>,
        stiffness: f64,
        mask: &mut Vec<u8>,
    ) -> (usize, usize) {
        update_mask(mask, p, gap, |_, pi, gi| pi > stiffness * gi)
    }

    fn complementarity(&mut self, p: &Vec<f64>, gap: &Vec<f64>, stiffness: f64) -> (f64, f64) {
        p.par_iter()
            .with_min_len(PAR_MIN)
            .zip(gap.par_iter())
            .map(|(pi, gi)| {
                let r = pi.min(stiffness * gi);
                (r * r, pi * pi)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1))
    }
}
