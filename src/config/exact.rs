//! Fixed-length number arrays read exactly. Serde's `[f64; N]` stops
//! reading after its length, so `creep_spectrum = [[C, tau, x]]` or
//! `speed_range = [from, to, points, x]` would pass with `x` dropped; these
//! readers refuse any other length, naming the key (through the TOML
//! reader's error) and the length expected.

use serde::{Deserialize, Deserializer};

/// `N` numbers, no more and no fewer.
struct Exact<const N: usize>([f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor<const N: usize>;
        impl<'de, const N: usize> serde::de::Visitor<'de> for Visitor<N> {
            type Value = Exact<N>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of length {N}")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Exact<N>, A::Error> {
                let mut v = Vec::with_capacity(N);
                while let Some(x) = seq.next_element::<f64>()? {
                    v.push(x);
                }
                <[f64; N]>::try_from(v.as_slice())
                    .map(Exact)
                    .map_err(|_| serde::de::Error::invalid_length(v.len(), &self))
            }
        }
        d.deserialize_seq(Visitor::<N>)
    }
}

/// An optional array of exactly `N` numbers (`wlf`, `speed_range`).
pub(crate) fn exactly<'de, const N: usize, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[f64; N]>, D::Error> {
    Ok(Option::<Exact<N>>::deserialize(d)?.map(|e| e.0))
}

/// An optional list of rows of exactly `N` numbers (`creep_spectrum`,
/// `prony`).
pub(crate) fn exact_rows<'de, const N: usize, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<[f64; N]>>, D::Error> {
    Ok(
        Option::<Vec<Exact<N>>>::deserialize(d)?
            .map(|rows| rows.into_iter().map(|e| e.0).collect()),
    )
}
