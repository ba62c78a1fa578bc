//! The row march of the coefficient tables ([`super::table`]; physics.md
//! section 3, "Discretisation").
//!
//! Sliding direction along a grid axis (and no layer thinner than the
//! kernel's thin limit: half a cell for the cell integrals of Eq. 5, four
//! cells for the paper's collocation): along each row `y = j a` parallel to `e_v`, the memory part
//! of Eq. 4 is a one-dimensional correlation. Per creep term,
//! `G_k(x) = int_0^inf lambda_k e^{-lambda_k s} g(x + s) ds` (with `g = Theta L`,
//! or its transverse cell average for the derivative table) obeys
//!
//! `G_k(x) = e^{-lambda_k a} G_k(x + a) + int_0^a lambda_k e^{-lambda_k s} g(x + s) ds`,
//!
//! so each row is marched backwards from its far `+e_v` end, where the start
//! value is the tail integral. Terms are grouped by `lambda_k a`:
//! * `l_k < 1e-13 a`: relaxed compliance, `C_k g(x)`;
//! * `lambda_k a <= 2` (shared): panel integrals by 8-point Gauss-Legendre
//!   on the cell, node values of `g` shared by all terms;
//! * `2 < lambda_k a <= 200` (mid): per-term 8-point Gauss rule for the
//!   weight `lambda_k e^{-lambda_k s}` on `[0, a]` (Stieltjes + Golub-Welsch);
//! * `lambda_k a > 200` (peaked): no march; all such terms together through
//!   one 10-point Gauss rule for `sum_k (C_k/l_k) e^{-s/l_k}` on `[0, a/4]`
//!   (the mass beyond `a/4` is below `e^{-50}`);
//! * `l_k = inf` or beyond `1e18` times the grid: glassy (no memory).
//!
//! Beyond 20 cells from the source every marched term (shared ones too when
//! there are at most two) and the peaked group switch to 4-point Gauss rules
//! for their own weights: `g` is then analytic in a Bernstein ellipse of
//! parameter ~80 around the panel, and the weight's exponential is built
//! into the rule, so 4 nodes leave ~1e-16.
//!
//! Panels closer than 2.5 cells to the source (where `g` has kinks or nearby
//! singularities) are integrated per term by adaptive Gauss-Kronrod, the
//! start values by a shared geometric-panel rule (ratio `sqrt 2`, 10 nodes)
//! or, next to the source, adaptively; targets within three cells of the
//! source are evaluated by the per-offset path. Elsewhere the nearest
//! singularity of `g` is at least 2.5 cells from a one-cell panel, so the
//! 8-point rules converge to round-off. Rows are independent (rayon) and the
//! table is mirror-symmetric in the transverse offset by construction.
//!
//! On a layer with the cell integrals of Eq. 5 ([`super::cell`]), `g` is
//! Love's `L` plus a part analytic within `2h` of the row, so the 8-point
//! rules keep ~1e-10 down to `h = a/2`; the 4-point far rules are used only
//! for `h >= 4a` (Bernstein parameter >= 32), and rows or targets beyond
//! the reach of `Theta` are zero without evaluation. Measured agreement
//! with the per-offset path: ~1e-11 of the self coefficient for `h` from
//! one to five cells (tests/kernel/layer_cells.rs).

use rayon::prelude::*;

use super::line::{memory_breaks, GLASSY, RELAXED};
use super::progress::Progress;
use super::quad::{adaptive, clean_breaks, gauss_from_samples, gauss_legendre_unit};
use super::{Axis, SlidingKernel};

/// Panels at least this many cells from the source use [`FAR_NODES`]-point
/// rules: the nearest singularity of `g` is then beyond a Bernstein ellipse
/// of parameter ~80 around a one-cell panel, so 4 nodes (exact for degree 7)
/// leave ~80^-8 ~ 6e-16.
const FAR_CELLS: f64 = 20.0;
const FAR_NODES: usize = 4;

