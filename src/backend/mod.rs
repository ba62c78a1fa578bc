//! Executors: the CPU reference path and the GPU (wgpu) path. The contact
//! iteration ([`crate::solver`]) is written once against [`Backend`]; each
//! executor supplies storage and a handful of fused kernels.

pub mod cpu;
pub mod gpu;

pub use cpu::CpuBackend;

/// Storage and kernels the constrained iteration needs. Vectors are either
/// grid vectors (length `nx ny`, C order) or short vectors over the current
/// contact set, addressed through an [`Backend::Index`]. Scalars come back to
/// the host; all vectors may stay on the device.
pub trait Backend {
    type Vector;
    /// Positions of the cells of a contact set.
    type Index;
    /// Which grid cells are in the contact set (one flag per cell).
    type Mask;

    /// Executor name for reports (e.g. `cpu (2 threads)` or the adapter).
    fn name(&self) -> String;
    /// Length of a grid vector.
    fn grid_len(&self) -> usize;
    /// Relative rounding unit of the vector arithmetic (`f64::EPSILON` for
    /// f64 storage, `f32::EPSILON` for f32); the solver clamps its
    /// tolerances to a small multiple of it.
    fn epsilon(&self) -> f64 {
        f64::EPSILON
    }
    /// Whether `count` more vectors of `len` entries fit in the memory the
    /// vectors live in; an error names what does not fit. Default: yes (a
    /// device's vectors come from its fixed pool).
    fn reserve(&mut self, count: usize, len: usize) -> Result<(), String> {
        let _ = (count, len);
        Ok(())
    }
    /// A new zero vector of `len` entries.
    fn zeros(&mut self, len: usize) -> Self::Vector;
    /// Change the length of `v` to `len` (contents unspecified).
    fn resize(&mut self, v: &mut Self::Vector, len: usize);
    /// Host -> vector (lengths equal).
    fn upload(&mut self, host: &[f64], dst: &mut Self::Vector);
    /// A vector holding `host`, which is consumed (an executor whose
    /// vectors live on the host keeps the allocation: no copy).
    fn adopt(&mut self, host: Vec<f64>) -> Self::Vector {
        let mut v = self.zeros(host.len());
        self.upload(&host, &mut v);
        v
    }
    /// A grid vector's values on the host, the vector consumed.
    fn take_host(&mut self, v: Self::Vector) -> Vec<f64> {
        let mut host = vec![0.0; self.grid_len()];
        self.download(&v, &mut host);
        host
    }
    /// The mask of the cells where `host > 0.5` (one value per grid cell).
    fn mask_from(&mut self, host: &[f64]) -> Self::Mask;
    /// Vector -> host (lengths equal).
    fn download(&mut self, src: &Self::Vector, host: &mut [f64]);
    /// `dst = src`.
    fn copy(&mut self, src: &Self::Vector, dst: &mut Self::Vector);
    /// `y = L x` on grid vectors, the influence operator (paper Eq. 7), to
    /// the rounding of the vectors ([`Backend::epsilon`]).
    fn apply(&mut self, x: &Self::Vector, y: &mut Self::Vector);
    /// Whether the Krylov products ([`Backend::apply_set`]) and the
    /// preconditioner run in a lower precision than [`Backend::apply`]
    /// (mixed precision, physics.md section 13): the solver then computes
    /// the residual of every GMRES restart with [`Backend::apply`]
    /// (iterative refinement). Default: no.
    fn refines(&self) -> bool {
        false
    }
    /// `y = (L x)[index]` for `x` on the contact set `index` (zero off
    /// it): the operator's rows on a contact set, in the working precision
    /// of the Krylov solves ([`Backend::refines`]). Short vectors in, short
    /// vectors out: whether grid-size work vectors are needed is the
    /// executor's business (the CPU's FFT operators need none).
    fn apply_set(&mut self, index: &Self::Index, x: &Self::Vector, y: &mut Self::Vector);
    /// [`Backend::apply_set`] to the rounding of [`Backend::apply`] (the
    /// residuals of iterative refinement).
    fn apply_set_exact(&mut self, index: &Self::Index, x: &Self::Vector, y: &mut Self::Vector);
    /// `y = (K x)[index]` for `x` on the set ([`Backend::precondition`]).
    fn precondition_set(&mut self, index: &Self::Index, x: &Self::Vector, y: &mut Self::Vector);
    /// Whether [`Backend::precondition`] applies an approximate inverse of
    /// the operator (default: no; the iteration then runs unpreconditioned).
    fn has_preconditioner(&self) -> bool {
        false
    }
    /// The fraction of the grid's cells in the contact set of the next inner
    /// solve, for a backend with more than one approximate inverse to pick
    /// from ([`crate::operator::GridOperator::set_contact_fraction`];
    /// default: nothing to pick).
    fn set_contact_fraction(&mut self, _fraction: f64) {}
    /// `y = K x` on grid vectors, `K` an approximate inverse of `L` (the
    /// stiffness); only called when [`Backend::has_preconditioner`].
    fn precondition(&mut self, x: &Self::Vector, y: &mut Self::Vector) {
        self.copy(x, y);
    }
    /// `a . b`.
    fn dot(&mut self, a: &Self::Vector, b: &Self::Vector) -> f64;
    /// `out[k] = basis[k] . w` for every `k` (one batched reduction).
    fn dots(&mut self, basis: &[Self::Vector], w: &Self::Vector, out: &mut [f64]);
    /// `y += alpha x`.
    fn axpy(&mut self, alpha: f64, x: &Self::Vector, y: &mut Self::Vector);
    /// `y += sum_k coeffs[k] basis[k]`.
    fn combine(&mut self, coeffs: &[f64], basis: &[Self::Vector], y: &mut Self::Vector);
    /// `x *= alpha`.
    fn scale(&mut self, alpha: f64, x: &mut Self::Vector);
    /// `x[i] += alpha` for every entry.
    fn add_scalar(&mut self, alpha: f64, x: &mut Self::Vector);
    /// `sum x`.
    fn sum(&mut self, x: &Self::Vector) -> f64;
    /// The cells of a mask.
    fn index_of(&mut self, mask: &Self::Mask) -> Self::Index;
    /// Number of cells in an index.
    fn index_len(&self, index: &Self::Index) -> usize;
    /// `short[k] = full[index[k]]`.
    fn gather(&mut self, index: &Self::Index, full: &Self::Vector, short: &mut Self::Vector);
    /// `full = 0` except `full[index[k]] = short[k]`.
    fn scatter(&mut self, index: &Self::Index, short: &Self::Vector, full: &mut Self::Vector);
    /// `out = g - delta + u`: the gap of physics.md section 1.
    fn gap(&mut self, g: &Self::Vector, u: &Self::Vector, delta: f64, out: &mut Self::Vector);
    /// [`Backend::gap`] in place: `x = g - delta + x` (the displacement
    /// `x` becomes the gap; the iteration keeps no displacement vector).
    fn to_gap(&mut self, g: &Self::Vector, delta: f64, x: &mut Self::Vector) {
        self.axpy(1.0, g, x);
        self.add_scalar(-delta, x);
    }
    /// Primal-dual active-set update on grid vectors: a cell in the set
    /// stays iff `p > 0`, a cell outside joins iff `gap < 0`. Returns
    /// `(changes, size of the new set)`.
    fn update_active_set(
        &mut self,
        p: &Self::Vector,
        gap: &Self::Vector,
        mask: &mut Self::Mask,
    ) -> (usize, usize);
    /// The set of the semismooth Newton rule `{p > k gap}` for every cell,
    /// whichever side it was on (the update after a damped step,
    /// [`crate::solver`]'s line search). Returns as
    /// [`Backend::update_active_set`].
    fn newton_set(
        &mut self,
        p: &Self::Vector,
        gap: &Self::Vector,
        stiffness: f64,
        mask: &mut Self::Mask,
    ) -> (usize, usize);
    /// `(sum min(p, k gap)^2, sum p^2)`: the complementarity residual of the
    /// LCP with `k` converting a gap into a pressure.
    fn complementarity(
        &mut self,
        p: &Self::Vector,
        gap: &Self::Vector,
        stiffness: f64,
    ) -> (f64, f64);
}

