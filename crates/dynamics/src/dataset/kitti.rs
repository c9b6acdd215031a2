//! KITTI's raw OXTS recordings read as a strapdown dataset (`navkf convert kitti`).
//!
//! A KITTI raw drive holds an `oxts/` folder: `timestamps.txt` (one
//! `YYYY-MM-DD HH:MM:SS.fffffffff` line per frame) and `data/NNNNNNNNNN.txt` (one file per
//! frame, 30 space-separated values, in the order of the KITTI raw devkit's `dataformat.txt`:
//! lat, lon, alt, roll, pitch, yaw, vn, ve, vf, vl, vu, ax, ay, az, af, al, au, wx, wy, wz,
//! wf, wl, wu, posacc, velacc, navstat, numsats, posmode, velmode, orimode). The unit is an
//! OXTS RT3003 GNSS/INS recording at about 100 Hz.
//!
//! **Frames and signs.** `wx, wy, wz` and `ax, ay, az` are the rates and accelerations about
//! and along the vehicle's front, left and top axes: this project's forward-left-up body axes
//! (docs/model.md eq. (49)), as they are. The accelerations are specific forces, gravity
//! included (about `+9.8` on `az` at rest); `inspect`'s plausibility warnings say so if a
//! recording's are not. The attitude follows other conventions: KITTI's roll is positive
//! left side up (this project's right side down: the same), its pitch positive front down
//! (this project's nose up: negated), its yaw the heading from East, counter-clockwise (this
//! project's from North, clockwise: `heading = 90 deg - yaw`). The first frame's attitude
//! becomes `[initial]`.
//!
//! **What is not what it seems.** KITTI has no wheel odometer: the speed written is `vf`, the
//! RT3003's own forward velocity, and the positions are its own GNSS/INS solution, so both
//! carry the unit's filter, not independent sensors; `dataset.toml`'s `[simulation]` note
//! says so. The GPS sigma is the recording's median `posacc` (navkf's default when no frame
//! gives a positive one, and the note says so); the odometer's noise takes
//! the defaults, and the non-holonomic constraint 0.1 m/s (a car on a road).
//!
//! Measurements are taken once every `every_s` seconds (the filter period): the first frame
//! at or after each multiple of it.

use super::{Dataset, InitialAttitude, InputSample, Measurement, Provenance};
use crate::error::DynamicsError;
use crate::input_file::{read_text, TextFile};
use crate::model_kind::ModelKind;
use crate::noise::NoiseConfig;
use crate::prior::PlatformPrior;
use std::path::Path;

/// The 30 fields of a frame, by name.
pub const OXTS_FIELDS: [&str; 30] = [
    "lat", "lon", "alt", "roll", "pitch", "yaw", "vn", "ve", "vf", "vl", "vu", "ax", "ay", "az",
    "af", "al", "au", "wx", "wy", "wz", "wf", "wl", "wu", "posacc", "velacc", "navstat", "numsats",
    "posmode", "velmode", "orimode",
];

/// The constraint's sigma a converted car recording states, m/s.
const CAR_NHC_M_S: f64 = 0.1;

fn field(name: &str) -> usize {
    OXTS_FIELDS
        .iter()
        .position(|f| *f == name)
        .expect("a KITTI field")
}

fn data_error(path: &Path, line: usize, column: &str, message: String) -> DynamicsError {
    DynamicsError::Data {
        path: path.to_path_buf(),
        line,
        column: column.to_string(),
        message,
    }
}

