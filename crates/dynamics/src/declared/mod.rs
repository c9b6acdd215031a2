//! Effects declared in TOML, without Rust: `[[effect]]` tables in `dataset.toml`, in a study
//! file, or in a file of their own (`--effects-file`). docs/declared-effects.md is the
//! user's page.
//!
//! Why: the loop the harness exists for ends with "add the missing effect and watch the error
//! fall", and most effects are data already. The catalogue's rate effects are a coefficient
//! times a kinematic quantity (docs/model.md eqs. (37)-(40)), its measurement effects a
//! coefficient times the velocity or the position's rate (docs/model.md eqs. (41)-(42)). A
//! declaration states those terms; [`DeclaredEffect`] evaluates them and their partials, so a
//! declared effect serves the simulator, the three filters, the diagnosis, the studies and the
//! planner like a catalogued one. An effect of another form (its own noise, or non-linear in
//! its coefficient like `odometer-misalignment`'s rotation) is still a Rust [`crate::Effect`].
//!
//! ```
//! use navkf_dynamics::declared::parse_declarations;
//! use navkf_dynamics::{PlatformModel, NoiseConfig, Registry, SystemModel};
//!
//! let text = r#"
//! [[effect]]
//! name = "drag"
//! description = "v' += kd v: a velocity-proportional drag (kd < 0)"
//! coefficients = [{ name = "kd", unit = "1/s", sigma = 5e-5 }]
//! rates = [
//!     { to = "v_x", coefficient = "kd", feature = "v_x" },
//!     { to = "v_y", coefficient = "kd", feature = "v_y" },
//! ]
//! "#;
//! let mut registry = Registry::catalogue();
//! registry.declare(&parse_declarations(text).unwrap()).unwrap();
//! let model = PlatformModel::new(registry.build_all(&["drag"]).unwrap(), &NoiseConfig::default())
//!     .unwrap();
//! assert_eq!(model.state_names()[20], "kd");
//! ```

mod catalogue;
mod declaration;
mod effect;
mod effects_file;
mod feature;
pub mod strapdown;

pub use catalogue::EffectCatalogue;
pub use declaration::{
    CoefficientDeclaration, EffectDeclaration, PlaceDeclaration, TermDeclaration,
};
pub use effect::DeclaredEffect;
pub use effects_file::DeclaredFile;
pub use feature::{TermFeature, TermSide};

use crate::error::DynamicsError;
use crate::input_file::{read_text, toml_error, TextFile};
use serde::Deserialize;
use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Mutex;

/// A file of declarations: `[[effect]]` tables and nothing else.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EffectsFile {
    #[serde(default)]
    effect: Vec<EffectDeclaration>,
}

/// The `[[effect]]` tables of `text` (a file holding only those).
pub fn parse_declarations(text: &str) -> Result<Vec<EffectDeclaration>, toml::de::Error> {
    toml::from_str::<EffectsFile>(text).map(|f| f.effect)
}

/// Reads an effects file (`--effects-file`): `[[effect]]` tables only. A syntax error or an
/// unknown key is located by line and column; the declarations are checked when declared
/// ([`crate::Registry::declare`]).
pub fn read_declarations(path: &Path) -> Result<Vec<EffectDeclaration>, DynamicsError> {
    let text = read_text(path, &TextFile::EFFECTS)?;
    let declarations = parse_declarations(&text).map_err(|e| toml_error(path, &text, &e))?;
    if declarations.is_empty() {
        return Err(DynamicsError::File {
            path: path.to_path_buf(),
            message: "no [[effect]] table; expected at least one declared effect \
                      (docs/declared-effects.md)"
                .into(),
        });
    }
    Ok(declarations)
}

/// `s` as a `&'static str`, each distinct string leaked once: an [`crate::Effect`] lends its
/// coefficient names as `&[&str]`, which a value built at run time can only do from storage
/// that outlives it. Declarations are few and small, and a string declared again reuses its
/// first copy, so the memory is bounded by what was ever declared.
pub(crate) fn intern(s: &str) -> &'static str {
    static STRINGS: Mutex<BTreeSet<&'static str>> = Mutex::new(BTreeSet::new());
    let mut strings = STRINGS
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(found) = strings.get(s) {
        return found;
    }
    let leaked: &'static str = Box::leak(s.to_owned().into_boxed_str());
    strings.insert(leaked);
    leaked
}
