//! The dissipation form summed component by component over a node's grid
//! fields (module docs of `dissipation/`): each stress component's field
//! transformed into its buffer, then its share added.

use num_complex::Complex64;

use super::super::stress::ModeStress;

/// The buffer component `c`'s grid field is transformed into: component
/// 0's is kept in `first` for component 1's share ([`accumulate`]), the
/// others go to `field` (no copy: a copy of each row cost a tenth of the
/// separable path).
pub(super) fn field_for<'a>(c: usize, field: &'a mut [f64], first: &'a mut [f64]) -> &'a mut [f64] {
    if c == 0 {
        first
    } else {
        field
    }
}

/// `out +=` component `c`'s share of the dissipation form (weighted by
/// `dev` and `trace`) of its grid field (`field`, component 0's in
/// `first`: its share is added with component 1's, [`field_for`]). The
/// form `(1 + nu) (xx^2 + yy^2 + zz^2 + 2 xy^2 + 2 xz^2 + 2 yz^2) + (1 -
/// 2 nu) / 3 tr^2`, `zz = -(xx + yy)`.
pub(super) fn accumulate(
    c: usize,
    field: &[f64],
    first: &[f64],
    out: &mut [f64],
    dev: f64,
    trace: f64,
) {
    match c {
        0 => {}
        1 => out
            .iter_mut()
            .zip(first.iter())
            .zip(field)
            .for_each(|((o, x), y)| *o += dev * (x * x + y * y + (x + y) * (x + y))),
        5 => out
            .iter_mut()
            .zip(field)
            .for_each(|(o, v)| *o += trace * v * v),
        _ => out
            .iter_mut()
            .zip(field)
            .for_each(|(o, v)| *o += 2.0 * dev * v * v),
    }
}

/// Component `c` of a stress: the five deviatoric ones, then the trace.
pub(super) fn component(s: &ModeStress, c: usize) -> Complex64 {
    if c < 5 {
        s.dev[c]
    } else {
        s.trace
    }
}
