//! Building a [`Material`] from its `[material]` section (the types live in
//! [`crate::config::material`]; key names fixed by the project).

use std::path::Path;

use super::file::load_material_file;
use super::{CreepSpectrum, CreepTerm, Material, MaterialError, PronySeries, PronyTerm, Wlf};
use crate::config::{MaterialConfig, MaterialModel};

/// Each key of `[material]` with the unit its error messages quote.
const KEYS: [(&str, &str); 11] = [
    ("relaxed_modulus", "E0 in Pa"),
    ("glassy_modulus", "E_inf in Pa"),
    ("creep_time", "s"),
    ("relaxation_time", "s"),
    ("creep_spectrum", "[[C_k in 1/Pa, tau_k in s], ...]"),
    ("prony", "[[E_j in Pa, theta_j in s], ...]"),
    ("file", "path of a material.toml, relative to the config"),
    ("poisson", "dimensionless, in (-1, 0.5]"),
    ("wlf", "[C1, C2 in K, T_ref in C]"),
    (
        "wlf_range",
        "[lowest, highest] temperature of the WLF fit's data, in C",
    ),
    (
        "frequency_range",
        "[lowest, highest] angular frequency of the fit's data, in rad/s",
    ),
];

fn unit(key: &str) -> &'static str {
    KEYS.iter()
        .find(|(k, _)| *k == key)
        .map(|(_, u)| *u)
        .unwrap_or("")
}

/// The moduli accepted \[Pa\]: beyond them the compliances leave the
/// range the solver's double precision carries.
pub const MODULUS_RANGE: (f64, f64) = (1e-3, 1e15);

/// The relaxed and glassy moduli a spectrum implies within
/// [`MODULUS_RANGE`], as the keys that give them directly are: a creep
/// spectrum's compliances or a Prony series' moduli can put them anywhere
/// (a compliance of 1e20 1/Pa made `E0` 1e-20 Pa and a friction of 1e23).
fn check_implied_moduli(spectrum: &CreepSpectrum, model: &str) -> Result<(), MaterialError> {
    let (lo, hi) = MODULUS_RANGE;
    for (name, e) in [
        ("relaxed modulus E0", spectrum.relaxed_modulus()),
        ("glassy modulus E_inf", 1.0 / spectrum.glassy_compliance()),
    ] {
        if !(lo..=hi).contains(&e) {
            return Err(MaterialError::Invalid(format!(
                "[material] model = \"{model}\" implies a {name} of {e:e} Pa, outside [{lo:e}, {hi:e}] Pa, the moduli of solids (gels to diamond) with room on both sides; check its terms"
            )));
        }
    }
    Ok(())
}

