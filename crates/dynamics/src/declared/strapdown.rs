//! A declaration as a strapdown effect. The strapdown catalogue is itself a list of
//! declarations: each coefficient sits in one place of the sensor-error description the model
//! evaluates (docs/model.md eqs. (63)-(70); [`crate::strapdown::errors`]). A user's effect is
//! the same, with two freedoms the catalogue does not use: a coefficient may sit in several
//! places, and each place takes it times a constant factor. A unit turned on its mount by a
//! small angle `d` about its z axis, for one, is `-d` in `E_g[x][y]` and `E_a[x][y]` and `d`
//! in `E_g[y][x]` and `E_a[y][x]`: one coefficient, four places.
//!
//! ```
//! use navkf_dynamics::declared::parse_declarations;
//! use navkf_dynamics::strapdown::effects::StrapdownRegistry;
//!
//! let text = r#"
//! [[effect]]
//! name = "mount-yaw"
//! description = "the whole unit turned by d about its z axis on its mount"
//! coefficients = [{ name = "d_mz", unit = "rad", sigma = 1e-3 }]
//! places = [
//!     { coefficient = "d_mz", place = "E_g[x][y]", factor = -1 },
//!     { coefficient = "d_mz", place = "E_g[y][x]" },
//!     { coefficient = "d_mz", place = "E_a[x][y]", factor = -1 },
//!     { coefficient = "d_mz", place = "E_a[y][x]" },
//! ]
//! "#;
//! let mut registry = StrapdownRegistry::catalogue();
//! registry.declare(&parse_declarations(text).unwrap()).unwrap();
//! let effect = registry.get("mount-yaw").unwrap();
//! assert_eq!(effect.coefficients[0].places.iter().count(), 4);
//! ```

use super::declaration::EffectDeclaration;
use super::intern;
use crate::strapdown::effects::{Coefficient, Place, Places, Slot, StrapdownEffect};
use crate::strapdown::state::{ACCEL_DEPARTURE_NAMES, GYRO_DEPARTURE_NAMES, STATE_NAMES};
use std::sync::{Arc, Mutex};

/// The places a declaration may name, as docs/model.md writes them (axes `x`, `y`, `z`:
/// forward, left, up).
pub const PLACES: [&str; 8] = [
    "E_g[i][j]",
    "E_a[i][j]",
    "G[i]",
    "kod",
    "a_y",
    "a_p",
    "l[i]",
    "tau",
];

/// The slot `text` names (`E_g[x][y]`, `kod`, ...), or `None`.
pub fn parse_place(text: &str) -> Option<Slot> {
    let axis = |c: &str| ["x", "y", "z"].iter().position(|a| *a == c);
    let indices = |rest: &str| -> Option<Vec<usize>> {
        let rest = rest.strip_prefix('[')?.strip_suffix(']')?;
        rest.split("][").map(axis).collect()
    };
    let text = text.trim();
    Some(match text {
        "kod" => Slot::OdometerScale,
        "a_y" => Slot::OdometerYaw,
        "a_p" => Slot::OdometerPitch,
        "tau" => Slot::Latency,
        _ => {
            let (head, rest) = text.split_at(text.find('[')?);
            match (head, indices(rest)?.as_slice()) {
                ("E_g", [i, j]) => Slot::Gyro(*i, *j),
                ("E_a", [i, j]) => Slot::Accel(*i, *j),
                ("G", [i]) => Slot::GyroG(*i),
                ("l", [i]) => Slot::LeverArm(*i),
                _ => return None,
            }
        }
    })
}

