//! `truth.csv` of a simulated dataset: the states by name, at the measurements' times.

use super::*;

/// `truth.csv`: columns that are states of the base model or of a known effect (a misspelt
/// one would be silently left out of every comparison), rows inside the inputs' span, and a
/// last row at the last measurement (the diagnosis compares its final estimates with it).
pub(super) fn read_truth(
    path: &Path,
    known: &[String],
    inputs: &[InputSample],
    inputs_file: &str,
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
            // Examples spread over the family's states and its effects' coefficients.
            let examples: Vec<&str> = known
                .iter()
                .step_by((known.len() / 5).max(1))
                .take(5)
                .map(String::as_str)
                .collect();
            return Err(data_error(
                path,
                header.line,
                name,
                format!(
                    "`{}` is no state of the base model or of a known effect; expected a state \
                     of the dataset's family or of its effects, such as {} (misspelt?)",
                    name,
                    examples.join(", ")
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
                    "t = {time} is outside the span of {inputs_file}; expected {t0} <= t <= {t1}"
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
