//! The columns of a DMA CSV that the reader does not take
//! ([`super::DmaData::parse`]): a temperature in kelvin or Fahrenheit is
//! refused, since the reader takes temperatures from `temperature_c` (C)
//! only and would otherwise read all points as one temperature; any other
//! unread column is named in a warning.

/// The unit a column's name gives a temperature, when the name looks
/// like one (`temperature_k`, `temp_f`, `T [K]`, `temp`, `t`, ...):
/// `Some("K")`, `Some("F")`, `Some("C")`, or `Some("")` for none stated.
fn temperature_unit(name: &str) -> Option<&'static str> {
    let tokens: Vec<&str> = name
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|t| !t.is_empty())
        .collect();
    let temperature = |t: &str| matches!(t, "t" | "temp" | "tmp" | "temperature");
    match tokens.as_slice() {
        ["kelvin"] => return Some("K"),
        ["fahrenheit"] => return Some("F"),
        [first, ..] if temperature(first) => {}
        _ => return None,
    }
    let unit = tokens[1..].iter().find_map(|t| match *t {
        "k" | "kelvin" => Some("K"),
        "f" | "degf" | "fahrenheit" => Some("F"),
        "c" | "degc" | "celsius" => Some("C"),
        _ => None,
    });
    Some(unit.unwrap_or(""))
}

/// The message for a column the reader does not take, `name` (lower
/// case): `Err` for a temperature in kelvin or Fahrenheit when the file
/// has no `temperature_c` column, else the warning that it is ignored.
pub(super) fn unread_column(name: &str, has_celsius: bool) -> Result<String, String> {
    match temperature_unit(name) {
        Some(unit @ ("K" | "F")) if !has_celsius => Err(format!(
            "column {name} looks like a temperature in {unit}, which is not read: the reader takes temperatures in C from a column named temperature_c only (convert them, or all points are read as one temperature)"
        )),
        Some(_) if !has_celsius => Ok(format!(
            "column {name} is ignored: it looks like a temperature, but the reader takes temperatures in C from a column named temperature_c only, so all points are read as one temperature"
        )),
        _ => Ok(format!("column {name} is not one the reader takes and is ignored")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temperature_like_names_and_units() {
        for (name, unit) in [
            ("temperature_k", Some("K")),
            ("temp_k", Some("K")),
            ("t (k)", Some("K")),
            ("kelvin", Some("K")),
            ("temperature_f", Some("F")),
            ("t[degf]", Some("F")),
            ("temp_c", Some("C")),
            ("temp", Some("")),
            ("t", Some("")),
            ("tan_delta", None),
            ("time_s", None),
        ] {
            assert_eq!(temperature_unit(name), unit, "{name}");
        }
    }

    #[test]
    fn kelvin_is_refused_naming_the_column_the_reader_takes() {
        let e = unread_column("temperature_k", false).unwrap_err();
        assert!(
            e.contains("temperature_k") && e.contains("temperature_c"),
            "{e}"
        );
        // Beside a temperature_c column it is merely ignored.
        let w = unread_column("temperature_k", true).unwrap();
        assert!(w.contains("ignored"), "{w}");
        let w = unread_column("temp", false).unwrap();
        assert!(
            w.contains("temperature_c") && w.contains("one temperature"),
            "{w}"
        );
        assert!(unread_column("tan_delta", false)
            .unwrap()
            .contains("tan_delta"));
    }
}