/// Shared pieces of the row march for one kernel and cell size.
struct Plan {
    /// Cell side along the sliding axis: the panel length.
    a: f64,
    /// Cell side across the sliding axis: the spacing of the rows.
    across: f64,
    /// Whether the 4-point far rules are accurate (no layer, or one at
    /// least four cells thick: `g` analytic within `2h >= 8a` of the row).
    far_ok: bool,
    glassy_plus_relaxed: f64,
    /// Shared class: `(C_k, E_k = e^{-lambda a})` and weights on the GL nodes.
    shared: Vec<(f64, f64)>,
    shared_w: Vec<Vec<f64>>,
    gl_t: Vec<f64>,
    /// Mid class: `(C_k, E_k)`, per-term Gauss nodes (fractions of `a`) and weights.
    mid: Vec<(f64, f64)>,
    mid_rule: Vec<(Vec<f64>, Vec<f64>)>,
    /// All marched terms as `(C_k, lambda_k)` (shared then mid).
    marched: Vec<(f64, f64)>,
    /// Peaked class: combined rule, nodes in fractions of `a`, weights incl. `C_k`.
    peaked: Option<(Vec<f64>, Vec<f64>)>,
    /// Far from the source: 4-point Gauss rules per marched term (weight
    /// `lambda_k e^{-lambda_k s}` on the cell, nodes in fractions of `a`) and
    /// for the peaked group.
    far_rule: Vec<(Vec<f64>, Vec<f64>)>,
    peaked_far: Option<(Vec<f64>, Vec<f64>)>,
    /// Tail rule: offsets `s` \[m\] and per-marched-term weights.
    tail_s: Vec<f64>,
    tail_w: Vec<Vec<f64>>,
}

fn fine_geometric(lo: f64, hi: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    // Fine GL rule on [0, hi] graded geometrically (ratio 2) down to `lo`.
    let (gx, gw) = gauss_legendre_unit(n);
    let mut edges = vec![0.0];
    let mut e = lo;
    while e < hi {
        edges.push(e);
        e *= 2.0;
    }
    edges.push(hi);
    let mut xs = vec![];
    let mut ws = vec![];
    for p in edges.windows(2) {
        for (t, w) in gx.iter().zip(&gw) {
            xs.push(p[0] + (p[1] - p[0]) * t);
            ws.push(w * (p[1] - p[0]));
        }
    }
    (xs, ws)
}

