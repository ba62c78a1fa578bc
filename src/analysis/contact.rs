//! Real contact area and pressure statistics (physics.md section 5).

use serde::Serialize;

/// Scalar statistics of a contact solution.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactStatistics {
    /// Cells in contact.
    pub contact_cells: usize,
    /// Real contact area `A` [m^2].
    pub contact_area: f64,
    /// `A / A0` with `A0` the area of the map.
    pub contact_area_fraction: f64,
    /// Largest pressure \[Pa\].
    pub max_pressure: f64,
    /// Normal load `a^2 sum p` \[N\].
    pub normal_load: f64,
    /// Nominal mean pressure `F_N / A0` \[Pa\].
    pub mean_pressure: f64,
    /// Pressure centroid `(x, y)` \[m\] relative to the centre of the map.
    pub pressure_centroid: [f64; 2],
}

/// Statistics of `pressure` and the contact map (`contact[i] > 0.5` in
/// contact) on an `nx x ny` grid of cells of sides `(a_x, a_y)` (area
/// `a_x a_y` each).
pub fn contact_statistics(
    pressure: &[f64],
    contact: &[f64],
    nx: usize,
    ny: usize,
    (ax, ay): (f64, f64),
) -> ContactStatistics {
    let cells = contact.iter().filter(|&&c| c > 0.5).count();
    let total: f64 = pressure.iter().sum();
    let (mut sx, mut sy) = (0.0, 0.0);
    for i in 0..nx {
        for j in 0..ny {
            let p = pressure[i * ny + j];
            sx += p * ((i as f64 + 0.5) * ax - 0.5 * nx as f64 * ax);
            sy += p * ((j as f64 + 0.5) * ay - 0.5 * ny as f64 * ay);
        }
    }
    let area0 = (nx * ny) as f64 * ax * ay;
    let load = total * ax * ay;
    ContactStatistics {
        contact_cells: cells,
        contact_area: cells as f64 * ax * ay,
        contact_area_fraction: cells as f64 / (nx * ny) as f64,
        max_pressure: pressure.iter().cloned().fold(0.0, f64::max),
        normal_load: load,
        mean_pressure: load / area0,
        pressure_centroid: if total > 0.0 {
            [sx / total, sy / total]
        } else {
            [0.0, 0.0]
        },
    }
}
