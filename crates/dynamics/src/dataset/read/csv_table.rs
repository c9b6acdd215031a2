//! CSV files read with located errors: a header checked against the exact columns, one
//! cell per column, finite numbers, strictly increasing times, and a line that is too long
//! refused before it is read whole.

use super::*;

/// One CSV line: its 1-based line number and its cells, trimmed of surrounding blanks.
#[derive(Clone)]
pub(super) struct Row {
    pub(super) line: usize,
    pub(super) cells: Vec<String>,
}

/// A CSV file read as a stream: its header row, then one data row at a time, so that an
/// error on line 2 is reported before the rest is read, and memory holds only what the caller
/// keeps of each row.
pub(super) struct Table {
    pub(super) path: PathBuf,
    pub(super) header: Row,
    pub(super) reader: CsvReader,
    pub(super) record: csv::ByteRecord,
    /// Line of the last row read (the header's before any).
    pub(super) last_line: usize,
}

impl Table {
    /// The line just after the last row read: where a missing row was expected.
    pub(super) fn next_line(&self) -> usize {
        self.last_line + 1
    }

    /// The next data row, or `None` at the end of the file.
    pub(super) fn next_row(&mut self) -> Result<Option<Row>, DynamicsError> {
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
pub(super) fn read_table(path: &Path, expected_header: &str) -> Result<Table, DynamicsError> {
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
pub(super) fn file_encoding(file: &mut std::fs::File) -> std::io::Result<Option<&'static str>> {
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
pub(super) fn read_row(
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

pub(super) fn csv_error(path: &Path, e: csv::Error) -> DynamicsError {
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
pub(super) fn check_header(table: &Table, expected: &[&str]) -> Result<(), DynamicsError> {
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
pub(super) struct Cells<'a> {
    pub(super) path: &'a Path,
    pub(super) columns: &'a [&'a str],
    pub(super) row: &'a Row,
}

impl Cells<'_> {
    pub(super) fn error(&self, column: &str, message: String) -> DynamicsError {
        data_error(self.path, self.row.line, column, message)
    }

    /// One cell per column.
    pub(super) fn check_count(&self) -> Result<(), DynamicsError> {
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
    pub(super) fn optional(&self, i: usize) -> Result<Option<f64>, DynamicsError> {
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
    pub(super) fn required(&self, i: usize) -> Result<f64, DynamicsError> {
        self.optional(i)?.ok_or_else(|| {
            self.error(
                self.columns.get(i).copied().unwrap_or("-"),
                "empty cell; expected a finite number".to_owned(),
            )
        })
    }
}

/// Checks `t` against the previous row's time `(t, line)` and remembers it. A time that goes
/// back is said to be one: a unit's clock that restarts, or two recordings joined, is the
/// usual cause, and a reader told only "not increasing" hunts for a typo.
pub(super) fn check_increasing(
    path: &Path,
    line: usize,
    t: f64,
    previous: &mut Option<(f64, usize)>,
) -> Result<(), DynamicsError> {
    if let Some((tp, lp)) = *previous {
        if t <= tp {
            let why = if t == tp {
                "the same time twice (a repeated row?)".to_owned()
            } else {
                // Seven significant digits: `0.30000000000000004 s` reads as a bug of its own.
                let back: f64 = format!("{:.6e}", tp - t).parse().unwrap_or(tp - t);
                format!(
                    "the time goes back by {back} s (a clock that restarted, two recordings \
                     joined (split them into two datasets), or rows out of order)"
                )
            };
            return Err(data_error(
                path,
                line,
                "t",
                format!(
                    "t = {t} is not after t = {tp} on line {lp}: {why}; expected times \
                     strictly increasing"
                ),
            ));
        }
    }
    *previous = Some((t, line));
    Ok(())
}
