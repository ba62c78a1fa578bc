//! What a user should know about the validity of a solution: results that
//! are computed but lie outside the model's range or the grid's resolution.
//! Each warning is one line that names the cause and what to change; they
//! are printed on the console and recorded in `summary.json` (`warnings`).

use crate::analysis::ContactStatistics;
use crate::config::Formulation;

use super::{Problem, ShortestWavelength};

/// Relative difference of the two friction routes above which a solution
/// warns.
pub(crate) const FRICTION_ROUTES_TOLERANCE: f64 = 0.02;

/// The rms slope beyond which the small-slope model is warned about.
pub(super) const RMS_SLOPE_LIMIT: f64 = 1.0;

/// Friction coefficients below this are zero to round-off.
pub(super) const FRICTION_ROUND_OFF: f64 = 1e-14;

/// A relative difference as a percentage, in scientific notation beyond
/// 1e4 % (a difference against a value near zero).
fn percent(diff: f64) -> String {
    let p = 100.0 * diff;
    if p < 1e4 {
        format!("{p:.1} %")
    } else {
        format!("{p:.2e} %")
    }
}

/// Cells per shortest surface wavelength below which a disagreement of
/// the friction routes is blamed on the surface's resolution (every solve
/// warns below [`super::MIN_CELLS_PER_WAVELENGTH`] in any case).
const CELLS_PER_WAVELENGTH: f64 = 8.0;

/// Cells across a layer's thickness below which the layer is
/// under-resolved.
const CELLS_PER_THICKNESS: f64 = 4.0;

/// Share of a map's points filled by harmonic interpolation above which a
/// solve warns: the filling is smooth (a harmonic function has no interior
/// extremum), so the roughness of the filled points is missing from the
/// contact, about that share of the map's.
const FILLED_SHARE_WARNING: f64 = 0.05;

/// Cells in contact below which the contact is warned to be at the grid's
/// resolution. A spot of a few cells is mostly its edge: on
/// `configs/default.toml` at 64^2 (8 scales, `v = 0.0117 m/s`) against the
/// same surface at 256^2, 33 cells in contact had the friction 16 % and the
/// area 20 % off, 5 cells 13 % and 33 %, one cell (any load below about
/// 3e-4 N) a friction that only follows the load; 118 cells were 2 % and
/// 7 % off.
const MIN_CONTACT_CELLS: usize = 16;

impl Problem {
    /// The warnings of a solution of this problem with contact statistics
    /// `stats` and the friction coefficients `mu` (Eq. 9) and `mu_d`
    /// (dissipation).
    pub(super) fn warnings(&self, stats: &ContactStatistics, mu: f64, mu_d: f64) -> Vec<String> {
        let mut out: Vec<String> = self.resolution_warning().into_iter().collect();
        out.extend(crate::surface::cell_aspect_warning(
            self.surface.cell_size,
            self.surface.cell_size_y,
        ));
        let (lx, ly) = (self.surface.length_x(), self.surface.length_y());
        let p0 = stats.normal_load / (lx * ly);
        let e0 = self.material.spectrum.relaxed_modulus();
        if p0 > e0 {
            out.push(format!(
                "the mean pressure {p0:.3e} Pa exceeds the relaxed modulus E0 = {e0:.3e} Pa: strains are not small and the linear small-strain model does not hold there; lower the load"
            ));
        }
        let cells = stats.contact_cells;
        if cells > 0 && cells < MIN_CONTACT_CELLS {
            out.push(format!(
                "the contact holds only {cells} cell{} of the {} x {} grid: spots of a few cells are mostly edge, so the contact area and the friction are set by the grid rather than the surface; raise the load or use more cells (check with `viscoslide refine`)",
                if cells == 1 { "" } else { "s" },
                self.surface.nx,
                self.surface.ny
            ));
        }
        out.extend(self.wrapped_map_warning());
        out.extend(self.periodic_map_as_pad_warning());
        out.extend(self.filled_warning());
        if let super::SurfaceSource::Generated(p) = &self.source {
            // The parameters made this surface: they are valid.
            out.extend(crate::surface::anisotropy_warning(p).ok().flatten());
        }
        out.extend(self.material.extrapolated_shift_warning());
        out.extend(self.extrapolated_frequencies_warning());
        // A layer thinner than one cell: in summary.json and Python's
        // warnings, not only on the command line's stderr.
        let coarser_side = self.surface.cell_size.max(self.surface.cell_size_y);
        out.extend(self.layer.and_then(|l| l.resolution_warning(coarser_side)));
        let (s, heights) = (&self.surface, &self.surface.heights);
        let slope = crate::surface::rms_slope_real(s.nx, s.ny, s.cell_size, s.cell_size_y, heights);
        if slope > RMS_SLOPE_LIMIT {
            out.push(format!(
                "the rms slope of the surface is {slope:.3e}, beyond {RMS_SLOPE_LIMIT}: the small-slope theory of the model (paper Eq. 1-4, surfaces nearly flat) does not hold there; lower rms_slope or check the heights' unit"
            ));
        }
        if self.material.spectrum.terms.is_empty() {
            out.push(format!(
                "the material has no creep or relaxation terms (an empty prony or creep_spectrum list): it is elastic with E = {:.4e} Pa at every speed, and its friction is zero",
                self.material.spectrum.relaxed_modulus()
            ));
        }
        let diff = if mu_d != 0.0 {
            (mu - mu_d).abs() / mu_d.abs()
        } else {
            (mu - mu_d).abs()
        };
        // Both zero to round-off (a speed far below the relaxation): no
        // friction to compare.
        let zero = mu.abs().max(mu_d.abs()) < FRICTION_ROUND_OFF;
        if diff > FRICTION_ROUTES_TOLERANCE && !zero {
            out.push(format!(
                "the two friction routes differ by {} (Eq. 9: {mu:.4e}, dissipation: {mu_d:.4e}); likely cause: {}",
                percent(diff),
                self.likely_causes().join("; ")
            ));
        }
        out
    }

