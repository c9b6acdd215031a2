//! A family's catalogue of effects, extended by declarations: what the effects file, a study
//! file's `[[effect]]` tables and a dataset share, whichever family they are of.
//!
//! Why a trait: each family keeps its effects in a registry of its own type (the platform's
//! builds [`crate::DynEffect`]s, the strapdown's holds places in the body frame), but every
//! reader of declarations asks the same of it: the catalogue, with these declared. Written
//! once here, a third family's registry is one `impl` beside it, not a method in each reader.

use super::EffectDeclaration;
use crate::error::DynamicsError;

/// A family's registry of effects: its catalogue, to which declarations add.
pub trait EffectCatalogue: Sized {
    /// The family's catalogue, nothing declared.
    fn catalogue() -> Self;

    /// Adds `declarations`, each checked against the effects known before it; on error
    /// nothing is added, and the error names the key (`effect[1].name`).
    fn declare(&mut self, declarations: &[EffectDeclaration]) -> Result<(), DynamicsError>;

    /// The catalogue with `declarations` added.
    ///
    /// ```
    /// use navkf_dynamics::declared::{parse_declarations, EffectCatalogue};
    /// use navkf_dynamics::Registry;
    ///
    /// let declared = parse_declarations(
    ///     r#"
    /// [[effect]]
    /// name = "drag"
    /// coefficients = [{ name = "kd", unit = "1/s", sigma = 5e-5 }]
    /// rates = [{ to = "v_x", coefficient = "kd", feature = "v_x" }]
    /// "#,
    /// )
    /// .unwrap();
    /// let registry = Registry::with_declared(&declared).unwrap();
    /// assert!(registry.names().contains(&"drag".to_string()));
    /// ```
    fn with_declared(declarations: &[EffectDeclaration]) -> Result<Self, DynamicsError> {
        let mut registry = Self::catalogue();
        registry.declare(declarations)?;
        Ok(registry)
    }
}