impl MaterialConfig {
    /// Build the material; `base_dir` resolves relative file paths.
    ///
    /// * `sls`: `relaxed_modulus`, `glassy_modulus` and exactly one of
    ///   `creep_time` (`tau` of Eq. 2) or `relaxation_time`
    ///   (`theta = tau E0 / E_inf`, physics.md section 2);
    /// * `creep_spectrum`: `glassy_modulus` and `creep_spectrum` (Eq. 2);
    /// * `prony`: `relaxed_modulus` and `prony` (generalized Maxwell), converted
    ///   exactly to a creep spectrum ([`super::PronySeries::to_creep`]);
    /// * `file`: `file` (a `material.toml` from `viscoslide material fit`);
    ///   `poisson` here overrides the file's.
    ///
    /// `wlf = [C1, C2, T_ref]` (any model) gives the WLF constants of a
    /// `[loading] temperature` (physics.md section 12); a `file` fitted
    /// with `--wlf` carries its own. `wlf_range = [lowest, highest]`
    /// records the temperatures of the data they were fitted to
    /// ([`Wlf::data_range`]; for `file`, the file's `[fit]` records its own),
    /// `frequency_range = [lowest, highest]` the data's angular frequencies
    /// ([`Material::frequency_range`]).
    ///
    /// `poisson` defaults to 0.5. A key the model does not use is an error
    /// (it would be silently ignored otherwise), as is any non-finite or
    /// non-positive value.
    /// Builds the material; moduli must lie in 1e-3 .. 1e15 Pa (`MODULUS_RANGE`).
    pub fn build(&self, base_dir: &Path) -> Result<Material, MaterialError> {
        let model = self.model_name();
        let invalid = |key: &str, what: String| {
            MaterialError::Invalid(format!("[material] {key} ({}): {what}", unit(key)))
        };
        let allowed: &[&str] = match self.model {
            MaterialModel::Sls => &[
                "relaxed_modulus",
                "glassy_modulus",
                "creep_time",
                "relaxation_time",
            ],
            MaterialModel::CreepSpectrum => &["glassy_modulus", "creep_spectrum"],
            MaterialModel::Prony => &["relaxed_modulus", "prony"],
            MaterialModel::File => &["file"],
        };
        for key in self.present_keys() {
            if !["poisson", "wlf", "wlf_range", "frequency_range"].contains(&key)
                && !allowed.contains(&key)
            {
                return Err(MaterialError::Invalid(format!(
                    "[material] model = \"{model}\" does not use `{key}` ({}); remove it (this model takes {})",
                    unit(key),
                    allowed.join(", ")
                )));
            }
        }
        let need = |v: Option<f64>, key: &str| {
            v.ok_or_else(|| {
                MaterialError::Invalid(format!(
                    "[material] model = \"{model}\" needs `{key}` ({})",
                    unit(key)
                ))
            })
        };
        let positive = |v: f64, key: &str| {
            let (lo, hi) = MODULUS_RANGE;
            if !(v.is_finite() && v > 0.0) {
                Err(invalid(key, format!("{v} must be positive and finite")))
            } else if key.ends_with("_modulus") && !(lo..=hi).contains(&v) {
                Err(invalid(
                    key,
                    format!("{v:e} Pa is outside [{lo:e}, {hi:e}] Pa, the moduli of solids (gels to diamond) with room on both sides"),
                ))
            } else {
                Ok(v)
            }
        };
        let pairs = |list: &Option<Vec<[f64; 2]>>, key: &str| {
            let list = list.as_ref().ok_or_else(|| {
                MaterialError::Invalid(format!(
                    "[material] model = \"{model}\" needs `{key}` ({})",
                    unit(key)
                ))
            })?;
            for (i, [w, t]) in list.iter().enumerate() {
                if !(w.is_finite() && *w >= 0.0 && t.is_finite() && *t > 0.0) {
                    return Err(invalid(
                        key,
                        format!(
                            "entry {i} = [{w}, {t}]: weight must be >= 0 and time > 0, both finite"
                        ),
                    ));
                }
            }
            Ok(list.clone())
        };
        let nu = match self.poisson {
            None => 0.5,
            Some(v) if v.is_finite() && v > -1.0 && v <= 0.5 => v,
            Some(v) => return Err(invalid("poisson", format!("{v} is outside (-1, 0.5]"))),
        };
        let wlf = self
            .wlf
            .map(|[c1, c2, t]| Wlf::new(c1, c2, t).map_err(|e| invalid("wlf", e.to_string())))
            .transpose()?;
        let spectrum = match self.model {
            MaterialModel::Sls => {
                let e0 = positive(
                    need(self.relaxed_modulus, "relaxed_modulus")?,
                    "relaxed_modulus",
                )?;
                let einf = positive(
                    need(self.glassy_modulus, "glassy_modulus")?,
                    "glassy_modulus",
                )?;
                if einf < e0 {
                    return Err(invalid(
                        "glassy_modulus",
                        format!("{einf} must be >= relaxed_modulus = {e0} Pa"),
                    ));
                }
                let tau = match (self.creep_time, self.relaxation_time) {
                    (Some(_), Some(_)) => {
                        return Err(MaterialError::Invalid(
                            "[material] give either `creep_time` (s) or `relaxation_time` (s), not both"
                                .into(),
                        ))
                    }
                    (Some(t), None) => positive(t, "creep_time")?,
                    // theta = tau E0 / E_inf  =>  tau = theta E_inf / E0.
                    (None, Some(t)) => positive(t, "relaxation_time")? * einf / e0,
                    (None, None) => {
                        return Err(MaterialError::Invalid(
                            "[material] model = \"sls\" needs `creep_time` (s) or `relaxation_time` (s)"
                        .into()))
                    }
                };
                CreepSpectrum::standard_linear_solid(e0, einf, tau)?
            }
            MaterialModel::CreepSpectrum => {
                let einf = positive(
                    need(self.glassy_modulus, "glassy_modulus")?,
                    "glassy_modulus",
                )?;
                let terms = pairs(&self.creep_spectrum, "creep_spectrum")?
                    .into_iter()
                    .map(|[c, t]| CreepTerm {
                        compliance: c,
                        time: t,
                    })
                    .collect();
                CreepSpectrum::new(einf, terms)?
            }
            MaterialModel::Prony => {
                let e0 = positive(
                    need(self.relaxed_modulus, "relaxed_modulus")?,
                    "relaxed_modulus",
                )?;
                let terms = pairs(&self.prony, "prony")?
                    .into_iter()
                    .map(|[e, t]| PronyTerm {
                        modulus: e,
                        time: t,
                    })
                    .collect();
                PronySeries::new(e0, terms)?.to_creep()?
            }
            MaterialModel::File => {
                let rel = self.file.as_ref().ok_or_else(|| {
                    MaterialError::Invalid(format!(
                        "[material] model = \"file\" needs `file` ({})",
                        unit("file")
                    ))
                })?;
                let path = base_dir.join(rel);
                let material = load_material_file(&path, self.poisson.map(|_| nu))?;
                check_implied_moduli(&material.spectrum, model)?;
                let material = match wlf {
                    Some(w) => {
                        let t = material.temperature;
                        material
                            .with_wlf(w, t)
                            .map_err(|e| invalid("wlf", e.to_string()))?
                    }
                    None => material,
                };
                return self.with_data_ranges(material);
            }
        };
        check_implied_moduli(&spectrum, model)?;
        let material = Material::new(spectrum, nu)?;
        let material = match wlf {
            Some(w) => material.with_wlf(w, None)?,
            None => material,
        };
        self.with_data_ranges(material)
    }