/// `items` as a `&'static` slice, each distinct list leaked once into `lists` (as [`intern`]
/// does for names): a [`StrapdownEffect`] lends its coefficients and their places as
/// `&'static`, like the catalogue's constants.
fn intern_in<T: PartialEq>(lists: &Mutex<Vec<&'static [T]>>, items: Vec<T>) -> &'static [T] {
    let mut lists = lists
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(found) = lists.iter().find(|l| **l == items.as_slice()) {
        return found;
    }
    let leaked: &'static [T] = Box::leak(items.into_boxed_slice());
    lists.push(leaked);
    leaked
}

static PLACE_LISTS: Mutex<Vec<&'static [Place]>> = Mutex::new(Vec::new());
static COEFFICIENT_LISTS: Mutex<Vec<&'static [Coefficient]>> = Mutex::new(Vec::new());

impl EffectDeclaration {
    /// The declaration as a strapdown effect, checked against the effects known already
    /// (`effects`, and `owner_of`, the effect owning a coefficient name). The error names the
    /// key within the declaration (`places[1].place`) and says what was expected.
    pub(crate) fn strapdown_effect(
        &self,
        effects: &[String],
        owner_of: impl Fn(&str) -> Option<String>,
    ) -> Result<StrapdownEffect, (String, String)> {
        // The base states and a bias instability's departures (docs/model.md eq. (69)): a
        // coefficient of the same name would be a second state answering to it.
        let reserved: Vec<&str> = STATE_NAMES
            .iter()
            .chain(&GYRO_DEPARTURE_NAMES)
            .chain(&ACCEL_DEPARTURE_NAMES)
            .copied()
            .collect();
        self.check_name_and_coefficients(effects, owner_of, &reserved)?;
        if !self.rates.is_empty() || !self.measurement.is_empty() {
            let key = if self.rates.is_empty() {
                "measurement"
            } else {
                "rates"
            };
            return Err((
                key.into(),
                "terms are the platform family's; expected `places` for a strapdown effect \
                 (where each coefficient sits: `E_g[x][y]`, `kod`, ...)"
                    .into(),
            ));
        }
        if self.places.is_empty() {
            return Err((
                "places".into(),
                format!(
                    "empty; expected where each coefficient sits, one of {}",
                    PLACES.join(", ")
                ),
            ));
        }
        // Each coefficient's places.
        let mut places: Vec<Vec<Place>> = vec![Vec::new(); self.coefficients.len()];
        for (i, p) in self.places.iter().enumerate() {
            let key = |k: &str| format!("places[{i}].{k}");
            let c = self.coefficient_index(&p.coefficient, key("coefficient"))?;
            let Some(slot) = parse_place(&p.place) else {
                return Err((
                    key("place"),
                    format!(
                        "`{}`: expected one of {} (i, j: x, y or z)",
                        p.place,
                        PLACES.join(", ")
                    ),
                ));
            };
            if !(p.factor.is_finite() && p.factor != 0.0) {
                return Err((
                    key("factor"),
                    format!("{}: expected a finite factor other than 0", p.factor),
                ));
            }
            if let Some(other) = places
                .iter()
                .position(|mine| mine.iter().any(|q| q.slot == slot))
            {
                return Err((
                    key("place"),
                    format!(
                        "`{}` holds `{}` already; expected each place once",
                        p.place, self.coefficients[other].name
                    ),
                ));
            }
            places[c].push(Place {
                slot,
                factor: p.factor,
            });
        }
        for (i, (c, mine)) in self.coefficients.iter().zip(&places).enumerate() {
            if mine.is_empty() {
                return Err((
                    format!("coefficients[{i}].name"),
                    format!(
                        "`{}` is in no place; expected every coefficient in at least one \
                         (one in none cannot be estimated)",
                        c.name
                    ),
                ));
            }
            // The truth takes a latency exactly, as a time shift of the whole fix: its
            // coefficient cannot act anywhere else.
            if mine.len() > 1 && mine.iter().any(|p| p.slot == Slot::Latency) {
                return Err((
                    format!("coefficients[{i}].name"),
                    format!(
                        "`{}` sits in `tau` and elsewhere; expected a latency's coefficient \
                         in `tau` alone",
                        c.name
                    ),
                ));
            }
        }
        let coefficients = self
            .coefficients
            .iter()
            .zip(places)
            .map(|(c, mine)| Coefficient {
                name: intern(&c.name),
                unit: intern(&c.unit),
                places: match mine.as_slice() {
                    [only] if only.factor == 1.0 => Places::One(only.slot),
                    _ => Places::Many(intern_in(&PLACE_LISTS, mine)),
                },
                sigma: [c.sigma; 3],
                bound: c.physical_bound(),
            })
            .collect();
        let description = if self.description.trim().is_empty() {
            self.written_places()
        } else {
            self.description.clone()
        };
        Ok(StrapdownEffect {
            name: intern(&self.name),
            description: intern(&description),
            coefficients: intern_in(&COEFFICIENT_LISTS, coefficients),
            instability: None,
            declaration: Some(Arc::new(self.clone())),
        })
    }

    /// The places written out, for the description when the declaration gives none:
    /// `E_g[x][y] = -1 d_mz; E_g[y][x] = d_mz`.
    fn written_places(&self) -> String {
        self.places
            .iter()
            .map(|p| {
                let factor = if p.factor == 1.0 {
                    String::new()
                } else {
                    format!("{} ", p.factor)
                };
                format!("{} = {factor}{}", p.place.trim(), p.coefficient)
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_parse_as_the_model_document_writes_them() {
        assert_eq!(parse_place("E_g[x][y]"), Some(Slot::Gyro(0, 1)));
        assert_eq!(parse_place(" E_a[z][z] "), Some(Slot::Accel(2, 2)));
        assert_eq!(parse_place("G[y]"), Some(Slot::GyroG(1)));
        assert_eq!(parse_place("l[z]"), Some(Slot::LeverArm(2)));
        assert_eq!(parse_place("kod"), Some(Slot::OdometerScale));
        assert_eq!(parse_place("a_y"), Some(Slot::OdometerYaw));
        assert_eq!(parse_place("a_p"), Some(Slot::OdometerPitch));
        assert_eq!(parse_place("tau"), Some(Slot::Latency));
        for bad in [
            "E_g[x]",
            "E_g[0][1]",
            "E_g[x][w]",
            "G[x][y]",
            "E_b[x][y]",
            "l",
            "",
        ] {
            assert_eq!(parse_place(bad), None, "{bad}");
        }
    }

    /// A coefficient named as a base state or a bias instability's departure is refused at
    /// its key: beside `gyro-bias-instability` the model would hold two states `dbgx`.
    #[test]
    fn a_coefficient_named_as_a_state_is_refused() {
        for name in ["heading", "bax", "dbgx", "dbaz"] {
            let text = format!(
                "[[effect]]\nname = \"mine\"\n\
                 coefficients = [{{ name = \"{name}\", unit = \"1\", sigma = 1e-3 }}]\n\
                 places = [{{ coefficient = \"{name}\", place = \"kod\" }}]\n"
            );
            let mut registry = crate::strapdown::effects::StrapdownRegistry::catalogue();
            let decl = crate::declared::parse_declarations(&text).unwrap();
            let e = registry.declare(&decl).unwrap_err().to_string();
            assert!(
                e.contains("coefficients[0].name") && e.contains("is a state of the model"),
                "{name}: {e}"
            );
        }
    }
}
