//! Reading a dataset folder, with validation.
//!
//! The files come from users (recorded or simulated elsewhere), so a mistake in them must be
//! fixable without guessing: every error names the file, the 1-based line (the header is
//! line 1), the column and what was expected. Nothing here panics on user input. The checks
//! are the ones of `docs/data-format.md`: exact headers, one cell per column, finite
//! numbers, strictly increasing times, measurements inside the inputs' span, plausible
//! latitude/longitude in degrees, sensor pairs either complete or empty.

use super::{
    Dataset, InputSample, Measurement, Provenance, Truth, CONFIG_FILE, INPUTS_FILE, INPUT_COLUMNS,
    MEASUREMENTS_FILE, MEASUREMENT_COLUMNS, TRUTH_FILE,
};
use crate::earth::{meridian_radius, prime_vertical_radius};
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::input_file::{
    check_regular, other_encoding, printable, read_text, toml_error, LineLimit, LineTooLong,
    TextFile, CSV_LINE_MAX_BYTES,
};
use crate::noise::NoiseConfig;
use crate::prior::PlatformPrior;
use crate::state::{BASE_NAMES, NAV_DIM};
use serde::Deserialize;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

impl Dataset {
    /// Reads and validates the dataset folder `dir` (`docs/data-format.md`): `inputs.csv` and
    /// `measurements.csv` (required), `dataset.toml` and `truth.csv` (optional). The name is
    /// the folder's final path component. Coefficient names in `[prior.coefficients]` must be
    /// base coefficients or coefficients of the catalogue's effects.
    pub fn read(dir: &Path) -> Result<Dataset, DynamicsError> {
        Self::read_with(dir, &Registry::catalogue())
    }

    /// [`Dataset::read`], knowing the coefficients of `registry`'s effects (a user's own
    /// effects among them) for `[prior.coefficients]`.
    pub fn read_with(dir: &Path, registry: &Registry) -> Result<Dataset, DynamicsError> {
        if !dir.is_dir() {
            return Err(DynamicsError::File {
                path: dir.to_path_buf(),
                message: format!(
                    "not a folder; expected a dataset folder holding {INPUTS_FILE} and \
                     {MEASUREMENTS_FILE}"
                ),
            });
        }
        let inputs = read_inputs(&dir.join(INPUTS_FILE))?;
        let measurements = read_measurements(&dir.join(MEASUREMENTS_FILE), &inputs)?;
        let config_path = dir.join(CONFIG_FILE);
        let config = if exists(&config_path)? {
            read_config(&config_path, &known_coefficients(registry))?
        } else {
            ConfigFile::default()
        };
        let truth_path = dir.join(TRUTH_FILE);
        let truth = if exists(&truth_path)? {
            let mut known: Vec<String> = BASE_NAMES.iter().map(|s| s.to_string()).collect();
            known.extend(known_coefficients(registry));
            Some(read_truth(&truth_path, &known, &inputs, &measurements)?)
        } else {
            None
        };
        Ok(Dataset {
            name: folder_name(dir),
            inputs,
            measurements,
            noise: config.noise.unwrap_or_default(),
            noise_stated: config.noise.is_some(),
            prior: config.prior,
            provenance: config.simulation,
            truth,
        })
    }
}

/// The folder's final component; for paths like `.` the canonical path's.
fn folder_name(dir: &Path) -> String {
    let named = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    named(dir)
        .or_else(|| dir.canonicalize().ok().and_then(|p| named(&p)))
        .unwrap_or_else(|| "dataset".to_owned())
}