use serde::{Deserialize, Serialize};

/// Which executor runs a computation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum BackendChoice {
    /// The GPU when an adapter exists, otherwise the CPU (with a notice).
    #[default]
    Auto,
    /// The GPU; an error when no adapter exists.
    Gpu,
    /// The CPU reference path.
    Cpu,
}

/// Environment variable that selects the backend when no flag is given.
pub const BACKEND_ENV: &str = "VISCOSLIDE_BACKEND";

impl std::str::FromStr for BackendChoice {
    type Err = String;

    /// `auto`, `gpu` or `cpu` (any case).
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(BackendChoice::Auto),
            "gpu" => Ok(BackendChoice::Gpu),
            "cpu" => Ok(BackendChoice::Cpu),
            other => Err(format!("{other}: expected auto, gpu or cpu")),
        }
    }
}

impl BackendChoice {
    /// The flag if given, else `VISCOSLIDE_BACKEND`, else `auto`.
    pub fn resolve(flag: Option<BackendChoice>) -> Result<BackendChoice, String> {
        if let Some(f) = flag {
            return Ok(f);
        }
        match std::env::var(BACKEND_ENV) {
            Ok(v) if v.trim().is_empty() => Ok(BackendChoice::Auto),
            Ok(v) => v.parse().map_err(|e| format!("{BACKEND_ENV}={e}")),
            Err(_) => Ok(BackendChoice::Auto),
        }
    }
}