impl Plan {
    fn new(k: &SlidingKernel, (a, across): (f64, f64), extent: f64) -> Self {
        let (gl_t, gl_w) = gauss_legendre_unit(8);
        let far_ok = k
            .theta()
            .is_none_or(|t| t.layer.thickness >= 4.0 * a.max(across));
        let mut plan = Plan {
            a,
            across,
            far_ok,
            glassy_plus_relaxed: k.glassy,
            shared: vec![],
            shared_w: vec![],
            gl_t: gl_t.clone(),
            mid: vec![],
            mid_rule: vec![],
            marched: vec![],
            peaked: None,
            far_rule: vec![],
            peaked_far: None,
            tail_s: vec![],
            tail_w: vec![],
        };
        let mut peaked_terms = vec![];
        let mut mid_marched = vec![];
        for &(c, l) in &k.terms {
            if c == 0.0 {
                continue;
            }
            if l < RELAXED * a {
                plan.glassy_plus_relaxed += c;
                continue;
            }
            if !l.is_finite() || l > GLASSY * (extent + a) {
                continue;
            }
            let la = a / l;
            if la <= 2.0 {
                plan.shared.push((c, (-la).exp()));
                plan.shared_w.push(
                    gl_t.iter()
                        .zip(&gl_w)
                        .map(|(t, w)| la * (-la * t).exp() * w)
                        .collect(),
                );
                plan.marched.push((c, 1.0 / l));
            } else if la <= 200.0 {
                plan.mid.push((c, (-la).exp()));
                mid_marched.push((c, 1.0 / l));
                let (xs, ws) = fine_geometric(1.0 / (16.0 * la), 1.0, 20);
                let wts: Vec<f64> = xs
                    .iter()
                    .zip(&ws)
                    .map(|(t, w)| w * la * (-la * t).exp())
                    .collect();
                plan.mid_rule.push(gauss_from_samples(&xs, &wts, 8));
            } else {
                peaked_terms.push((c, l / a));
            }
        }
        plan.marched.extend(mid_marched);
        if !peaked_terms.is_empty() {
            let lmin = peaked_terms
                .iter()
                .map(|t| t.1)
                .fold(f64::INFINITY, f64::min);
            let (xs, ws) = fine_geometric(lmin / 16.0, 0.25, 20);
            let wts: Vec<f64> = xs
                .iter()
                .zip(&ws)
                .map(|(t, w)| {
                    w * peaked_terms
                        .iter()
                        .map(|&(c, l)| c / l * (-t / l).exp())
                        .sum::<f64>()
                })
                .collect();
            plan.peaked = Some(gauss_from_samples(&xs, &wts, 10));
            plan.peaked_far = Some(gauss_from_samples(&xs, &wts, FAR_NODES));
        }
        plan.far_rule = plan
            .marched
            .iter()
            .map(|&(_, lam)| {
                let la = lam * a;
                let (xs, ws) = fine_geometric((1.0 / (16.0 * la)).min(1.0 / 16.0), 1.0, 20);
                let wts: Vec<f64> = xs
                    .iter()
                    .zip(&ws)
                    .map(|(t, w)| w * la * (-la * t).exp())
                    .collect();
                gauss_from_samples(&xs, &wts, FAR_NODES)
            })
            .collect();
        if !plan.marched.is_empty() {
            let lmax = plan.marched.iter().map(|t| 1.0 / t.1).fold(0.0, f64::max);
            let s_hi = 46.0 * lmax.max(a);
            let (gx, gw) = gauss_legendre_unit(10);
            let mut edges = vec![0.0];
            let mut e = a / 1024.0;
            let r = std::f64::consts::SQRT_2;
            while e < s_hi {
                edges.push(e);
                e *= r;
            }
            edges.push(s_hi);
            let mut ws = vec![];
            for p in edges.windows(2) {
                for (t, w) in gx.iter().zip(&gw) {
                    plan.tail_s.push(p[0] + (p[1] - p[0]) * t);
                    ws.push(w * (p[1] - p[0]));
                }
            }
            plan.tail_w = plan
                .marched
                .iter()
                .map(|&(_, lam)| {
                    plan.tail_s
                        .iter()
                        .zip(&ws)
                        .map(|(s, w)| w * lam * (-lam * s).exp())
                        .collect()
                })
                .collect();
        }
        plan
    }
}

