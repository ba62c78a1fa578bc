//! Contact spots: connected components of the contact map.
//!
//! Connectivity rule: two contact cells belong to the same spot when they
//! share a side (4-connectivity, the convention for cell-wise contact maps:
//! cells touching only at a corner carry no common contact line). The count
//! under 8-connectivity (sides or corners) is reported alongside. The map is
//! not periodic: spots do not wrap around the domain edges.

use serde::Serialize;

/// Neighbourhood used to join contact cells into spots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Connectivity {
    /// Cells sharing a side.
    Four,
    /// Cells sharing a side or a corner.
    Eight,
}

/// One connected contact spot.
#[derive(Debug, Clone, PartialEq)]
pub struct Spot {
    /// Cells in the spot.
    pub cells: usize,
    /// Whether the spot touches the boundary of the map.
    pub touches_edge: bool,
    /// Centroid `(i, j)` in cell units (cell centres at integer + 0.5).
    pub centroid: [f64; 2],
    /// Second moments of the cell centres about the centroid, in cells^2:
    /// `[var_x, var_y, cov_xy]`.
    pub moments: [f64; 3],
}

impl Spot {
    /// Largest eigenvalue of the second-moment tensor [cells^2] (for an
    /// ellipse of semi-axes `A >= B`, `A^2 / 4`).
    pub fn major_variance(&self) -> f64 {
        let [xx, yy, xy] = self.moments;
        0.5 * (xx + yy) + (0.5 * (xx - yy)).hypot(xy)
    }
}

/// Label the spots of `contact` (`> 0.5` in contact; `nx x ny`, C order).
/// Returns the spots in the order of their first cell in C order.
pub fn find_spots(contact: &[f64], nx: usize, ny: usize, conn: Connectivity) -> Vec<Spot> {
    let n = nx * ny;
    let mut label = vec![usize::MAX; n];
    let mut spots = Vec::new();
    let mut stack = Vec::new();
    let offsets: &[(isize, isize)] = match conn {
        Connectivity::Four => &[(-1, 0), (1, 0), (0, -1), (0, 1)],
        Connectivity::Eight => &[
            (-1, -1),
            (-1, 0),
            (-1, 1),
            (0, -1),
            (0, 1),
            (1, -1),
            (1, 0),
            (1, 1),
        ],
    };
    for start in 0..n {
        if contact[start] <= 0.5 || label[start] != usize::MAX {
            continue;
        }
        let id = spots.len();
        label[start] = id;
        stack.push(start);
        let (mut cells, mut edge) = (0usize, false);
        let (mut si, mut sj, mut sii, mut sjj, mut sij) = (0.0, 0.0, 0.0, 0.0, 0.0);
        while let Some(k) = stack.pop() {
            let (i, j) = (k / ny, k % ny);
            cells += 1;
            edge |= i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            si += x;
            sj += y;
            sii += x * x;
            sjj += y * y;
            sij += x * y;
            for &(di, dj) in offsets {
                let (ii, jj) = (i as isize + di, j as isize + dj);
                if ii < 0 || jj < 0 || ii >= nx as isize || jj >= ny as isize {
                    continue;
                }
                let kk = ii as usize * ny + jj as usize;
                if contact[kk] > 0.5 && label[kk] == usize::MAX {
                    label[kk] = id;
                    stack.push(kk);
                }
            }
        }
        let c = cells as f64;
        let (mi, mj) = (si / c, sj / c);
        spots.push(Spot {
            cells,
            touches_edge: edge,
            centroid: [mi, mj],
            moments: [
                (sii / c - mi * mi).max(0.0),
                (sjj / c - mj * mj).max(0.0),
                sij / c - mi * mj,
            ],
        });
    }
    spots
}

/// One bin of the spot-area histogram: spots with
/// `min_cells <= cells <= max_cells`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AreaBin {
    pub min_cells: usize,
    pub max_cells: usize,
    pub count: usize,
}

/// Statistics of the contact spots.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpotStatistics {
    /// The rule used for `count` and the areas: always `four`.
    pub connectivity: Connectivity,
    /// Number of spots (4-connected).
    pub count: usize,
    /// Number of spots if corner-touching cells were joined (8-connected).
    pub count_8_connected: usize,
    /// Spots with a cell on the boundary of the map (their area is cut).
    pub touching_edge: usize,
    /// Mean spot area \[cells\].
    pub mean_area_cells: f64,
    /// Median spot area \[cells\] (mean of the two middle ones for an even count).
    pub median_area_cells: f64,
    /// Largest spot area \[cells\].
    pub max_area_cells: usize,
    /// Mean spot area [m^2].
    pub mean_area: f64,
    /// Largest spot area [m^2].
    pub max_area: f64,
    /// Histogram of the areas in octaves: `[1, 1], [2, 3], [4, 7], ...`.
    pub histogram: Vec<AreaBin>,
}

/// Spot statistics of `contact` with cells of side `cell_size` \[m\].
pub fn spot_statistics(contact: &[f64], nx: usize, ny: usize, cell_size: f64) -> SpotStatistics {
    let spots = find_spots(contact, nx, ny, Connectivity::Four);
    let count_8 = find_spots(contact, nx, ny, Connectivity::Eight).len();
    statistics_of(&spots, count_8, cell_size * cell_size)
}

/// Spot statistics of `spots` on cells of area `cell_area` \[m^2\].
pub(crate) fn statistics_of(spots: &[Spot], count_8: usize, cell_area: f64) -> SpotStatistics {
    let mut areas: Vec<usize> = spots.iter().map(|s| s.cells).collect();
    areas.sort_unstable();
    let count = areas.len();
    let total: usize = areas.iter().sum();
    let mean = if count > 0 {
        total as f64 / count as f64
    } else {
        0.0
    };
    let median = match count {
        0 => 0.0,
        c if c % 2 == 1 => areas[c / 2] as f64,
        c => 0.5 * (areas[c / 2 - 1] + areas[c / 2]) as f64,
    };
    let max = areas.last().copied().unwrap_or(0);
    let mut histogram = Vec::new();
    let mut lo = 1usize;
    while lo <= max {
        let hi = 2 * lo - 1;
        let n = areas.iter().filter(|&&a| a >= lo && a <= hi).count();
        histogram.push(AreaBin {
            min_cells: lo,
            max_cells: hi,
            count: n,
        });
        lo *= 2;
    }
    let a2 = cell_area;
    SpotStatistics {
        connectivity: Connectivity::Four,
        count,
        count_8_connected: count_8,
        touching_edge: spots.iter().filter(|s| s.touches_edge).count(),
        mean_area_cells: mean,
        median_area_cells: median,
        max_area_cells: max,
        mean_area: mean * a2,
        max_area: max as f64 * a2,
        histogram,
    }
}
