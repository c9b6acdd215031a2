//! `navkf convert kitti OXTS_DIR --out DATASET`: a recording in another project's format
//! written as a navkf dataset folder (docs/data-format.md), read back before it is put in
//! place. KITTI raw OXTS is the one format so far ([`navkf_dynamics::dataset::kitti`] states
//! its frames, signs and what its values really are).

use navkf_dynamics::dataset::kitti::read_kitti;
use navkf_dynamics::dataset::Dataset;
use navkf_report::{FolderKind, ResultsDir};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The recording's format.
    #[arg(value_parser = ["kitti"])]
    format: String,
    /// The recording: for KITTI, a drive's `oxts` folder (timestamps.txt and data/).
    from: PathBuf,
    /// Folder to write: a new one, an empty one, or a dataset navkf wrote before.
    #[arg(long)]
    out: PathBuf,
    /// One odometer and GPS measurement this often, s (the filter period).
    #[arg(long, default_value_t = 1.0, value_name = "S")]
    every: f64,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    if !a.from.is_dir() {
        return Err(format!(
            "{}: not a folder; expected a KITTI drive's oxts folder (timestamps.txt, data/)",
            a.from.display()
        )
        .into());
    }
    let name = navkf_study::simulation::dataset_name(&a.out);
    let staged = ResultsDir::begin_kind(&a.out, FolderKind::Dataset, &[])?;
    let ds = read_kitti(&a.from, &name, a.every)?;
    ds.write(staged.path())?;
    // Read back before it is put in place: what the converter wrote must be a dataset navkf
    // reads (a recording's latitude beyond 90 deg, say, is refused here, naming `--out`).
    Dataset::read(staged.path()).map_err(|e| {
        let e = e.to_string().replace(
            &staged.path().display().to_string(),
            &a.out.display().to_string(),
        );
        format!("the converted recording is not a dataset navkf reads ({e}); nothing was written")
    })?;
    staged.commit()?;
    eprintln!(
        "wrote {} from KITTI {} ({} readings, {} measurements)",
        a.out.display(),
        a.from.display(),
        ds.inputs.len(),
        ds.measurements.len()
    );
    if let Some(note) = ds.provenance.as_ref().and_then(|p| p.note.as_ref()) {
        eprintln!("note: {note}");
    }
    let summary = ds.summary();
    say!("{summary}");
    for w in ds.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(())
}
