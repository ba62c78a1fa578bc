//! Units of length that surface files state (headers, Gwyddion unit
//! strings): one table of metres per unit that every reader looks up.

/// Metres per unit of every spelling a reader accepts: SI prefixes on `m`
/// (`um` and `µm` with the micro sign or the Greek mu) and the Ångström
/// (`Å`, `A`, `Angstrom`, `angstrom`). Each reader states which of them it
/// takes.
const METRES_PER_UNIT: &[(&str, f64)] = &[
    ("km", 1e3),
    ("m", 1.0),
    ("dm", 1e-1),
    ("cm", 1e-2),
    ("mm", 1e-3),
    ("um", 1e-6),
    ("µm", 1e-6),
    ("μm", 1e-6),
    ("nm", 1e-9),
    ("Å", 1e-10),
    ("A", 1e-10),
    ("Angstrom", 1e-10),
    ("angstrom", 1e-10),
    ("pm", 1e-12),
    ("fm", 1e-15),
];

/// Metres per unit of `unit`, spelled exactly as in [`METRES_PER_UNIT`];
/// `None` for any other text.
pub(super) fn metres_per(unit: &str) -> Option<f64> {
    METRES_PER_UNIT
        .iter()
        .find(|(name, _)| *name == unit)
        .map(|&(_, metres)| metres)
}