    /// Why the friction routes may disagree, with what to change.
    fn likely_causes(&self) -> Vec<String> {
        let a = self.surface.cell_size;
        let lx = self.surface.length_x();
        let times = self.material.spectrum.terms.iter().map(|t| t.time);
        let longest = times.clone().fold(0.0, f64::max) * self.speed;
        let shortest = times.fold(f64::INFINITY, f64::min) * self.speed;
        let mut causes = Vec::new();
        if longest > lx {
            let room = match self.formulation {
                Formulation::NonPeriodic => "the pad",
                Formulation::Periodic => "the periodic cell",
            };
            causes.push(format!(
                "v tau = {longest:.3e} m is longer than {room} (L = {lx:.3e} m), so the solid under it never relaxes; lower the speed or use a longer map"
            ));
        }
        if shortest > 0.0 && shortest < a {
            causes.push(format!(
                "v tau = {shortest:.3e} m is shorter than a cell (a = {a:.3e} m), so the memory of the solid is not resolved; use more cells"
            ));
        }
        if let (Some(ShortestWavelength::UpperCutoff(_)), Some(cells)) = (
            self.shortest_wavelength(),
            self.cells_per_shortest_wavelength(),
        ) {
            if cells < CELLS_PER_WAVELENGTH {
                causes.push(format!(
                    "only {cells:.1} cells per shortest wavelength 2 pi / q1; use at least {CELLS_PER_WAVELENGTH} (more cells or fewer scales)"
                ));
            }
        }
        if let Some(layer) = &self.layer {
            let cells = layer.thickness / a;
            if cells < 1.0 {
                causes.push(format!(
                    "the layer (h = {:.3e} m) is thinner than a cell (h / a = {cells:.2e}): its response reaches wavenumbers of about 1/h, beyond the 3 alias images of each mode that the dissipation route sums, so that route misses part of it, high or low (Eq. 9's coefficients are the exact cell integrals); for agreement use at least {CELLS_PER_THICKNESS} cells per thickness (more cells)",
                    layer.thickness
                ));
            } else if cells < CELLS_PER_THICKNESS {
                causes.push(format!(
                    "the layer (h = {:.3e} m) is only {cells:.1} cells thick; use at least {CELLS_PER_THICKNESS} (more cells)",
                    layer.thickness
                ));
            }
        }
        if causes.is_empty() {
            causes.push("the grid may be too coarse for this speed; solve again with more cells and compare".into());
        }
        causes
    }
}