/// Whether an optional file is there (an I/O failure other than "not found" is an error).
fn exists(path: &Path) -> Result<bool, DynamicsError> {
    match std::fs::metadata(path) {
        Ok(_) => Ok(true),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(false),
        Err(source) => Err(DynamicsError::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

fn data_error(path: &Path, line: usize, column: &str, message: String) -> DynamicsError {
    DynamicsError::Data {
        path: path.to_path_buf(),
        line,
        column: printable(column),
        message: printable(&message),
    }
}

/// One CSV line: its 1-based line number and its cells, trimmed of surrounding blanks.
#[derive(Clone)]
struct Row {
    line: usize,
    cells: Vec<String>,
}

/// A CSV file read as a stream: its header row, then one data row at a time, so that an
/// error on line 2 is reported before the rest is read, and memory holds only what the caller
/// keeps of each row.
struct Table {
    path: PathBuf,
    header: Row,
    reader: CsvReader,
    record: csv::ByteRecord,
    /// Line of the last row read (the header's before any).
    last_line: usize,
}

impl Table {
    /// The line just after the last row read: where a missing row was expected.
    fn next_line(&self) -> usize {
        self.last_line + 1
    }

    /// The next data row, or `None` at the end of the file.
    fn next_row(&mut self) -> Result<Option<Row>, DynamicsError> {
        let row = read_row(
            &self.path,
            &mut self.reader,
            &mut self.record,
            self.last_line,
        )?;
        if let Some(r) = &row {
            self.last_line = r.line;
        }
        Ok(row)
    }
}

/// The CSV parser over a file whose lines are at most [`CSV_LINE_MAX_BYTES`].
type CsvReader = csv::Reader<LineLimit<std::fs::File>>;

/// Opens a CSV file and reads its header row, without interpreting it. `flexible` so that
/// rows of the wrong length reach us and are reported with their column; bytes that are not
/// UTF-8 become U+FFFD and so fail as "not a number" or as a wrong column name, with their
/// line. Anything but a regular file (a device such as `/dev/zero`, a FIFO, a folder) is
/// refused before opening: it could hang or never end. A line longer than
/// [`CSV_LINE_MAX_BYTES`] is refused, with its number, before it is buffered whole.
fn read_table(path: &Path, expected_header: &str) -> Result<Table, DynamicsError> {
    let not_found = |source: std::io::Error| {
        if source.kind() == ErrorKind::NotFound {
            DynamicsError::File {
                path: path.to_path_buf(),
                message: format!(
                    "not found; a dataset folder needs it, header `{expected_header}`"
                ),
            }
        } else {
            DynamicsError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    };
    let what = format!("a CSV file with the header `{expected_header}`");
    check_regular(path, &what).map_err(|e| match e {
        DynamicsError::Io { source, .. } => not_found(source),
        other => other,
    })?;
    let mut file = std::fs::File::open(path).map_err(not_found)?;
    if let Some(encoding) = file_encoding(&mut file).map_err(not_found)? {
        return Err(DynamicsError::File {
            path: path.to_path_buf(),
            message: format!(
                "is {encoding}; expected UTF-8 (or plain ASCII) text: save it as UTF-8 CSV"
            ),
        });
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(LineLimit::new(file, CSV_LINE_MAX_BYTES));
    let mut record = csv::ByteRecord::new();
    let Some(mut header) = read_row(path, &mut reader, &mut record, 0)? else {
        return Err(data_error(
            path,
            1,
            "-",
            format!("empty file; expected the header `{expected_header}`"),
        ));
    };
    // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first name.
    if let Some(first) = header.cells.first_mut() {
        if let Some(rest) = first.strip_prefix('\u{feff}') {
            *first = rest.trim().to_owned();
        }
    }
    Ok(Table {
        path: path.to_path_buf(),
        last_line: header.line,
        header,
        reader,
        record,
    })
}

/// The encoding of `file` when it is UTF-16 or UTF-32 ([`other_encoding`]), which would
/// otherwise read as garbled column names; the file is left at its start.
fn file_encoding(file: &mut std::fs::File) -> std::io::Result<Option<&'static str>> {
    use std::io::{Read, Seek};
    let mut head = [0u8; 4];
    let mut n = 0;
    while n < head.len() {
        match file.read(&mut head[n..])? {
            0 => break,
            k => n += k,
        }
    }
    file.rewind()?;
    Ok(other_encoding(&head[..n]))
}

/// One row of `reader`, its cells trimmed; `previous` is the line of the row before.
fn read_row(
    path: &Path,
    reader: &mut CsvReader,
    record: &mut csv::ByteRecord,
    previous: usize,
) -> Result<Option<Row>, DynamicsError> {
    match reader.read_byte_record(record) {
        Ok(true) => {}
        Ok(false) => return Ok(None),
        Err(e) => return Err(csv_error(path, e)),
    }
    let line = record.position().map_or(previous + 1, |p| {
        usize::try_from(p.line()).unwrap_or(usize::MAX)
    });
    let cells = record
        .iter()
        .map(|b| String::from_utf8_lossy(b).trim().to_owned())
        .collect();
    Ok(Some(Row { line, cells }))
}

fn csv_error(path: &Path, e: csv::Error) -> DynamicsError {
    let line = e
        .position()
        .map_or(0, |p| usize::try_from(p.line()).unwrap_or(usize::MAX));
    let message = e.to_string();
    match e.into_kind() {
        csv::ErrorKind::Io(source) if LineTooLong::inside(&source).is_some() => {
            let line = LineTooLong::inside(&source)
                .map_or(line, |t| usize::try_from(t.line).unwrap_or(usize::MAX));
            data_error(
                path,
                line,
                "-",
                format!(
                    "line longer than {} KiB (refused before reading it whole); expected CSV \
                     rows of a time and a few numbers (the widest, truth.csv's with every \
                     effect, is under 1 KiB)",
                    CSV_LINE_MAX_BYTES / 1024
                ),
            )
        }
        csv::ErrorKind::Io(source) => DynamicsError::Io {
            path: path.to_path_buf(),
            source,
        },
        _ => data_error(path, line, "-", format!("unreadable CSV: {message}")),
    }
}

/// Checks that the header is exactly `expected`, naming the missing, unexpected or misplaced
/// column.
fn check_header(table: &Table, expected: &[&str]) -> Result<(), DynamicsError> {
    let found: Vec<&str> = table.header.cells.iter().map(String::as_str).collect();
    if found == expected {
        return Ok(());
    }
    let want = expected.join(",");
    let got = found.join(",");
    let missing: Vec<&str> = expected
        .iter()
        .copied()
        .filter(|c| !found.contains(c))
        .collect();
    let unexpected: Vec<&str> = found
        .iter()
        .copied()
        .filter(|c| !expected.contains(c))
        .collect();
    let (column, what) = if let Some(&m) = missing.first() {
        let instead = unexpected
            .first()
            .map(|u| format!(" (found unexpected column `{u}`: misnamed?)"))
            .unwrap_or_default();
        (m, format!("missing column `{m}`{instead}"))
    } else if let Some(&u) = unexpected.first() {
        (u, format!("unexpected column `{u}`"))
    } else {
        // Same names, but repeated or in another order: name the first misplaced one.
        let i = expected
            .iter()
            .zip(&found)
            .position(|(e, f)| e != f)
            .unwrap_or(expected.len().min(found.len()));
        let at = found.get(i).copied().unwrap_or("");
        let want_here = expected.get(i).copied().unwrap_or("nothing");
        (
            want_here,
            format!("column {} is `{at}`, expected `{want_here}` there", i + 1),
        )
    };
    Err(data_error(
        &table.path,
        table.header.line,
        column,
        format!("{what}; expected the header `{want}`, found `{got}`"),
    ))
}

/// The cells of one row, with the names of their columns.
struct Cells<'a> {
    path: &'a Path,
    columns: &'a [&'a str],
    row: &'a Row,
}

impl Cells<'_> {
    fn error(&self, column: &str, message: String) -> DynamicsError {
        data_error(self.path, self.row.line, column, message)
    }

    /// One cell per column.
    fn check_count(&self) -> Result<(), DynamicsError> {
        let (n, want) = (self.row.cells.len(), self.columns.len());
        if n == want {
            return Ok(());
        }
        let column = self.columns.get(n).copied().unwrap_or("-");
        let what = if n < want {
            "missing cells"
        } else {
            "too many cells"
        };
        Err(self.error(
            column,
            format!(
                "{what}: {n} cells, expected {want} ({})",
                self.columns.join(",")
            ),
        ))
    }

    /// Cell `i` as a finite number, or `None` when empty.
    fn optional(&self, i: usize) -> Result<Option<f64>, DynamicsError> {
        let column = self.columns.get(i).copied().unwrap_or("-");
        let cell = self.row.cells.get(i).map_or("", String::as_str);
        if cell.is_empty() {
            return Ok(None);
        }
        match cell.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            Ok(_) => Err(self.error(
                column,
                format!("`{cell}` is not finite; expected a finite number"),
            )),
            Err(_) => Err(self.error(
                column,
                format!("`{cell}` is not a number; expected a finite number"),
            )),
        }
    }

    /// Cell `i` as a finite number; an empty cell is an error.
    fn required(&self, i: usize) -> Result<f64, DynamicsError> {
        self.optional(i)?.ok_or_else(|| {
            self.error(
                self.columns.get(i).copied().unwrap_or("-"),
                "empty cell; expected a finite number".to_owned(),
            )
        })
    }
}