/// Whole seconds since 1970-01-01 and the fraction of a `YYYY-MM-DD HH:MM:SS.fffffffff`
/// stamp, or what is wrong (kept apart so that a difference of stamps keeps nanoseconds: as
/// one `f64` since 1970 it would keep a quarter of a microsecond).
fn stamp_seconds(s: &str) -> Result<(i64, f64), String> {
    let expected = "expected `YYYY-MM-DD HH:MM:SS.fffffffff`";
    let (date, time) = s
        .trim()
        .split_once(' ')
        .ok_or_else(|| format!("`{s}`: {expected}"))?;
    let d: Vec<i64> = date
        .split('-')
        .map(|p| p.parse::<i64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}`: {expected}"))?;
    let hms: Vec<&str> = time.split(':').collect();
    if d.len() != 3 || hms.len() != 3 || !(1..=12).contains(&d[1]) || !(1..=31).contains(&d[2]) {
        return Err(format!("`{s}`: {expected}"));
    }
    // A year any recording can have (the days since 1970 of a wild one overflow).
    if !(1900..=9999).contains(&d[0]) {
        return Err(format!("`{s}`: year {}: expected 1900 to 9999", d[0]));
    }
    let (h, m): (i64, i64) = match (hms[0].parse(), hms[1].parse()) {
        (Ok(h), Ok(m)) if (0..24).contains(&h) && (0..60).contains(&m) => (h, m),
        _ => return Err(format!("`{s}`: {expected}")),
    };
    let sec: f64 = hms[2]
        .parse()
        .ok()
        .filter(|v: &f64| (0.0..61.0).contains(v))
        .ok_or_else(|| format!("`{s}`: {expected}"))?;
    // Days since 1970-01-01 of a proleptic Gregorian date.
    let (y, mo) = if d[1] <= 2 {
        (d[0] - 1, d[1] + 9)
    } else {
        (d[0], d[1] - 3)
    };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * mo + 2) / 5 + d[2] - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    let whole = sec.floor();
    Ok((
        days * 86_400 + h * 3600 + m * 60 + whole as i64,
        sec - whole,
    ))
}

/// Reads the KITTI raw `oxts` folder `dir` as a strapdown dataset named `name` (module
/// documentation), with a measurement every `every_s` seconds.
pub fn read_kitti(dir: &Path, name: &str, every_s: f64) -> Result<Dataset, DynamicsError> {
    if !(every_s.is_finite() && every_s > 0.0) {
        return Err(DynamicsError::Config {
            key: "--every".into(),
            message: format!("{every_s}: expected a period > 0 s"),
        });
    }
    let stamps_path = dir.join("timestamps.txt");
    let stamps = read_text(&stamps_path, &TextFile::KITTI_STAMPS)?;
    let mut t = Vec::new();
    let mut first = None;
    for (i, line) in stamps.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let s = stamp_seconds(line).map_err(|m| data_error(&stamps_path, i + 1, "-", m))?;
        let (w0, f0) = *first.get_or_insert(s);
        let ti = (s.0 - w0) as f64 + (s.1 - f0);
        if let Some(&(tp, lp)) = t.last() {
            if ti <= tp {
                return Err(data_error(
                    &stamps_path,
                    i + 1,
                    "-",
                    format!(
                        "not after line {lp}; expected times strictly increasing (a KITTI \
                         drive with a repeated or backward stamp needs it mended first)"
                    ),
                ));
            }
        }
        t.push((ti, i + 1));
    }
    if t.len() < 3 {
        return Err(data_error(
            &stamps_path,
            t.len() + 1,
            "-",
            format!("{} frame(s); expected at least 3", t.len()),
        ));
    }
    // Every frame file has its stamp: a frame past the last stamp would be left out unsaid.
    let data = dir.join("data");
    let files = std::fs::read_dir(&data)
        .map_err(|source| DynamicsError::Io {
            path: data.clone(),
            source,
        })?
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "txt"))
        .count();
    if files != t.len() {
        return Err(DynamicsError::File {
            path: data,
            message: format!(
                "{files} frame files (*.txt) for the {} stamps of timestamps.txt; expected one \
                 frame file per stamp, 0000000000.txt on",
                t.len()
            ),
        });
    }
    crate::memory::check(
        "timestamps.txt",
        "the KITTI frames",
        t.len() as f64,
        std::mem::size_of::<[f64; 30]>() + std::mem::size_of::<InputSample>(),
    )?;
    let frames: Vec<[f64; 30]> = (0..t.len())
        .map(|k| read_frame(&dir.join("data").join(format!("{k:010}.txt"))))
        .collect::<Result<_, _>>()?;
    let f = |k: usize, name: &str| frames[k][field(name)];
    let inputs = (0..frames.len())
        .map(|k| InputSample {
            t: t[k].0,
            f: ["wx", "wy", "wz", "ax", "ay", "az"].map(|n| f(k, n)),
        })
        .collect();
    let mut measurements = Vec::new();
    let mut next = every_s;
    for (k, (tk, _)) in t.iter().enumerate() {
        if *tk + 1e-9 < next {
            continue;
        }
        measurements.push(Measurement {
            t: *tk,
            velocity: None,
            speed: Some(f(k, "vf")),
            nhc: None,
            zupt: None,
            position_deg: Some([f(k, "lat"), f(k, "lon")]),
        });
        next = ((tk / every_s).floor() + 1.0) * every_s;
    }
    if measurements.is_empty() {
        let last = t.last().map_or(0.0, |l| l.0);
        return Err(DynamicsError::Config {
            key: "--every".into(),
            message: format!(
                "{every_s} s: no measurement, the drive lasting {last:.3} s; expected a period \
                 shorter than the drive"
            ),
        });
    }
    let mut posacc: Vec<f64> = (0..frames.len())
        .map(|k| f(k, "posacc"))
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    posacc.sort_by(f64::total_cmp);
    let (gps_m, gps_words) = match posacc.get(posacc.len() / 2) {
        Some(&median) => (median, "gps_m is the median posacc"),
        None => (
            NoiseConfig::default().gps_m,
            "gps_m is navkf's default, no frame giving a positive posacc",
        ),
    };
    Ok(Dataset {
        name: name.to_string(),
        inputs,
        measurements,
        noise: NoiseConfig {
            gps_m,
            nhc_m_s: Some(CAR_NHC_M_S),
            ..NoiseConfig::default()
        },
        noise_stated: true,
        prior: PlatformPrior::default(),
        provenance: Some(Provenance {
            seed: None,
            run: None,
            effects: Vec::new(),
            note: Some(format!(
                "converted from KITTI raw OXTS ({}): speed is the RT3003's own forward \
                 velocity (vf), not a wheel odometer, and the positions its GNSS/INS solution; \
                 {gps_words}; the rest are navkf's defaults",
                dir.display()
            )),
        }),
        truth: None,
        model: ModelKind::Strapdown,
        initial: Some(InitialAttitude {
            roll_deg: f(0, "roll").to_degrees(),
            pitch_deg: -f(0, "pitch").to_degrees(),
            heading_deg: 90.0 - f(0, "yaw").to_degrees(),
        }),
        effects: Vec::new(),
    })
}

/// One frame's 30 values; errors name the file, line 1 and the field.
fn read_frame(path: &Path) -> Result<[f64; 30], DynamicsError> {
    let text = read_text(path, &TextFile::KITTI_FRAME)?;
    let cells: Vec<&str> = text.split_whitespace().collect();
    if cells.len() != OXTS_FIELDS.len() {
        return Err(data_error(
            path,
            1,
            OXTS_FIELDS.get(cells.len()).copied().unwrap_or("-"),
            format!(
                "{} values; expected the 30 of a KITTI OXTS frame ({})",
                cells.len(),
                OXTS_FIELDS.join(" ")
            ),
        ));
    }
    let mut out = [0.0; 30];
    for (i, (cell, v)) in cells.iter().zip(out.iter_mut()).enumerate() {
        *v = cell
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                data_error(
                    path,
                    1,
                    OXTS_FIELDS[i],
                    format!("`{cell}` is not a finite number"),
                )
            })?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::stamp_seconds;

    #[test]
    fn stamps_count_seconds_across_midnight_and_month_ends() {
        let a = stamp_seconds("2011-09-30 23:59:59.500000001").unwrap();
        let b = stamp_seconds("2011-10-01 00:00:00.250000000").unwrap();
        assert_eq!(b.0 - a.0, 1);
        assert!(((b.0 - a.0) as f64 + (b.1 - a.1) - 0.749999999).abs() < 1e-12);
        assert_eq!(stamp_seconds("1970-01-01 00:00:01.0"), Ok((1, 0.0)));
        assert!(stamp_seconds("2011-13-01 00:00:00.0").is_err());
        assert!(stamp_seconds("13:02:25.964389445").is_err());
        // A year whose seconds since 1970 overflowed.
        let e = stamp_seconds("99999999999999-01-01 00:00:00.0").unwrap_err();
        assert!(e.contains("expected 1900 to 9999"), "{e}");
    }
}