impl Problem {
    /// The frequencies the sliding excites, `v |q . e_v|` from the map's
    /// fundamental along the sliding to its shortest wavelength (the
    /// band's `q1`, or the grid's Nyquist wavenumber), against the
    /// frequencies of the data the material was fitted to
    /// ([`crate::material::Material::frequency_range`], at this
    /// temperature): a warning for each end more than a decade beyond
    /// them ([`crate::material::Material::extrapolated_frequencies_warnings`]).
    fn extrapolated_frequencies_warning(&self) -> Vec<String> {
        let v = self.speed;
        if self.material.frequency_range.is_none() || v <= 0.0 || !v.is_finite() {
            return Vec::new();
        }
        let (ex, ey) = crate::response::unit_direction(self.direction_rad);
        let (lx, ly) = (self.surface.length_x(), self.surface.length_y());
        let fundamental = [(ex, lx), (ey, ly)]
            .iter()
            .filter(|(e, _)| *e != 0.0)
            .map(|(e, l)| std::f64::consts::TAU * e.abs() / l)
            .fold(f64::INFINITY, f64::min);
        let shortest = self
            .shortest_wavelength()
            .map_or(2.0 * self.coarser_cell_side(), |w| w.length());
        let (w_lo, w_hi) = (v * fundamental, v * std::f64::consts::TAU / shortest);
        self.material.extrapolated_frequencies_warnings(w_lo, w_hi)
    }

    /// A map whose filled points ([`Problem::filled_points`]) are more
    /// than [`FILLED_SHARE_WARNING`] of it.
    fn filled_warning(&self) -> Option<String> {
        let total = self.surface.heights.len();
        let share = self.filled_points as f64 / total as f64;
        (share > FILLED_SHARE_WARNING).then(|| {
            format!(
                "{}: the filling is smooth, so the roughness of that part of the map is missing from the contact and the friction; crop the map to where it was measured",
                crate::surface::filled_note(self.filled_points, total).unwrap_or_default()
            )
        })
    }

    /// A map marked periodic solved as a finite pad because no formulation
    /// was given (the default, `"non_periodic"`): Python's
    /// `formulation="auto"` solves the same map with the periodic
    /// formulation, and the two answers differ (by 7.5 % in friction on a
    /// 32^2 map at 1 % contact). A formulation given in `[solver]` is a
    /// choice and not warned about.
    fn periodic_map_as_pad_warning(&self) -> Option<String> {
        let marked = self.preprocessing.is_some_and(|p| p.periodic);
        let given = self
            .document
            .get("solver")
            .and_then(|s| s.get("formulation"))
            .is_some();
        (marked && self.formulation == Formulation::NonPeriodic && !given).then(|| {
            "the map is marked periodic ([surface] periodic = true) but is solved as a finite pad, the default formulation = \"non_periodic\": set formulation = \"periodic\" to solve it as one period of a periodic surface (as Python's formulation=\"auto\" does), or formulation = \"non_periodic\" to keep the pad without this warning".to_string()
        })
    }

    /// A measured map (read from a file or given as values) that is not
    /// marked periodic, solved with the periodic formulation: the solve
    /// takes it as one period, so its opposite edges meet. States the rms
    /// step between them along x and y in units of the rms height, beside
    /// the rms step between neighbouring cells, and what was removed.
    fn wrapped_map_warning(&self) -> Option<String> {
        let pre = self.preprocessing?;
        if self.formulation != Formulation::Periodic || pre.periodic {
            return None;
        }
        let crate::surface::EdgeSteps {
            edge_x,
            edge_y,
            cell_x,
            cell_y,
        } = crate::surface::edge_steps(self.surface.nx, self.surface.ny, &self.surface.heights)?;
        Some(format!(
            "the map is solved as one period of a periodic surface (formulation = \"periodic\") but is not marked periodic ([surface] periodic = true, Python periodic=True): its opposite edges meet with an rms step of {edge_x:.3} rms heights along x and {edge_y:.3} along y (neighbouring cells: {cell_x:.3} and {cell_y:.3}); detrend = \"{}\" was applied. A scan is not a period: use formulation = \"non_periodic\" for it, or mark a map that is one period as periodic",
            pre.detrend.name()
        ))
    }
}