/// Canonical table for sliding along `+x` on cells of side `aa` along and
/// `at` across (`cell = (aa, at)`; physics.md section 11: the sliding line
/// integral shifts the along coordinate only): `(2na-1) x (2nt-1)` values
/// of `K` (or of `D_x` when `derivative`), row-major in the along index.
///
/// With `shift`, the targets are the cell vertices instead: offsets
/// `((i + 1/2) aa, (j + 1/2) at)` for `i in -na..na`, `j in -nt..nt`, a
/// `2na x 2nt` table (values of `K` only).
#[allow(clippy::too_many_arguments)]
pub(super) fn canonical(
    k: &SlidingKernel,
    na: usize,
    nt: usize,
    (a, at): (f64, f64),
    derivative: bool,
    slide_axis: Axis,
    sign: f64,
    shift: bool,
) -> Vec<f64> {
    debug_assert!(!(shift && derivative));
    // The source cell in canonical (along, across) coordinates, and in the
    // grid's own for the near block.
    let cell = k.cell(a, at);
    let grid_cell = match slide_axis {
        Axis::X => k.cell(a, at),
        Axis::Y => k.cell(at, a),
    };
    let extent = ((na as f64 + 1.0) * a).hypot((nt as f64 + 1.0) * at);
    let plan = Plan::new(k, (a, at), extent);
    let h = if shift { 0.5 } else { 0.0 };
    let (wt, wa) = if shift {
        (2 * nt, 2 * na)
    } else {
        (2 * nt - 1, 2 * na - 1)
    };
    // Across-row index of the offset `(j + h) a` and of its mirror image.
    let row_index = |j: usize| -> (usize, usize) {
        if shift {
            (nt + j, nt - 1 - j)
        } else {
            (nt - 1 + j, nt - 1 - j)
        }
    };
    // Rows j >= 0, mirrored afterwards.
    let progress = Progress::new(
        if derivative {
            "friction-stencil table"
        } else {
            "influence-coefficient table"
        },
        nt as u64,
    );
    let rows: Vec<Vec<f64>> = (0..nt)
        .into_par_iter()
        .map(|j| {
            let y = (j as f64 + h) * at;
            // Rows beyond the reach of Theta (trail included) vanish.
            let gy = if derivative { 0.5 * at } else { 0.0 };
            let zero = cell
                .layer
                .as_ref()
                .is_some_and(|lc| lc.beyond(0.0, y, f64::INFINITY, gy));
            let row = if zero {
                vec![0.0; wa]
            } else if derivative {
                let g = |x: f64| k.transverse_average(&cell, x, y, Axis::X);
                let x0 = -(na as f64 - 0.5) * a;
                let kb = march_row(k, &plan, &g, x0, 2 * na, y, true);
                (0..wa).map(|i| (kb[i + 1] - kb[i]) / a).collect()
            } else {
                let f = k.spatial(&cell);
                let g = |x: f64| f(x, y);
                let x0 = -(na as f64 - 1.0 + h) * a;
                march_row(k, &plan, &g, x0, wa, y, false)
            };
            progress.inc();
            row
        })
        .collect();
    progress.finish();
    let mut out = vec![0.0; wa * wt];
    for (j, row) in rows.iter().enumerate() {
        let (up, down) = row_index(j);
        for (i, v) in row.iter().enumerate() {
            out[i * wt + up] = *v;
            out[i * wt + down] = *v;
        }
    }
    // Near block: per-offset evaluation of the targets within three cells
    // of the larger side of the source.
    let span = |side: f64| (3.0 * a.max(at) / side).ceil() as isize;
    let (m, mt) = (span(a), span(at));
    let lo = if shift { -m - 1 } else { -m };
    let first = if shift { na as isize } else { na as isize - 1 };
    for di in lo..=m {
        for dj in 0..=mt {
            if (di + first) < 0 || (di + first) as usize >= wa || dj as usize >= nt {
                continue;
            }
            // Physical offset of the canonical (along, across) offset.
            let (along, across) = (sign * (di as f64 + h) * a, (dj as f64 + h) * at);
            let (x, y) = match slide_axis {
                Axis::X => (along, across),
                Axis::Y => (across, along),
            };
            let v = if derivative {
                sign * k.derivative_with(&grid_cell, x, y, slide_axis)
            } else {
                k.coefficient_with(&grid_cell, x, y).total()
            };
            let i = (di + first) as usize;
            let (up, down) = row_index(dj as usize);
            out[i * wt + up] = v;
            out[i * wt + down] = v;
        }
    }
    out
}

/// Distance from the segment `[x0, x1] x {y}` to the rectangle
/// `[-hx, hx] x [-hy, hy]`.
fn seg_rect_dist(x0: f64, x1: f64, y: f64, hx: f64, hy: f64) -> f64 {
    let gx = if x1 < -hx {
        -hx - x1
    } else if x0 > hx {
        x0 - hx
    } else {
        0.0
    };
    let gy = (y.abs() - hy).max(0.0);
    gx.hypot(gy)
}

