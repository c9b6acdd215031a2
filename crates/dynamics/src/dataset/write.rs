//! Writing a dataset folder, atomically and bit-exactly.
//!
//! The simulator writes datasets that are then read back through the same path as recorded
//! data, so a write followed by a read must give the same `Dataset`: every `f64` is printed in
//! Rust's shortest round-trip form (never a fixed precision). A crash or an I/O error must not
//! leave a half-written file: every file is first written in full (and synced) to a temporary
//! file in the same folder, and only when all are written are they renamed into place (a rename
//! within one folder replaces a file atomically). A failed write removes the temporary files
//! and leaves the folder as it was; only a failing rename (rare: the files are already on disk)
//! can leave some files replaced and the others old.
//!
//! `write` does not validate: it writes what it is given, and [`Dataset::read`] is the judge
//! (a NaN written here is refused on reading, with its line).

use super::{files_of, Dataset, Odometer, CONFIG_FILE, MEASUREMENTS_FILE, TRUTH_FILE};
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use std::fs;
use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};

impl Dataset {
    /// Writes the dataset into `dir` (created if needed): `inputs.csv` (a strapdown dataset's
    /// `imu.csv`, as rates), `measurements.csv`,
    /// `dataset.toml` (`[noise]` with every key, `[prior]` with what it states, `[simulation]`
    /// when there is provenance) and
    /// `truth.csv` when there is truth (a `truth.csv` left from an earlier write is removed
    /// otherwise). Existing files are replaced atomically.
    pub fn write(&self, dir: &Path) -> Result<(), DynamicsError> {
        fs::create_dir_all(dir).map_err(|source| io_error(dir, source))?;
        let mut files = vec![
            (files_of(self.model).inputs_file(), self.inputs_csv(dir)?),
            (MEASUREMENTS_FILE, self.measurements_csv(dir)?),
            (CONFIG_FILE, self.config_toml(dir)?),
        ];
        if self.truth.is_some() {
            files.push((TRUTH_FILE, self.truth_csv(dir)?));
        }

        // Stage every file; on any failure remove what was staged and leave the folder as it was.
        let mut staged: Vec<(PathBuf, PathBuf)> = Vec::with_capacity(files.len());
        for (name, bytes) in &files {
            let target = dir.join(name);
            let temp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
            if let Err(e) = write_synced(&temp, bytes) {
                let _ = fs::remove_file(&temp);
                remove_all(&staged);
                return Err(e);
            }
            staged.push((temp, target));
        }
        // Commit.
        for (i, (temp, target)) in staged.iter().enumerate() {
            if let Err(source) = fs::rename(temp, target) {
                remove_all(&staged[i..]);
                return Err(io_error(target, source));
            }
        }
        if self.truth.is_none() {
            let stale = dir.join(TRUTH_FILE);
            match fs::remove_file(&stale) {
                Err(e) if e.kind() != ErrorKind::NotFound => return Err(io_error(&stale, e)),
                _ => {}
            }
        }
        Ok(())
    }

    fn inputs_csv(&self, dir: &Path) -> Result<Vec<u8>, DynamicsError> {
        let files = files_of(self.model);
        let path = dir.join(files.inputs_file());
        let columns = files.input_columns();
        let mut w = csv_writer();
        record(&mut w, &path, columns)?;
        for s in &self.inputs {
            let used = &s.f[..columns.len() - 1];
            record(
                &mut w,
                &path,
                std::iter::once(&s.t).chain(used).copied().map(fmt_f64),
            )?;
        }
        finish(w, &path)
    }

    fn measurements_csv(&self, dir: &Path) -> Result<Vec<u8>, DynamicsError> {
        let path = dir.join(MEASUREMENTS_FILE);
        let mut w = csv_writer();
        let pair =
            |p: Option<[f64; 2]>| p.map_or([String::new(), String::new()], |p| p.map(fmt_f64));
        let files = files_of(self.model);
        record(&mut w, &path, files.measurement_columns())?;
        match files.odometer() {
            Odometer::VelocityEastNorth => {
                for m in &self.measurements {
                    let [ve, vn] = pair(m.velocity);
                    let [lat, lon] = pair(m.position_deg);
                    record(&mut w, &path, [fmt_f64(m.t), ve, vn, lat, lon])?;
                }
            }
            Odometer::ForwardSpeed => {
                for m in &self.measurements {
                    let speed = m.speed.map_or(String::new(), fmt_f64);
                    let [lat, lon] = pair(m.position_deg);
                    record(&mut w, &path, [fmt_f64(m.t), speed, lat, lon])?;
                }
            }
        }
        finish(w, &path)
    }

    fn truth_csv(&self, dir: &Path) -> Result<Vec<u8>, DynamicsError> {
        let path = dir.join(TRUTH_FILE);
        let mut w = csv_writer();
        if let Some(truth) = &self.truth {
            record(
                &mut w,
                &path,
                std::iter::once("t").chain(truth.names.iter().map(String::as_str)),
            )?;
            for (t, state) in truth.t.iter().zip(&truth.states) {
                record(
                    &mut w,
                    &path,
                    std::iter::once(*t)
                        .chain(state.iter().copied())
                        .map(fmt_f64),
                )?;
            }
        }
        finish(w, &path)
    }

