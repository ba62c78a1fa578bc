//! Restarted GMRES with classical Gram-Schmidt and one re-orthogonalisation
//! (CGS2), written against [`Backend`] so that every long vector may live on
//! a device and each iteration reads back only a few scalars (two batched
//! dot-product sets and a norm). Vectors may carry one extra host scalar, so
//! the same routine solves the bordered system of load control. An operator
//! may supply a right preconditioner `M` (GMRES then runs on `A M` and
//! minimises the true residual). Where the operator's products run in a
//! lower precision ([`AugOperator::apply_exact`]) the residual of each
//! restart is the exact one, so the restarts refine the solution to the
//! precision of the vectors.

use super::Observer;
use crate::backend::Backend;

/// A grid vector plus an optional bordering scalar.
pub struct AugVec<V> {
    pub v: V,
    pub s: f64,
}

/// The map a Krylov method applies: `y = A x`.
pub trait AugOperator<B: Backend> {
    /// `y = A (x_v, x_s)`.
    fn apply(&mut self, backend: &mut B, x_v: &B::Vector, x_s: f64, y: &mut AugVec<B::Vector>);
    /// `y = A (x_v, x_s)` to the rounding of the vectors: the residual at
    /// every restart (iterative refinement where [`AugOperator::apply`]
    /// runs in a lower precision; default: [`AugOperator::apply`]).
    fn apply_exact(
        &mut self,
        backend: &mut B,
        x_v: &B::Vector,
        x_s: f64,
        y: &mut AugVec<B::Vector>,
    ) {
        self.apply(backend, x_v, x_s, y);
    }
    /// Whether the bordering scalar is an unknown.
    fn bordered(&self) -> bool;
    /// Whether [`AugOperator::precondition`] applies a right preconditioner.
    fn preconditioned(&self) -> bool {
        false
    }
    /// `y = M (x_v, x_s)`, `M` an approximate inverse of `A`.
    fn precondition(
        &mut self,
        _backend: &mut B,
        _x_v: &B::Vector,
        _x_s: f64,
        _y: &mut AugVec<B::Vector>,
    ) {
    }
}

/// Outcome of one GMRES solve.
#[derive(Debug, Clone, Copy)]
pub struct GmresOutcome {
    /// Whether `|b - A x| <= tol |b|` was reached.
    pub converged: bool,
    /// Whether the solve stopped on its own terms: converged, or reduced
    /// its starting residual by the requested `reduction` (an inexact
    /// Newton step), rather than running out of matvecs.
    pub reached: bool,
    /// Whether the observer stopped the solve ([`Observer::cancelled`]);
    /// `x` is then a partial update.
    pub cancelled: bool,
    /// The true residual at the end over the one at the start (0 for a
    /// zero right-hand side, NaN when cancelled).
    pub reduction: f64,
}

/// Work space for [`gmres`]: `restart + 1` basis vectors and scratch.
pub struct GmresWork<V> {
    basis: Vec<V>,
    basis_s: Vec<f64>,
    w: AugVec<V>,
    /// `M v_j` under right preconditioning.
    z: AugVec<V>,
    h: Vec<f64>,
}

impl<V> GmresWork<V> {
    /// Work space for vectors of `len` entries.
    pub fn new<B: Backend<Vector = V>>(backend: &mut B, restart: usize, len: usize) -> Self {
        let restart = restart.max(1);
        Self {
            basis: (0..=restart).map(|_| backend.zeros(len)).collect(),
            basis_s: vec![0.0; restart + 1],
            w: AugVec {
                v: backend.zeros(len),
                s: 0.0,
            },
            z: AugVec {
                v: backend.zeros(len),
                s: 0.0,
            },
            h: vec![0.0; (restart + 1) * restart],
        }
    }

    /// Re-size every vector to `len` entries (storage is kept).
    pub fn resize<B: Backend<Vector = V>>(&mut self, backend: &mut B, len: usize) {
        for v in &mut self.basis {
            backend.resize(v, len);
        }
        backend.resize(&mut self.w.v, len);
        backend.resize(&mut self.z.v, len);
    }
}