/// Values of `Kbar` (or `K`) / prefactor at the targets `x0 + m a`,
/// `m = 0..count`, on the row `y`, times the prefactor.
fn march_row(
    k: &SlidingKernel,
    plan: &Plan,
    g: &impl Fn(f64) -> f64,
    x0: f64,
    count: usize,
    y: f64,
    averaged: bool,
) -> Vec<f64> {
    let a = plan.a;
    let hx = 0.5 * a;
    let hy = if averaged {
        plan.across
    } else {
        0.5 * plan.across
    };
    let near = |xa: f64, xb: f64| seg_rect_dist(xa, xb, y, hx, hy) < 2.5 * a;
    let far = |xa: f64, xb: f64| plan.far_ok && seg_rect_dist(xa, xb, y, hx, hy) >= FAR_CELLS * a;
    let mut out = vec![0.0; count];
    let nm = plan.marched.len();
    let ns = plan.shared.len();
    let mut state = vec![0.0; nm];
    let tol = if averaged {
        k.average_tol((a, plan.across))
    } else {
        k.tol()
    };
    let adaptive_panel = |x: f64, lam: f64, len: f64| -> f64 {
        let l = 1.0 / lam;
        let mut br = vec![-hx - x, hx - x, -x];
        let hi = if len.is_infinite() {
            46.0 * l.max(a)
        } else {
            len
        };
        // The geometric grid only for the tail to infinity.
        let smallest = if len.is_infinite() {
            l.min(a)
        } else {
            8.0 * hi
        };
        memory_breaks(&mut br, &[l], smallest, hi);
        let br = clean_breaks(br, 0.0, hi);
        let scale = g(x).abs() + g(x + a).abs();
        adaptive(
            |s| lam * (-lam * s).exp() * g(x + s),
            &br,
            0.1 * tol * scale,
            0.1 * tol,
            2000,
        )
    };
    let mut fv = vec![0.0; plan.gl_t.len()];
    for m in (0..count).rev() {
        let x = x0 + m as f64 * a;
        let gx = g(x);
        if nm > 0 {
            if m == count - 1 {
                if near(x, f64::INFINITY) {
                    for (t, st) in state.iter_mut().enumerate() {
                        *st = adaptive_panel(x, plan.marched[t].1, f64::INFINITY);
                    }
                } else {
                    let tv: Vec<f64> = plan.tail_s.iter().map(|s| g(x + s)).collect();
                    for (t, st) in state.iter_mut().enumerate() {
                        *st = plan.tail_w[t].iter().zip(&tv).map(|(w, v)| w * v).sum();
                    }
                }
            } else if near(x, x + a) {
                for (t, st) in state.iter_mut().enumerate() {
                    let e = if t < ns {
                        plan.shared[t].1
                    } else {
                        plan.mid[t - ns].1
                    };
                    *st = e * *st + adaptive_panel(x, plan.marched[t].1, a);
                }
            } else if far(x, x + a) {
                // Per-term 4-point rules (shared terms too when there are at
                // most two of them: 4 ns <= 8 evaluations).
                let per_term_shared = ns <= 2;
                if !per_term_shared {
                    for (q, v) in fv.iter_mut().enumerate() {
                        *v = g(x + a * plan.gl_t[q]);
                    }
                }
                for (t, st) in state.iter_mut().enumerate() {
                    let p: f64 = if t < ns && !per_term_shared {
                        plan.shared_w[t].iter().zip(&fv).map(|(w, v)| w * v).sum()
                    } else {
                        let (nodes, wts) = &plan.far_rule[t];
                        nodes.iter().zip(wts).map(|(tq, w)| w * g(x + a * tq)).sum()
                    };
                    let e = if t < ns {
                        plan.shared[t].1
                    } else {
                        plan.mid[t - ns].1
                    };
                    *st = e * *st + p;
                }
            } else {
                for (q, v) in fv.iter_mut().enumerate() {
                    *v = g(x + a * plan.gl_t[q]);
                }
                for (t, st) in state.iter_mut().take(ns).enumerate() {
                    let p: f64 = plan.shared_w[t].iter().zip(&fv).map(|(w, v)| w * v).sum();
                    *st = plan.shared[t].1 * *st + p;
                }
                for (t, (nodes, wts)) in plan.mid_rule.iter().enumerate() {
                    let p: f64 = nodes.iter().zip(wts).map(|(tq, w)| w * g(x + a * tq)).sum();
                    state[ns + t] = plan.mid[t].1 * state[ns + t] + p;
                }
            }
        }
        let mut v = plan.glassy_plus_relaxed * gx;
        for (t, st) in state.iter().enumerate() {
            v += plan.marched[t].0 * st;
        }
        let peaked = if far(x, x + 0.25 * a) {
            &plan.peaked_far
        } else {
            &plan.peaked
        };
        if let Some((nodes, wts)) = peaked {
            v += nodes
                .iter()
                .zip(wts)
                .map(|(tq, w)| w * g(x + a * tq))
                .sum::<f64>();
        }
        out[m] = k.prefactor * v;
    }
    out
}