    fn config_toml(&self, dir: &Path) -> Result<Vec<u8>, DynamicsError> {
        let path = dir.join(CONFIG_FILE);
        let n = &self.noise;
        let mut text = String::new();
        if self.model != ModelKind::default() {
            text.push_str(&format!("[model]\nkind = \"{}\"\n\n", self.model.name()));
        }
        if let Some(a) = &self.initial {
            text.push_str(
                "[initial]                                # attitude at the first IMU row, deg\n",
            );
            for (key, v) in [
                ("roll_deg", a.roll_deg),
                ("pitch_deg", a.pitch_deg),
                ("heading_deg", a.heading_deg),
            ] {
                text.push_str(&format!("{key} = {}\n", toml_f64(v)));
            }
            text.push('\n');
        }
        text.push_str("[noise]\n");
        for (key, value, comment) in [
            ("gyro_psd", n.gyro_psd, "q_g, rad^2/s"),
            ("accel_psd", n.accel_psd, "q_a, (m/s^2)^2/s"),
            (
                "odometer_rel",
                n.odometer_rel,
                "sigma_v = max(odometer_rel * |v|, odometer_floor)",
            ),
            ("odometer_floor", n.odometer_floor, "m/s"),
            ("gps_m", n.gps_m, "GPS position sigma, metres"),
        ] {
            let entry = format!("{key} = {}", toml_f64(value));
            text.push_str(&format!("{entry:<40} # {comment}\n"));
        }
        for (key, value, comment) in [
            ("nhc_m_s", n.nhc_m_s, "non-holonomic constraint sigma, m/s"),
            ("zupt_m_s", n.zupt_m_s, "zero-velocity update sigma, m/s"),
        ] {
            if let Some(v) = value {
                let entry = format!("{key} = {}", toml_f64(v));
                text.push_str(&format!("{entry:<40} # {comment}\n"));
            }
        }
        if !self.prior.is_empty() {
            let p = &self.prior;
            text.push_str("\n[prior]\n");
            let azimuth = files_of(self.model).heading_prior_key();
            for (key, value) in [
                ("level_rad", p.level_rad),
                (azimuth.as_str(), p.azimuth_rad),
            ] {
                if let Some(v) = value {
                    text.push_str(&format!("{key} = {}\n", toml_f64(v)));
                }
            }
            if !p.coefficients.is_empty() {
                text.push_str("\n[prior.coefficients]\n");
                for (name, v) in &p.coefficients {
                    text.push_str(&format!("{name} = {}\n", toml_f64(*v)));
                }
            }
        }
        if let Some(provenance) = &self.provenance {
            let body = toml::to_string(provenance).map_err(|e| DynamicsError::File {
                path: path.clone(),
                message: format!("cannot write [simulation]: {e}"),
            })?;
            text.push_str("\n[simulation]\n");
            text.push_str(&body);
        }
        if !self.effects.is_empty() {
            // Arrays of tables come last, so that no key above falls into one.
            #[derive(serde::Serialize)]
            struct Declared<'a> {
                effect: &'a [crate::declared::EffectDeclaration],
            }
            let body = toml::to_string(&Declared {
                effect: &self.effects,
            })
            .map_err(|e| DynamicsError::File {
                path: path.clone(),
                message: format!("cannot write [[effect]]: {e}"),
            })?;
            text.push_str("\n# Effects declared in TOML (docs/declared-effects.md).\n");
            text.push_str(&body);
        }
        Ok(text.into_bytes())
    }
}

/// `x` in a form that parses back to the same bits: Rust's shortest round-trip digits, in
/// exponent form for very small or large magnitudes (so that 1e-300 is not 300 digits long).
pub(super) fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// [`fmt_f64`] as a TOML float: TOML needs a `.` or an exponent (`3` would be an integer).
fn toml_f64(x: f64) -> String {
    let s = fmt_f64(x);
    if x.is_finite() && !s.contains(['.', 'e']) {
        s + ".0"
    } else if x.is_nan() {
        "nan".to_owned()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.to_owned()
    } else {
        s
    }
}

fn io_error(path: &Path, source: std::io::Error) -> DynamicsError {
    DynamicsError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn csv_writer() -> csv::Writer<Vec<u8>> {
    csv::WriterBuilder::new().from_writer(Vec::new())
}

fn record<I, T>(w: &mut csv::Writer<Vec<u8>>, path: &Path, cells: I) -> Result<(), DynamicsError>
where
    I: IntoIterator<Item = T>,
    T: AsRef<[u8]>,
{
    w.write_record(cells).map_err(|e| DynamicsError::File {
        path: path.to_path_buf(),
        message: format!("cannot format CSV: {e}"),
    })
}

fn finish(w: csv::Writer<Vec<u8>>, path: &Path) -> Result<Vec<u8>, DynamicsError> {
    w.into_inner().map_err(|e| DynamicsError::File {
        path: path.to_path_buf(),
        message: format!("cannot format CSV: {}", e.error()),
    })
}

/// Writes `bytes` to `path` and flushes them to disk.
fn write_synced(path: &Path, bytes: &[u8]) -> Result<(), DynamicsError> {
    let mut file = fs::File::create(path).map_err(|e| io_error(path, e))?;
    file.write_all(bytes).map_err(|e| io_error(path, e))?;
    file.sync_all().map_err(|e| io_error(path, e))
}

fn remove_all(staged: &[(PathBuf, PathBuf)]) {
    for (temp, _) in staged {
        let _ = fs::remove_file(temp);
    }
}
