//! An effects file as a command or the Python package takes it (`--effects-file`,
//! `navkf.diagnose(effects_file=...)`): its declarations, the model family they belong to, and
//! the path that every refusal names.
//!
//! Why a type: the same file reaches `effects`, `simulate`, `diagnose` and the Python
//! package, and each must refuse it the same way: checked against its family's catalogue when
//! read, refused with both families named when the dataset or the `--model` is of the other,
//! and any later clash (an effect that `dataset.toml` declares otherwise) reported with this
//! file's name, not as a bare key.

use super::{read_declarations, EffectCatalogue, EffectDeclaration};
use crate::dataset::files_of;
use crate::dataset::Dataset;
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use crate::Registry;
use std::path::{Path, PathBuf};

/// The declarations of one effects file, checked against their family's catalogue.
#[derive(Debug, Clone)]
pub struct DeclaredFile {
    path: PathBuf,
    family: ModelKind,
    declarations: Vec<EffectDeclaration>,
}

impl DeclaredFile {
    /// Reads `path` and checks its declarations against the catalogue of their family: the
    /// first other than the default whose terms a declaration states (the strapdown's
    /// `places`; [`crate::dataset::FamilyFiles::states_own_terms`]), the default family's
    /// otherwise. A file mixing two families' terms is refused by the check of the one
    /// found, at the key of the first term of the other.
    pub fn read(path: &Path) -> Result<DeclaredFile, DynamicsError> {
        let declarations = read_declarations(path)?;
        let states = |kind: ModelKind| {
            let files = files_of(kind);
            declarations.iter().any(|d| files.states_own_terms(d))
        };
        let family = ModelKind::ALL
            .into_iter()
            .find(|&kind| kind != ModelKind::default() && states(kind))
            .unwrap_or_default();
        let file = DeclaredFile {
            path: path.to_path_buf(),
            family,
            declarations,
        };
        files_of(family)
            .declare(&mut Registry::catalogue(), &file.declarations)
            .map_err(|e| file.locate(e))?;
        Ok(file)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The family its effects belong to.
    pub fn family(&self) -> ModelKind {
        self.family
    }

    /// Its declarations, in the file's order.
    pub fn declarations(&self) -> &[EffectDeclaration] {
        &self.declarations
    }

    /// The catalogue of a family ([`Registry`],
    /// [`StrapdownRegistry`](crate::strapdown::effects::StrapdownRegistry)) with these effects
    /// declared; an error names this file and the key.
    pub fn registry<R: EffectCatalogue>(&self) -> Result<R, DynamicsError> {
        R::with_declared(&self.declarations).map_err(|e| self.locate(e))
    }

    /// Refuses the file unless its effects are of `family`, the family of `what` (`dataset
    /// `drive``, `the model simulated (--model)`), naming the file and both families.
    pub fn expect_family(&self, family: ModelKind, what: &str) -> Result<(), DynamicsError> {
        if self.family == family {
            return Ok(());
        }
        Err(DynamicsError::File {
            path: self.path.clone(),
            message: format!(
                "declares {} effects ({}); {what} is a {} one; expected a file of {} effects",
                self.family.name(),
                crate::dataset::files_of(self.family).declaration_terms(),
                family.name(),
                family.name()
            ),
        })
    }

    /// Reads the dataset folder `dir` with `file`'s effects known, so that a platform
    /// dataset's `[prior.coefficients]` and truth may name their coefficients, and refuses a
    /// file of the other family than the dataset's. When the dataset reads without the file
    /// but not with it, the two declare an effect differently: the refusal names the file too.
    pub fn read_dataset(file: Option<&DeclaredFile>, dir: &Path) -> Result<Dataset, DynamicsError> {
        let Some(file) = file else {
            return Dataset::read(dir);
        };
        let ds = if file.family.is_platform() {
            Dataset::read_with(dir, &file.registry::<Registry>()?).map_err(|e| {
                if Dataset::read(dir).is_ok() {
                    DynamicsError::File {
                        path: file.path.clone(),
                        message: format!("its effects clash with the dataset's: {e}"),
                    }
                } else {
                    e
                }
            })?
        } else {
            Dataset::read(dir)?
        };
        file.expect_family(ds.model, &format!("dataset `{}`", ds.name))?;
        Ok(ds)
    }

    /// An error of declaring these effects (into a registry that already holds others, such
    /// as a dataset's), with this file's path: `FILE: effect[1].name: ...`.
    pub fn locate(&self, e: DynamicsError) -> DynamicsError {
        let message = match e {
            DynamicsError::Config { key, message } => format!("{key}: {message}"),
            DynamicsError::Effect(message) => message,
            located @ (DynamicsError::Data { .. }
            | DynamicsError::File { .. }
            | DynamicsError::Toml { .. }
            | DynamicsError::Io { .. }) => return located,
        };
        DynamicsError::File {
            path: self.path.clone(),
            message,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strapdown::effects::StrapdownRegistry;

    /// A fresh folder of one test's files, removed when the test ends, passed or failed: the
    /// tests must not litter /tmp.
    struct Scratch(PathBuf);

    impl Scratch {
        fn new(test: &str) -> Scratch {
            let dir = std::env::temp_dir()
                .join(format!("navkf-effects-file-{test}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            Scratch(dir)
        }

        /// Writes `text` to the file `name` in the folder; returns its path.
        fn file(&self, name: &str, text: &str) -> PathBuf {
            let path = self.0.join(name);
            std::fs::write(&path, text).unwrap();
            path
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    const DRAG: &str = r#"
[[effect]]
name = "drag"
coefficients = [{ name = "kd", unit = "1/s", sigma = 5e-5 }]
rates = [{ to = "v_x", coefficient = "kd", feature = "v_x" }]
"#;

    const SKEW: &str = r#"
[[effect]]
name = "skew"
coefficients = [{ name = "n_axy", unit = "rad", sigma = 2e-3 }]
places = [{ coefficient = "n_axy", place = "E_a[x][y]" }]
"#;

    #[test]
    fn a_file_is_of_the_family_its_declarations_say() {
        let dir = Scratch::new("family");
        let drag = DeclaredFile::read(&dir.file("drag.toml", DRAG)).unwrap();
        assert_eq!(drag.family(), ModelKind::Platform);
        assert!(drag.registry::<Registry>().unwrap().build("drag").is_ok());
        let skew = DeclaredFile::read(&dir.file("skew.toml", SKEW)).unwrap();
        assert_eq!(skew.family(), ModelKind::Strapdown);
        assert!(skew
            .registry::<StrapdownRegistry>()
            .unwrap()
            .get("skew")
            .is_ok());
        let refused = skew
            .expect_family(ModelKind::Platform, "dataset `drive`")
            .unwrap_err()
            .to_string();
        assert!(
            refused.contains("skew.toml")
                && refused.contains("declares strapdown effects")
                && refused.contains("dataset `drive` is a platform one"),
            "{refused}"
        );
        assert!(drag.expect_family(ModelKind::Platform, "x").is_ok());
    }

    #[test]
    fn refusals_name_the_file_and_the_key() {
        let dir = Scratch::new("refusals");
        let mixed = dir.file("mixed.toml", &format!("{SKEW}\n{}", DRAG));
        let err = DeclaredFile::read(&mixed).unwrap_err().to_string();
        assert!(err.starts_with(&mixed.display().to_string()), "{err}");
        assert!(err.contains("effect[1]"), "{err}");
        // A clash with an effect declared elsewhere under the same name names this file.
        let skew = DeclaredFile::read(&dir.file("skew2.toml", SKEW)).unwrap();
        let mut registry = StrapdownRegistry::catalogue();
        let mut other = skew.declarations().to_vec();
        other[0].coefficients[0].sigma = 1e-3;
        registry.declare(&other).unwrap();
        let clash = registry
            .declare(skew.declarations())
            .map_err(|e| skew.locate(e))
            .unwrap_err()
            .to_string();
        assert!(
            clash.starts_with(&skew.path().display().to_string()) && clash.contains("skew"),
            "{clash}"
        );
    }
}