/// Checks `t` against the previous row's time `(t, line)` and remembers it.
fn check_increasing(
    path: &Path,
    line: usize,
    t: f64,
    previous: &mut Option<(f64, usize)>,
) -> Result<(), DynamicsError> {
    if let Some((tp, lp)) = *previous {
        if t <= tp {
            return Err(data_error(
                path,
                line,
                "t",
                format!(
                    "t = {t} is not after t = {tp} on line {lp}; expected times strictly \
                     increasing"
                ),
            ));
        }
    }
    *previous = Some((t, line));
    Ok(())
}

fn read_inputs(path: &Path) -> Result<Vec<InputSample>, DynamicsError> {
    let mut table = read_table(path, &INPUT_COLUMNS.join(","))?;
    check_header(&table, &INPUT_COLUMNS)?;
    let mut inputs = Vec::new();
    let mut previous = None;
    while let Some(row) = table.next_row()? {
        let cells = Cells {
            path,
            columns: &INPUT_COLUMNS,
            row: &row,
        };
        cells.check_count()?;
        let t = cells.required(0)?;
        let f = [cells.required(1)?, cells.required(2)?, cells.required(3)?];
        check_increasing(path, row.line, t, &mut previous)?;
        inputs.push(InputSample { t, f });
    }
    if inputs.len() < 2 {
        return Err(data_error(
            path,
            table.next_line(),
            "-",
            format!(
                "{} data row(s); expected at least 2 input rows (the filter needs an interval)",
                inputs.len()
            ),
        ));
    }
    Ok(inputs)
}

