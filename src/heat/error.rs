//! `HeatError`: what the heat room refuses, each in one line that names
//! the quantity and what to give instead.

/// Errors of the heat problem's inputs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HeatError {
    /// A speed, conductivity, diffusivity, cell side or block length that
    /// is zero, negative, infinite or NaN.
    #[error("{name} = {value} must be positive and finite ({unit})")]
    NotPositive {
        name: &'static str,
        value: f64,
        unit: &'static str,
    },
    /// A block shorter than the periodic cell it holds.
    #[error("the block length {block:e} m is shorter than the periodic cell along the sliding direction ({cell:.4e} m): the cell is one piece of the block's nominal contact, so the block is at least as long; give the block's length along the sliding direction (m)")]
    BlockShorterThanCell { block: f64, cell: f64 },
    /// A sliding direction that is not a finite angle.
    #[error("the sliding direction {0} rad must be finite")]
    Direction(f64),
    /// A map or a list with nothing in it.
    #[error("{0} is empty: give at least one cell")]
    Empty(&'static str),
    /// A map whose length is not the grid's number of cells.
    #[error("{name} holds {found} values, but the {nx} x {ny} grid needs {expected}")]
    Shape {
        name: &'static str,
        found: usize,
        nx: usize,
        ny: usize,
        expected: usize,
    },
    /// A NaN or infinite source value.
    #[error("{name} is {value} at cell ({i}, {j}){}: every value must be finite", layer_text(.layer))]
    NotFinite {
        name: &'static str,
        value: f64,
        i: usize,
        j: usize,
        layer: Option<usize>,
    },
    /// Depth layers that do not start at the surface and go down.
    #[error("depth layers: {0}")]
    Layers(String),
    /// An output depth below zero or not finite.
    #[error("depth {0} m must be finite and >= 0 (0 is the surface)")]
    Depth(f64),
    /// A rise beyond f64's range (a flux near `f64::MAX`, or a
    /// conductivity near zero).
    #[error("the temperature rise overflows at cell ({i}, {j}) ({value} K): the heat source over the conductivity is beyond the range of f64")]
    Overflow { value: f64, i: usize, j: usize },
    /// Values each valid but together beyond what the heat problem's
    /// arithmetic or its verified rules hold (the message names them).
    #[error("{0}")]
    OutOfRange(String),
    /// A combination the heat room does not solve.
    #[error("{0}")]
    Unsupported(&'static str),
    /// A grid whose plan would not fit in memory (the message of
    /// [`crate::io::memory::MemoryError`]).
    #[error("{0}")]
    Memory(String),
    /// The caller asked to stop (a heated solve whose observer was
    /// cancelled) while the heat source was computed.
    #[error("the heat source was cancelled")]
    Cancelled,
    /// A transform that could not be planned or run.
    #[error("heat problem: {0}")]
    Transform(String),
}

/// [`HeatError::Overflow`] at the first rise that is not finite in a map
/// of `ny` cells per row.
pub(crate) fn check_rise(rise: &[f64], ny: usize) -> Result<(), HeatError> {
    match rise.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(HeatError::Overflow {
            value: rise[k],
            i: k / ny,
            j: k % ny,
        }),
        None => Ok(()),
    }
}

/// `" in layer L"` for a volume source.
fn layer_text(layer: &Option<usize>) -> String {
    layer.map(|l| format!(" in layer {l}")).unwrap_or_default()
}

/// `value` if it is positive and finite, else [`HeatError::NotPositive`].
pub(crate) fn positive(
    name: &'static str,
    value: f64,
    unit: &'static str,
) -> Result<f64, HeatError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(HeatError::NotPositive { name, value, unit })
    }
}

/// Check that `values` is a finite map of `nx x ny` cells.
pub(crate) fn check_map(
    name: &'static str,
    values: &[f64],
    (nx, ny): (usize, usize),
    layer: Option<usize>,
) -> Result<(), HeatError> {
    if values.is_empty() {
        return Err(HeatError::Empty(name));
    }
    if values.len() != nx * ny {
        return Err(HeatError::Shape {
            name,
            found: values.len(),
            nx,
            ny,
            expected: nx * ny,
        });
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(HeatError::NotFinite {
            name,
            value: values[k],
            i: k / ny,
            j: k % ny,
            layer,
        }),
        None => Ok(()),
    }
}