    /// `material` with this table's `frequency_range`, and its
    /// `wlf_range` on its WLF constants (the table's own, or a file's),
    /// when given.
    fn with_data_ranges(&self, mut material: Material) -> Result<Material, MaterialError> {
        if let Some(range) = self.frequency_range {
            material = material.with_frequency_range(range).map_err(|e| {
                MaterialError::Invalid(format!(
                    "[material] frequency_range ({}): {e}",
                    unit("frequency_range")
                ))
            })?;
        }
        let Some(range) = self.wlf_range else {
            return Ok(material);
        };
        let wlf = material.wlf.ok_or_else(|| {
            MaterialError::Invalid(
                "[material] wlf_range is the temperature range of the data WLF constants were fitted to: give the constants too (wlf = [C1, C2 (K), T_ref (C)], or a file fitted with `material fit --wlf`)".into(),
            )
        })?;
        material.wlf = Some(wlf.with_data_range(range).map_err(|e| {
            MaterialError::Invalid(format!("[material] wlf_range ({}): {e}", unit("wlf_range")))
        })?);
        Ok(material)
    }

    /// Names of the keys this table sets (besides `model`).
    fn present_keys(&self) -> Vec<&'static str> {
        let mut k = Vec::new();
        let mut add = |set: bool, name: &'static str| {
            if set {
                k.push(name);
            }
        };
        add(self.relaxed_modulus.is_some(), "relaxed_modulus");
        add(self.glassy_modulus.is_some(), "glassy_modulus");
        add(self.creep_time.is_some(), "creep_time");
        add(self.relaxation_time.is_some(), "relaxation_time");
        add(self.creep_spectrum.is_some(), "creep_spectrum");
        add(self.prony.is_some(), "prony");
        add(self.file.is_some(), "file");
        add(self.poisson.is_some(), "poisson");
        add(self.wlf.is_some(), "wlf");
        add(self.wlf_range.is_some(), "wlf_range");
        add(self.frequency_range.is_some(), "frequency_range");
        k
    }

    fn model_name(&self) -> &'static str {
        match self.model {
            MaterialModel::Sls => "sls",
            MaterialModel::CreepSpectrum => "creep_spectrum",
            MaterialModel::Prony => "prony",
            MaterialModel::File => "file",
        }
    }
}