fn read_measurements(
    path: &Path,
    inputs: &[InputSample],
) -> Result<Vec<Measurement>, DynamicsError> {
    let mut table = read_table(path, &MEASUREMENT_COLUMNS.join(","))?;
    check_header(&table, &MEASUREMENT_COLUMNS)?;
    let mut measurements = Vec::new();
    let mut lines = Vec::new();
    let mut previous = None;
    while let Some(row) = table.next_row()? {
        let cells = Cells {
            path,
            columns: &MEASUREMENT_COLUMNS,
            row: &row,
        };
        cells.check_count()?;
        let t = cells.required(0)?;
        let v = [cells.optional(1)?, cells.optional(2)?];
        let p = [cells.optional(3)?, cells.optional(4)?];
        let velocity = pair(&cells, v, [1, 2], "odometer")?;
        let position_deg = pair(&cells, p, [3, 4], "GPS")?;
        if velocity.is_none() && position_deg.is_none() {
            return Err(cells.error(
                "v_e,v_n,lat_deg,lon_deg",
                "all four cells empty: the row says nothing; expected an odometer pair \
                 (v_e,v_n), a GPS pair (lat_deg,lon_deg) or both"
                    .to_owned(),
            ));
        }
        if let Some([lat, lon]) = position_deg {
            if lat.abs() > 90.0 {
                return Err(cells.error(
                    "lat_deg",
                    format!("latitude {lat} is outside [-90, 90]; expected degrees"),
                ));
            }
            if lon.abs() > 360.0 {
                return Err(cells.error(
                    "lon_deg",
                    format!("longitude {lon} is outside [-360, 360]; expected degrees"),
                ));
            }
        }
        check_increasing(path, row.line, t, &mut previous)?;
        measurements.push(Measurement {
            t,
            velocity,
            position_deg,
        });
        lines.push(row.line);
    }
    if measurements.is_empty() {
        return Err(data_error(
            path,
            table.next_line(),
            "-",
            "no measurement rows; expected at least one row after the header".to_owned(),
        ));
    }
    // `inputs` has at least two samples, strictly increasing (read_inputs).
    let (t0, t1) = match (inputs.first(), inputs.last()) {
        (Some(a), Some(b)) => (a.t, b.t),
        _ => (f64::NEG_INFINITY, f64::INFINITY),
    };
    for (m, &line) in measurements.iter().zip(&lines) {
        if m.t < t0 || m.t > t1 {
            return Err(data_error(
                path,
                line,
                "t",
                format!(
                    "t = {} is outside the span of {INPUTS_FILE}; expected {t0} <= t <= {t1}",
                    m.t
                ),
            ));
        }
    }
    check_input_rate(path, &inputs_path(path), inputs, &measurements)?;
    if let Some((line, why)) = looks_like_radians(&measurements, &lines) {
        return Err(data_error(
            path,
            line,
            "lat_deg",
            format!(
                "lat_deg and lon_deg look like radians (from this first GPS row on, every \
                 |lat_deg| < 1.6 and |lon_deg| <= 2*pi, and {why}); expected degrees: \
                 multiply radians by 180/pi"
            ),
        ));
    }
    unwrap_longitude(&mut measurements);
    Ok(measurements)
}

