//! The one study-file loader: a study file declares its kind (`[study] kind`, see
//! [`StudyKind`]), and the kind's own loader reads it, from the text read once.

use navkf_diagnose::diagnosis_study::DiagnosisStudyConfig;
use navkf_dynamics::input_file::{read_text, toml_error, TextFile};
use navkf_report::StudyKind;
use navkf_study::StudyConfig;
use std::path::Path;

/// A study file, loaded as the kind it declares.
pub enum StudyFile {
    /// A Monte Carlo study (or a sweep of one).
    MonteCarlo(Box<StudyConfig>),
    /// A diagnosis study.
    Diagnosis(Box<DiagnosisStudyConfig>),
}

/// Reads `path` (a regular file of bounded size) and loads it as the kind it declares.
pub fn load(path: &Path) -> Result<StudyFile, Box<dyn std::error::Error>> {
    let text = read_text(path, &TextFile::STUDY)?;
    let kind = StudyKind::declared(&text).map_err(|e| toml_error(path, &text, &e))?;
    Ok(match kind {
        StudyKind::MonteCarlo => {
            StudyFile::MonteCarlo(Box::new(StudyConfig::from_file_text(path, &text)?))
        }
        StudyKind::Diagnosis => {
            StudyFile::Diagnosis(Box::new(DiagnosisStudyConfig::from_file_text(path, &text)?))
        }
    })
}
