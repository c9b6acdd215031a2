//! `inputs.csv` and `measurements.csv`: each row checked, sensor pairs complete or empty,
//! longitude unwrapped across the antimeridian, and the input rate against the
//! measurements'.

use super::*;

pub(in crate::dataset) fn read_inputs(path: &Path) -> Result<Vec<InputSample>, DynamicsError> {
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
        inputs.push(InputSample {
            t,
            f: crate::kinematics::platform_input(f),
        });
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

pub(super) fn read_measurements(
    path: &Path,
    inputs: &[InputSample],
    files: &dyn FamilyFiles,
) -> Result<Vec<Measurement>, DynamicsError> {
    let columns = files.measurement_columns();
    let mut table = read_table(path, &columns.join(","))?;
    check_header(&table, columns)?;
    let mut measurements = Vec::new();
    let mut lines = Vec::new();
    let mut previous = None;
    // The GPS pair's columns: the last two.
    let gps = [columns.len() - 2, columns.len() - 1];
    while let Some(row) = table.next_row()? {
        let cells = Cells {
            path,
            columns,
            row: &row,
        };
        cells.check_count()?;
        let t = cells.required(0)?;
        let p = [cells.optional(gps[0])?, cells.optional(gps[1])?];
        let position_deg = pair(&cells, p, gps, "GPS")?;
        let (velocity, speed) = match files.odometer() {
            Odometer::VelocityEastNorth => {
                let v = [cells.optional(1)?, cells.optional(2)?];
                (pair(&cells, v, [1, 2], "odometer")?, None)
            }
            Odometer::ForwardSpeed => (None, cells.optional(1)?),
        };
        if velocity.is_none() && speed.is_none() && position_deg.is_none() {
            let (odometer, all) = match files.odometer() {
                Odometer::VelocityEastNorth => ("an odometer pair (v_e,v_n)", "four"),
                Odometer::ForwardSpeed => ("an odometer speed", "three"),
            };
            return Err(cells.error(
                &columns[1..].join(","),
                format!(
                    "all {all} cells empty: the row says nothing; expected {odometer}, a GPS \
                     pair (lat_deg,lon_deg) or both"
                ),
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
            speed,
            nhc: None,
            zupt: None,
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
                    "t = {} is outside the span of {}; expected {t0} <= t <= {t1}",
                    m.t,
                    files.inputs_file()
                ),
            ));
        }
    }
    check_input_rate(
        path,
        &path.with_file_name(files.inputs_file()),
        inputs,
        &measurements,
    )?;
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

/// Largest change of longitude (deg) between consecutive fixes that an antimeridian
/// crossing may hide: over 1000 km at the equator, 190 km at 80 deg.
pub(super) const CROSSING_MAX_DEG: f64 = 10.0;

/// Makes a track that crosses the antimeridian (longitude jumping between +180 and -180)
/// one continuous track: a fix whose longitude jumps by more than half a turn from the
/// previous one, but lies within [`CROSSING_MAX_DEG`] of it once moved by whole turns, is
/// moved by those turns. The filters, `inspect`'s extent and the figures then all see the
/// vehicle drive on, not jump 40,000 km. Other fixes keep their value to the bit.
pub(super) fn unwrap_longitude(measurements: &mut [Measurement]) {
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
pub(super) fn check_input_rate(
    measurements_path: &Path,
    inputs_path: &Path,
    inputs: &[InputSample],
    measurements: &[Measurement],
) -> Result<(), DynamicsError> {
    use crate::dataset::plausibility::median_interval;
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
pub(super) fn pair(
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