/// `inputs.csv` beside `measurements`.
fn inputs_path(measurements: &Path) -> PathBuf {
    measurements.with_file_name(INPUTS_FILE)
}

/// Largest change of longitude (deg) between consecutive fixes that an antimeridian
/// crossing may hide: over 1000 km at the equator, 190 km at 80 deg.
const CROSSING_MAX_DEG: f64 = 10.0;

/// Makes a track that crosses the antimeridian (longitude jumping between +180 and -180)
/// one continuous track: a fix whose longitude jumps by more than half a turn from the
/// previous one, but lies within [`CROSSING_MAX_DEG`] of it once moved by whole turns, is
/// moved by those turns. The filters, `inspect`'s extent and the figures then all see the
/// vehicle drive on, not jump 40,000 km. Other fixes keep their value to the bit.
fn unwrap_longitude(measurements: &mut [Measurement]) {
    let mut previous: Option<f64> = None;
    for m in measurements.iter_mut() {
        if let Some([_, lon]) = m.position_deg.as_mut() {
            if let Some(p) = previous {
                let turns = ((p - *lon) / 360.0).round();
                let moved = *lon + 360.0 * turns;
                if turns != 0.0 && (moved - p).abs() <= CROSSING_MAX_DEG {
                    *lon = moved;
                }
            }
            previous = Some(*lon);
        }
    }
}

/// Refuses inputs recorded less often than the measurements: the filter integrates the
/// specific force between updates, so an input slower than the updates leaves intervals
/// with nothing to integrate (or one sample held for several updates). Compared as median
/// intervals, so gaps and jitter do not trip it.
fn check_input_rate(
    measurements_path: &Path,
    inputs_path: &Path,
    inputs: &[InputSample],
    measurements: &[Measurement],
) -> Result<(), DynamicsError> {
    use super::plausibility::median_interval;
    let (Some(di), Some(dm)) = (
        median_interval(inputs.iter().map(|i| i.t)),
        median_interval(measurements.iter().map(|m| m.t)),
    ) else {
        return Ok(());
    };
    if di > 1.5 * dm {
        return Err(data_error(
            inputs_path,
            3,
            "t",
            format!(
                "inputs every {di} s (median interval) are slower than the measurements of \
                 {} every {dm} s; expected inputs at least as often as the measurements (the \
                 filter integrates the specific force between updates)",
                measurements_path.file_name().map_or_else(
                    || measurements_path.display().to_string(),
                    |n| n.to_string_lossy().into_owned()
                )
            ),
        ));
    }
    Ok(())
}

