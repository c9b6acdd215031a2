//! `imu.csv` of a strapdown dataset: body rates and specific forces at the sample times, or
//! the increments a unit accumulated over each interval, read as the same input samples
//! (body rate in the first three numbers, specific force in the next three, forward-left-up
//! axes, docs/model.md eq. (50)).
//!
//! **Increments.** A row `t, dtheta, dv` holds what the unit accumulated over the interval
//! that ends at `t`: its mean rate and mean specific force over that interval are
//! `dtheta / dt`, `dv / dt`. The filters interpolate their inputs linearly between samples,
//! and the mean of a smooth signal over an interval is its value at the interval's middle to
//! second order, so each mean becomes a sample at the middle of its interval. The first row
//! marks the start: the interval its increment covers began before the file did, so its
//! values are read (and checked) but not used.

use super::*;
use crate::dataset::{IMU_INCREMENT_COLUMNS, IMU_RATE_COLUMNS};

/// What `imu.csv` holds, by its header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ImuForm {
    /// Rates and specific forces at `t`.
    Rates,
    /// Increments over the interval ending at `t`.
    Increments,
}

pub(in crate::dataset) fn read_imu(path: &Path) -> Result<Vec<InputSample>, DynamicsError> {
    let both = format!(
        "{}` or `{}",
        IMU_RATE_COLUMNS.join(","),
        IMU_INCREMENT_COLUMNS.join(",")
    );
    let mut table = read_table(path, &both)?;
    let first = table.header.cells.get(1).map_or("", String::as_str);
    let (form, columns) = if first.starts_with("dtheta") {
        (ImuForm::Increments, IMU_INCREMENT_COLUMNS)
    } else {
        (ImuForm::Rates, IMU_RATE_COLUMNS)
    };
    check_header(&table, &columns)?;
    let mut samples = Vec::new();
    let mut previous = None;
    while let Some(row) = table.next_row()? {
        let cells = Cells {
            path,
            columns: &columns,
            row: &row,
        };
        cells.check_count()?;
        let t = cells.required(0)?;
        // An IMU row is a whole reading: an empty cell is an error, not a missing sensor.
        let mut values = [0.0; 6];
        for (k, v) in values.iter_mut().enumerate() {
            *v = cells.optional(k + 1)?.ok_or_else(|| {
                cells.error(
                    columns[k + 1],
                    "empty cell; expected a number: each row of imu.csv is one whole reading \
                     of the three gyros and the three accelerometers"
                        .to_owned(),
                )
            })?;
        }
        let before = previous.map(|(tp, _)| tp);
        check_increasing(path, row.line, t, &mut previous)?;
        match (form, before) {
            (ImuForm::Rates, _) => samples.push(InputSample { t, f: values }),
            (ImuForm::Increments, None) => {}
            (ImuForm::Increments, Some(tp)) => {
                let dt = t - tp;
                samples.push(InputSample {
                    t: 0.5 * (tp + t),
                    f: values.map(|v| v / dt),
                });
            }
        }
    }
    if samples.len() < 2 {
        let rows = match form {
            ImuForm::Rates => "at least 2 rows",
            ImuForm::Increments => "at least 3 rows (the first marks the start)",
        };
        return Err(data_error(
            path,
            table.next_line(),
            "-",
            format!(
                "{} reading(s); expected {rows}: the filter needs an interval",
                samples.len()
            ),
        ));
    }
    Ok(samples)
}