/// Solve `A x = rhs` to `|r| <= tol |rhs|`, starting from `x`, with at most
/// `max_matvecs` applications of `A`; stop early once the residual is
/// `reduction` times the starting one (`0`: never), as an inexact Newton
/// step asks (the outcome is then not `converged` unless `tol` holds too).
/// `observer` is polled before every application of `A`
/// ([`Observer::cancelled`]).
#[allow(clippy::too_many_arguments)]
pub fn gmres<B: Backend, A: AugOperator<B>>(
    backend: &mut B,
    op: &mut A,
    rhs: &AugVec<B::Vector>,
    x: &mut AugVec<B::Vector>,
    work: &mut GmresWork<B::Vector>,
    tol: f64,
    reduction: f64,
    max_matvecs: usize,
    observer: &mut dyn Observer,
) -> GmresOutcome {
    let bordered = op.bordered();
    let m = work.basis.len() - 1;
    let sq = |s: f64| if bordered { s * s } else { 0.0 };
    let bnorm = (backend.dot(&rhs.v, &rhs.v) + sq(rhs.s)).sqrt();
    let mut matvecs = 0;
    if bnorm == 0.0 {
        backend.scale(0.0, &mut x.v);
        x.s = 0.0;
        return GmresOutcome {
            converged: true,
            reached: true,
            cancelled: false,
            reduction: 0.0,
        };
    }
    let mut cs = vec![0.0; m];
    let mut sn = vec![0.0; m];
    let mut gvec = vec![0.0; m + 1];
    let mut y = vec![0.0; m];
    let mut hcol = vec![0.0; m + 1];
    let mut dots = vec![0.0; m + 1];
    let mut neg = vec![0.0; m + 1];
    let mut beta0 = f64::NAN;
    let stopped = GmresOutcome {
        converged: false,
        reached: false,
        cancelled: true,
        reduction: f64::NAN,
    };
    loop {
        if observer.cancelled() {
            return stopped;
        }
        // r0 = rhs - A x, stored in basis[0] (the operator writes into w),
        // with the exact product: in mixed precision each restart is a step
        // of iterative refinement (GMRES-IR, physics.md section 13), the
        // cycle a correction computed with the f32 products.
        op.apply_exact(backend, &x.v, x.s, &mut work.w);
        matvecs += 1;
        backend.copy(&rhs.v, &mut work.basis[0]);
        backend.axpy(-1.0, &work.w.v, &mut work.basis[0]);
        work.basis_s[0] = if bordered { rhs.s - work.w.s } else { 0.0 };
        let beta = (backend.dot(&work.basis[0], &work.basis[0]) + sq(work.basis_s[0])).sqrt();
        let rel = beta / bnorm;
        if beta0.is_nan() {
            beta0 = beta;
        }
        let reduced = beta <= reduction * beta0;
        if rel <= tol || reduced || matvecs >= max_matvecs {
            return GmresOutcome {
                converged: rel <= tol,
                reached: rel <= tol || reduced,
                cancelled: false,
                reduction: beta / beta0,
            };
        }
        backend.scale(1.0 / beta, &mut work.basis[0]);
        work.basis_s[0] /= beta;
        gvec.fill(0.0);
        gvec[0] = beta;
        let mut k_done = 0;
        let preconditioned = op.preconditioned();
        for j in 0..m {
            if observer.cancelled() {
                return stopped;
            }
            if preconditioned {
                op.precondition(backend, &work.basis[j], work.basis_s[j], &mut work.z);
                op.apply(backend, &work.z.v, work.z.s, &mut work.w);
            } else {
                op.apply(backend, &work.basis[j], work.basis_s[j], &mut work.w);
            }
            matvecs += 1;
            // CGS2: classical Gram-Schmidt twice, each pass one batched
            // reduction and one fused update.
            hcol.fill(0.0);
            for _pass in 0..2 {
                backend.dots(&work.basis[..=j], &work.w.v, &mut dots[..=j]);
                for k in 0..=j {
                    dots[k] += sq(1.0) * work.basis_s[k] * work.w.s;
                    hcol[k] += dots[k];
                    neg[k] = -dots[k];
                }
                backend.combine(&neg[..=j], &work.basis[..=j], &mut work.w.v);
                if bordered {
                    work.w.s += neg[..=j]
                        .iter()
                        .zip(&work.basis_s)
                        .map(|(a, b)| a * b)
                        .sum::<f64>();
                }
            }
            let hn = (backend.dot(&work.w.v, &work.w.v) + sq(work.w.s)).sqrt();
            hcol[j + 1] = hn;
            for k in 0..j {
                let t = cs[k] * hcol[k] + sn[k] * hcol[k + 1];
                hcol[k + 1] = -sn[k] * hcol[k] + cs[k] * hcol[k + 1];
                hcol[k] = t;
            }
            let (a, b) = (hcol[j], hcol[j + 1]);
            let r = a.hypot(b);
            let (c, s) = if r == 0.0 { (1.0, 0.0) } else { (a / r, b / r) };
            cs[j] = c;
            sn[j] = s;
            hcol[j] = r;
            gvec[j + 1] = -s * gvec[j];
            gvec[j] *= c;
            for (k, hk) in hcol[..=j].iter().enumerate() {
                work.h[k * m + j] = *hk;
            }
            k_done = j + 1;
            let rel = gvec[j + 1].abs() / bnorm;
            let breakdown = hn <= f64::MIN_POSITIVE * 1e10;
            if !breakdown {
                backend.copy(&work.w.v, &mut work.basis[j + 1]);
                backend.scale(1.0 / hn, &mut work.basis[j + 1]);
                work.basis_s[j + 1] = work.w.s / hn;
            }
            let reduced = gvec[j + 1].abs() <= reduction * beta0;
            if rel <= tol || reduced || breakdown || matvecs >= max_matvecs {
                break;
            }
        }
        // Back substitution and update of x.
        for i in (0..k_done).rev() {
            let acc = gvec[i]
                - (i + 1..k_done)
                    .map(|k| work.h[i * m + k] * y[k])
                    .sum::<f64>();
            let d = work.h[i * m + i];
            y[i] = if d != 0.0 { acc / d } else { 0.0 };
        }
        let ys = if bordered {
            y[..k_done]
                .iter()
                .zip(&work.basis_s)
                .map(|(a, b)| a * b)
                .sum::<f64>()
        } else {
            0.0
        };
        if preconditioned {
            // x += M (V y): the combination in z, its image in w.
            backend.scale(0.0, &mut work.z.v);
            backend.combine(&y[..k_done], &work.basis[..k_done], &mut work.z.v);
            work.z.s = ys;
            op.precondition(backend, &work.z.v, work.z.s, &mut work.w);
            backend.axpy(1.0, &work.w.v, &mut x.v);
            x.s += work.w.s;
        } else {
            backend.combine(&y[..k_done], &work.basis[..k_done], &mut x.v);
            x.s += ys;
        }
    }
}