/// A sensor pair: both cells or neither; one without the other is an error naming the empty
/// one.
fn pair(
    cells: &Cells<'_>,
    values: [Option<f64>; 2],
    idx: [usize; 2],
    sensor: &str,
) -> Result<Option<[f64; 2]>, DynamicsError> {
    let name = |i: usize| cells.columns.get(i).copied().unwrap_or("-");
    match values {
        [Some(a), Some(b)] => Ok(Some([a, b])),
        [None, None] => Ok(None),
        [None, Some(_)] | [Some(_), None] => {
            let (empty, full) = if values[0].is_none() {
                (idx[0], idx[1])
            } else {
                (idx[1], idx[0])
            };
            Err(cells.error(
                name(empty),
                format!(
                    "empty while `{}` has a value; expected both {sensor} cells or neither \
                     (both empty = no {sensor} reading)",
                    name(full)
                ),
            ))
        }
    }
}

/// Odometer travel (m) below which it cannot tell degrees from radians.
const MIN_TRAVEL_M: f64 = 100.0;
/// If the GPS track read as degrees is shorter than this fraction of the odometer's, the
/// positions are radians (a radian track read as degrees is 180/pi = 57 times too short).
const TRAVEL_RATIO: f64 = 0.1;
/// Without odometer travel: distance from (0, 0) beyond which a small-valued track is radians.
const ORIGIN_RADIUS: f64 = 0.1;

/// Whether the GPS columns hold radians; if so, the line of the first fix and the evidence.
///
/// The heuristic, in order:
/// 1. Radians are bounded: if any fix has `|lat| >= 1.6` (a little over pi/2) or
///    `|lon| > 2*pi`, the values are degrees. Otherwise every fix lies, read as degrees,
///    within 180 km of the equator and 700 km of Greenwich: the open Gulf of Guinea. Real
///    degree tracks land there only when synthetic (a simulation placed at (0, 0)), so we
///    need more evidence than the box.
/// 2. With the odometer: between consecutive GPS fixes, compare the GPS chord (read as
///    degrees, in metres) with the odometer's displacement over the same interval (its
///    velocity integrated by trapezoids). Summed over the track, once the odometer has
///    covered at least [`MIN_TRAVEL_M`], degrees give a GPS length about equal to the
///    odometer's or longer (GPS noise adds length), radians read as degrees give 1/57 of it.
///    Below [`TRAVEL_RATIO`] of it, the column is radians. Chords between consecutive fixes
///    (rather than whole-track lengths) make GPS outages and closed loops harmless.
/// 3. Without odometer travel (standing still, or no odometer): radians if some fix is more
///    than [`ORIGIN_RADIUS`] from (0, 0) -- as degrees that is more than 11 km out at sea,
///    where no vehicle drives and a synthetic run placed at the origin does not start.
///    A radian track in the few hundred km next to (0, 0) with no odometer travel is
///    missed; such data are rare.
fn looks_like_radians(measurements: &[Measurement], lines: &[usize]) -> Option<(usize, String)> {
    let fixes: Vec<(f64, [f64; 2], usize)> = measurements
        .iter()
        .zip(lines)
        .filter_map(|(m, &l)| m.position_deg.map(|p| (m.t, p, l)))
        .collect();
    let first_line = fixes.first()?.2;
    if fixes
        .iter()
        .any(|(_, [lat, lon], _)| lat.abs() >= 1.6 || lon.abs() > std::f64::consts::TAU)
    {
        return None;
    }
    let odometer: Vec<(f64, [f64; 2])> = measurements
        .iter()
        .filter_map(|m| m.velocity.map(|v| (m.t, v)))
        .collect();
    let (mut gps_m, mut odo_m) = (0.0, 0.0);
    for w in fixes.windows(2) {
        let ((ta, a, _), (tb, b, _)) = (w[0], w[1]);
        let Some(d) = odometer_displacement(&odometer, ta, tb) else {
            continue;
        };
        odo_m += d;
        gps_m += chord_m(a, b);
    }
    if odo_m >= MIN_TRAVEL_M {
        return (gps_m < TRAVEL_RATIO * odo_m).then(|| {
            (
                first_line,
                format!(
                    "read as degrees the GPS track moves {gps_m:.1} m while the odometer \
                     moves {odo_m:.1} m"
                ),
            )
        });
    }
    fixes
        .iter()
        .find(|(_, [lat, lon], _)| lat.abs().max(lon.abs()) > ORIGIN_RADIUS)
        .map(|(_, _, line)| {
            (
                first_line,
                format!(
                    "read as degrees, the fix on line {line} would lie at sea more than \
                     {ORIGIN_RADIUS} deg off (0, 0), and no odometer travel tells otherwise"
                ),
            )
        })
}

/// The length (m) of the odometer's displacement over `[ta, tb]`, from its samples inside
/// the interval; `None` with fewer than two.
fn odometer_displacement(odometer: &[(f64, [f64; 2])], ta: f64, tb: f64) -> Option<f64> {
    odometer_east_north(odometer, ta, tb).map(|d| d[0].hypot(d[1]))
}

/// The odometer's East and North displacement (m) over `[ta, tb]` (its velocity integrated
/// by trapezoids over its samples inside the interval); `None` with fewer than two.
pub(super) fn odometer_east_north(
    odometer: &[(f64, [f64; 2])],
    ta: f64,
    tb: f64,
) -> Option<[f64; 2]> {
    let start = odometer.partition_point(|(t, _)| *t < ta);
    let end = odometer.partition_point(|(t, _)| *t <= tb);
    let inside = odometer.get(start..end)?;
    if inside.len() < 2 {
        return None;
    }
    let mut d = [0.0, 0.0];
    for w in inside.windows(2) {
        let ((t0, v0), (t1, v1)) = (w[0], w[1]);
        let dt = t1 - t0;
        d[0] += 0.5 * (v0[0] + v1[0]) * dt;
        d[1] += 0.5 * (v0[1] + v1[1]) * dt;
    }
    Some(d)
}

/// Distance (m) between two positions in degrees, on the local tangent plane.
pub(super) fn chord_m(a: [f64; 2], b: [f64; 2]) -> f64 {
    let lat = (0.5 * (a[0] + b[0])).to_radians();
    let s = lat.sin();
    let north = (b[0] - a[0]).to_radians() * meridian_radius(s);
    let east = (b[1] - a[1]).to_radians() * prime_vertical_radius(s) * lat.cos();
    north.hypot(east)
}

/// `dataset.toml`: the `[noise]`, `[prior]` and `[simulation]` tables, nothing else.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct ConfigFile {
    #[serde(default)]
    noise: Option<NoiseConfig>,
    #[serde(default)]
    prior: PlatformPrior,
    #[serde(default)]
    simulation: Option<Provenance>,
}

/// Every coefficient name a `[prior.coefficients]` key may take: the base model's and those
/// of `registry`'s effects.
fn known_coefficients(registry: &Registry) -> Vec<String> {
    let mut names: Vec<String> = BASE_NAMES[NAV_DIM..]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for effect in registry.names() {
        if let Ok(e) = registry.build(&effect) {
            names.extend(e.coefficient_names().iter().map(|s| s.to_string()));
        }
    }
    names
}

fn read_config(path: &Path, known: &[String]) -> Result<ConfigFile, DynamicsError> {
    let text = read_text(path, &TextFile::DATASET_CONFIG)?;
    let config: ConfigFile = toml::from_str(&text).map_err(|e| toml_error(path, &text, &e))?;
    if let Err(message) = config.noise.unwrap_or_default().validate() {
        // validate() names the key as `noise.<key>`; point at its line when we can find it.
        let key = message
            .strip_prefix("noise.")
            .and_then(|m| m.split_whitespace().next())
            .unwrap_or("");
        return Err(match key_line(&text, "noise", key) {
            Some(line) => data_error(path, line, &format!("noise.{key}"), message),
            None => DynamicsError::File {
                path: path.to_path_buf(),
                message: printable(&message),
            },
        });
    }
    if let Err((key, message)) = config.prior.validate(known) {
        // `prior.level_rad` sits in [prior]; `prior.coefficients.X` in [prior.coefficients].
        let (table, name) = key.rsplit_once('.').unwrap_or(("prior", &key));
        return Err(match key_line(&text, table, name) {
            Some(line) => data_error(path, line, &key, message),
            None => DynamicsError::File {
                path: path.to_path_buf(),
                message: printable(&format!("{key}: {message}")),
            },
        });
    }
    Ok(config)
}

/// The 1-based line of `key = ...` inside `[table]`, for the simple layout this project
/// writes; `None` for other layouts (inline or dotted tables).
fn key_line(text: &str, table: &str, key: &str) -> Option<usize> {
    if key.is_empty() {
        return None;
    }
    let header = format!("[{table}]");
    let mut inside = false;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line.split('#').next().is_some_and(|h| h.trim() == header);
        } else if inside {
            if let Some(rest) = line.strip_prefix(key) {
                if rest.trim_start().starts_with('=') {
                    return Some(i + 1);
                }
            }
        }
    }
    None
}

/// `truth.csv`: columns that are states of the base model or of a known effect (a misspelt
/// one would be silently left out of every comparison), rows inside the inputs' span, and a
/// last row at the last measurement (the diagnosis compares its final estimates with it).
fn read_truth(
    path: &Path,
    known: &[String],
    inputs: &[InputSample],
    measurements: &[Measurement],
) -> Result<Truth, DynamicsError> {
    let mut table = read_table(path, "t,<state names>")?;
    let header = table.header.clone();
    let first = header.cells.first().map_or("", String::as_str);
    if first != "t" {
        return Err(data_error(
            path,
            header.line,
            if first.is_empty() { "-" } else { first },
            format!("first column is `{first}`; expected `t`, then one column per state"),
        ));
    }
    let names: Vec<String> = header.cells.get(1..).unwrap_or_default().to_vec();
    if names.is_empty() {
        return Err(data_error(
            path,
            header.line,
            "-",
            "no state columns; expected `t` then at least one state name".to_owned(),
        ));
    }
    for (i, name) in header.cells.iter().enumerate().skip(1) {
        if name.is_empty() {
            return Err(data_error(
                path,
                header.line,
                &format!("#{}", i + 1),
                format!("column {} has no name; expected a state name", i + 1),
            ));
        }
        if let Some(j) = header.cells[..i].iter().position(|n| n == name) {
            return Err(data_error(
                path,
                header.line,
                name,
                format!(
                    "duplicate column `{name}` (columns {} and {}); expected unique state names",
                    j + 1,
                    i + 1
                ),
            ));
        }
    }
    for name in &names {
        if !known.contains(name) {
            return Err(data_error(
                path,
                header.line,
                name,
                format!(
                    "`{}` is no state of the base model or of a known effect; expected state \
                     names such as phi_x, v_x, L, Kg0x, Ka1y or an effect's coefficients \
                     (misspelt?)",
                    name
                ),
            ));
        }
    }
    let (t0, t1) = (
        inputs.first().map_or(f64::NEG_INFINITY, |i| i.t),
        inputs.last().map_or(f64::INFINITY, |i| i.t),
    );
    let columns: Vec<&str> = header.cells.iter().map(String::as_str).collect();
    let mut t = Vec::new();
    let mut states = Vec::new();
    let mut previous = None;
    while let Some(row) = table.next_row()? {
        let cells = Cells {
            path,
            columns: &columns,
            row: &row,
        };
        cells.check_count()?;
        let time = cells.required(0)?;
        let state = (1..columns.len())
            .map(|i| cells.required(i))
            .collect::<Result<Vec<f64>, _>>()?;
        check_increasing(path, row.line, time, &mut previous)?;
        if time < t0 || time > t1 {
            return Err(cells.error(
                "t",
                format!(
                    "t = {time} is outside the span of {INPUTS_FILE}; expected {t0} <= t <= {t1}"
                ),
            ));
        }
        t.push(time);
        states.push(state);
    }
    if t.is_empty() {
        return Err(data_error(
            path,
            table.next_line(),
            "-",
            "no rows; expected at least one row after the header".to_owned(),
        ));
    }
    let last_measurement = measurements.last().map_or(f64::NEG_INFINITY, |m| m.t);
    let last_truth = t.last().copied().unwrap_or(f64::NEG_INFINITY);
    if last_truth < last_measurement {
        return Err(data_error(
            path,
            table.next_line(),
            "t",
            format!(
                "the truth ends at t = {last_truth}, before the last measurement at t = \
                 {last_measurement}; expected a row at or after it (the final estimates are \
                 compared with the truth at the end)"
            ),
        ));
    }
    Ok(Truth { names, t, states })
}
