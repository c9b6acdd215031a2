//! Reading the files users name, so that no file can hang navkf or take its memory.
//!
//! Every path navkf reads comes from a user: a study file, a dataset folder's files, a
//! baseline `summary.json`, shard files, a trajectory file. Any of them may be `/dev/zero`
//! (never ends), a FIFO (opening it blocks until a writer comes), a sparse file of
//! terabytes, or a text whose one line is a gigabyte. A plain `read_to_string` takes the
//! first until memory runs out and blocks on the second; the `csv` crate buffers a whole
//! line before it looks at it; the `toml` crate's error quotes the offending line whole. So
//! every reader goes through this module:
//!
//! - [`read_text`] reads a whole file of one [`TextFile`] kind: it checks (following links,
//!   before opening) that the path is a regular file no larger than the kind's limit, reads
//!   at most that limit plus one byte (a file growing under us is still bounded), and
//!   refuses text that is not UTF-8;
//! - [`check_regular`] is that first check alone, for files read as a stream (the CSVs);
//! - [`LineLimit`] wraps a reader and fails on a line longer than a limit, so a CSV parser
//!   never buffers a giant header or row: memory stays a small multiple of the data kept;
//! - [`toml_error`] and [`toml_message`] say where a TOML file is wrong (`path:LINE:COL:` and
//!   the parser's message) with a short cut of the line, never the line whole;
//! - [`printable`] makes any text from a file safe to print (escaped control characters,
//!   long stretches cut, a bounded length).
//!
//! Each refusal names the file and what was expected, e.g. `/dev/zero: not a regular file
//! (a character device: reading it could block or never end); expected a study file (TOML)`
//! or `big.toml: 314.573 MB (314572800 bytes); expected a study file (TOML) of at most 16
//! MiB`.

use crate::error::DynamicsError;
use crate::memory::human;
use std::io::Read;
use std::path::Path;

const KIB: u64 = 1 << 10;
const MIB: u64 = 1 << 20;
const GIB: u64 = 1 << 30;

/// What a whole-file read expects: named in messages, and the largest size read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextFile {
    /// What the file should be, as said after "expected" ("a study file (TOML)").
    pub what: &'static str,
    /// The largest size accepted, bytes.
    pub max_bytes: u64,
}

/// Largest TOML file read (study files, diagnosis study files, `dataset.toml`, trajectory
/// files): 16 MiB. The committed study files are 1.5-4.9 KB; a segment of a
/// `[[trajectory.segment]]` list takes about 45 bytes, so this holds some 350,000 of them.
/// The parser's memory is some 30 times the text: a 15 MB list of 350,000 segments peaks
/// at 490 MB, the most a TOML file can take.
pub const TOML_MAX_BYTES: u64 = 16 * MIB;

/// Largest shard file read by `merge`: 4 GiB. A shard holds every block's tallies (per
/// stored time, per state, per filter), so it grows with its runs: `navkf study
/// studies/paper.toml --shard 0/2` (250 runs) writes 26.8 MB, about 107 KB a run; 4 GiB
/// takes a shard of some 40,000 such runs.
pub const SHARD_MAX_BYTES: u64 = 4 * GIB;

/// Largest baseline `summary.json` read: 64 MiB. A summary does not grow with the runs:
/// the committed studies' summaries are 20-115 KB (a sweep point's with its diverged
/// examples the largest), so this is some 500 times the largest seen.
pub const SUMMARY_MAX_BYTES: u64 = 64 * MIB;

/// Longest line of a dataset CSV read: 64 KiB. The widest legitimate row is `truth.csv`'s
/// with every catalogued effect (33 columns of full-precision numbers): 719 bytes; this is
/// 90 times that, room for some 2,500 columns of user effects. A longer header or row is
/// refused with its line number before it is buffered.
pub const CSV_LINE_MAX_BYTES: usize = 64 * KIB as usize;

/// Kinds of text files navkf reads whole.
impl TextFile {
    /// A study file, Monte Carlo or diagnosis.
    pub const STUDY: TextFile = TextFile {
        what: "a study file (TOML)",
        max_bytes: TOML_MAX_BYTES,
    };
    /// A dataset folder's `dataset.toml`.
    pub const DATASET_CONFIG: TextFile = TextFile {
        what: "a dataset.toml (TOML: [noise], [prior], [simulation])",
        max_bytes: TOML_MAX_BYTES,
    };
    /// A file of declared effects (`--effects-file`): `[[effect]]` tables.
    pub const EFFECTS: TextFile = TextFile {
        what: "an effects file (TOML: [[effect]] tables)",
        max_bytes: TOML_MAX_BYTES,
    };
    /// A file whose `[trajectory]` table `simulate --trajectory` drives.
    pub const TRAJECTORY: TextFile = TextFile {
        what: "a TOML file with a [trajectory] table",
        max_bytes: TOML_MAX_BYTES,
    };
    /// A shard's partial tallies, written by `navkf study --shard`.
    pub const SHARD: TextFile = TextFile {
        what: "a shard file (JSON written by `navkf study --shard`)",
        max_bytes: SHARD_MAX_BYTES,
    };
    /// A study's `summary.json`, as a baseline.
    pub const SUMMARY: TextFile = TextFile {
        what: "a study's summary.json",
        max_bytes: SUMMARY_MAX_BYTES,
    };
    /// A KITTI raw drive's `oxts/timestamps.txt`: 30 bytes a frame, so 64 MiB holds two
    /// million frames (over five hours at 100 Hz).
    pub const KITTI_STAMPS: TextFile = TextFile {
        what: "a KITTI oxts timestamps.txt (one YYYY-MM-DD HH:MM:SS.fffffffff line a frame)",
        max_bytes: 64 * MIB,
    };
    /// One KITTI OXTS frame, `oxts/data/NNNNNNNNNN.txt`: 30 numbers, a few hundred bytes.
    pub const KITTI_FRAME: TextFile = TextFile {
        what: "a KITTI oxts frame (30 numbers on one line)",
        max_bytes: 64 * KIB,
    };
}

/// Checks that `path` (following links) is a regular file, without opening it (opening a
/// FIFO blocks until a writer comes); returns its size. `what` is what it should be, for
/// the message. A path that cannot be looked at (not found, no permission) is
/// [`DynamicsError::Io`].
pub fn check_regular(path: &Path, what: &str) -> Result<u64, DynamicsError> {
    let meta = std::fs::metadata(path).map_err(|source| DynamicsError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if meta.is_file() {
        return Ok(meta.len());
    }
    let kind = if meta.is_dir() {
        "a folder".to_owned()
    } else {
        format!(
            "{}: reading it could block or never end",
            special_file_type(&meta)
        )
    };
    Err(DynamicsError::File {
        path: path.to_path_buf(),
        message: format!("not a regular file ({kind}); expected {what}"),
    })
}

/// What a path that is neither a regular file nor a folder is.
fn special_file_type(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "a device, FIFO or socket"
}

/// The whole text of `path`, a file of kind `kind`: refused unless it is a regular file (see
/// [`check_regular`]) of at most `kind.max_bytes`, UTF-8 (UTF-16 and UTF-32 are named as
/// such, see [`other_encoding`]). Reads at most the limit plus one byte, so a file growing
/// while read is still bounded.
pub fn read_text(path: &Path, kind: &TextFile) -> Result<String, DynamicsError> {
    let size = check_regular(path, kind.what)?;
    let too_large = |size: String| DynamicsError::File {
        path: path.to_path_buf(),
        message: format!(
            "{size}; expected {} of at most {}",
            kind.what,
            binary_size(kind.max_bytes)
        ),
    };
    if size > kind.max_bytes {
        return Err(too_large(format!("{} ({size} bytes)", human(size as f64))));
    }
    let io = |source| DynamicsError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0).saturating_add(1));
    file.take(kind.max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > kind.max_bytes {
        return Err(too_large("grew past the limit while read".to_owned()));
    }
    if let Some(encoding) = other_encoding(&bytes) {
        return Err(DynamicsError::File {
            path: path.to_path_buf(),
            message: format!("is {encoding}; expected {} in UTF-8", kind.what),
        });
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        DynamicsError::File {
            path: path.to_path_buf(),
            message: format!(
                "not UTF-8 text (line {}: byte {at} of the file is not part of a UTF-8 \
                 character); expected {} in UTF-8",
                line_of(e.as_bytes(), at),
                kind.what
            ),
        }
    })
}

/// `bytes` as "16 MiB" when a whole number of KiB, MiB or GiB, else "N bytes".
fn binary_size(bytes: u64) -> String {
    for (unit, name) in [(GIB, "GiB"), (MIB, "MiB"), (KIB, "KiB")] {
        if bytes >= unit && bytes.is_multiple_of(unit) {
            return format!("{} {name}", bytes / unit);
        }
    }
    format!("{bytes} bytes")
}

/// The 1-based line holding byte `at` of `bytes`.
fn line_of(bytes: &[u8], at: usize) -> usize {
    1 + bytes[..at.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// The encoding of a text starting with `head` when it is UTF-16 or UTF-32 (by byte-order
/// mark, or by the NUL bytes every ASCII character carries in them), which would otherwise
/// read as garbled names or a baffling parse error.
pub fn other_encoding(head: &[u8]) -> Option<&'static str> {
    match head.get(..4).unwrap_or(head) {
        [0xFF, 0xFE, 0, 0] | [0, 0, 0xFE, 0xFF] => Some("UTF-32 (byte-order mark)"),
        [0xFF, 0xFE, ..] | [0xFE, 0xFF, ..] => Some("UTF-16 (byte-order mark)"),
        [a, 0, b, 0] | [0, a, 0, b] if *a != 0 && *b != 0 => Some("UTF-16 (NUL bytes)"),
        _ => None,
    }
}

/// A line longer than [`LineLimit`]'s limit: the error inside the `std::io::Error` it returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineTooLong {
    /// The 1-based line (lines end at `\n`).
    pub line: u64,
    /// The limit, bytes.
    pub max_bytes: usize,
}

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {} is longer than {} (refused before reading it whole)",
            self.line,
            binary_size(self.max_bytes as u64)
        )
    }
}

impl std::error::Error for LineTooLong {}

impl LineTooLong {
    /// The [`LineTooLong`] inside `error`, if it is one from a [`LineLimit`].
    pub fn inside(error: &std::io::Error) -> Option<LineTooLong> {
        error
            .get_ref()
            .and_then(|e| e.downcast_ref::<LineTooLong>())
            .copied()
    }
}

/// A reader that fails (with a [`LineTooLong`] inside an `InvalidData` error) as soon as a
/// line grows past `max_bytes`, counting the bytes since the last `\n`; whatever parses its
/// output then never holds more than one such line.
pub struct LineLimit<R> {
    inner: R,
    max_bytes: usize,
    /// The line being read, 1-based.
    line: u64,
    /// Bytes of that line so far.
    in_line: usize,
}

impl<R: Read> LineLimit<R> {
    /// `inner`, refusing lines longer than `max_bytes`.
    pub fn new(inner: R, max_bytes: usize) -> Self {
        LineLimit {
            inner,
            max_bytes,
            line: 1,
            in_line: 0,
        }
    }
}

impl<R: Read> Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let mut rest = &buf[..n];
        loop {
            let end = rest.iter().position(|&b| b == b'\n');
            self.in_line += end.unwrap_or(rest.len());
            if self.in_line > self.max_bytes {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    LineTooLong {
                        line: self.line,
                        max_bytes: self.max_bytes,
                    },
                ));
            }
            let Some(end) = end else { break };
            self.line += 1;
            self.in_line = 0;
            rest = &rest[end + 1..];
        }
        Ok(n)
    }
}

/// Characters of a line shown around the error's column in a TOML error.
const EXCERPT_CHARS: usize = 100;

/// The TOML error `error` in `text`, the contents of `path`: [`DynamicsError::Toml`] with the
/// line, column, parser's message and a short cut of the line when the parser located it,
/// [`DynamicsError::File`] with the message otherwise.
pub fn toml_error(path: &Path, text: &str, error: &toml::de::Error) -> DynamicsError {
    let message = toml_parser_message(error);
    match error.span().map(|s| locate(text, s)) {
        Some((line, column, excerpt)) => DynamicsError::Toml {
            path: path.to_path_buf(),
            line,
            column,
            message,
            excerpt,
        },
        None => DynamicsError::File {
            path: path.to_path_buf(),
            message,
        },
    }
}

/// [`toml_error`] for a text without a file: `line L, column C: message` and the cut line.
pub fn toml_message(text: &str, error: &toml::de::Error) -> String {
    let message = toml_parser_message(error);
    match error.span().map(|s| locate(text, s)) {
        Some((line, column, excerpt)) => {
            format!("line {line}, column {column}: {message}\n{excerpt}")
        }
        None => message,
    }
}

/// The parser's message on one line, printable: "invalid table header; expected `.`, `]`".
fn toml_parser_message(error: &toml::de::Error) -> String {
    let lines: Vec<&str> = error
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    format!("TOML parse error: {}", printable(&lines.join("; ")))
}

/// The 1-based line and column (in characters) where `span` (bytes of `text`) starts, and
/// the excerpt: `LINE | <at most EXCERPT_CHARS characters of the line around the column>`
/// and carets under the span's part of it; a cut end shows `...`.
fn locate(text: &str, span: std::ops::Range<usize>) -> (usize, usize, String) {
    let mut at = span.start.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let end = text[at..].find('\n').map_or(text.len(), |i| at + i);
    let line_text = text[start..end].trim_end_matches('\r');
    let line = 1 + text[..start].matches('\n').count();
    let column = 1 + text[start..at].chars().count();
    let length = line_text.chars().count();
    // Where the carets end (0-based character index, exclusive): the span's part of this
    // line, at least one character. A span starting in the line's trailing `\r`s lies past
    // the trimmed line, so the upper bound is kept at or above `at`.
    let marked_end = text
        .get(at..span.end.clamp(at, (start + line_text.len()).max(at)))
        .map_or(0, |s| s.chars().count())
        .max(1)
        + column
        - 1;
    let first = if length <= EXCERPT_CHARS {
        0
    } else {
        (column - 1)
            .saturating_sub(EXCERPT_CHARS / 2)
            .min(length - EXCERPT_CHARS)
    };
    let (mut shown, mut marks) = (String::new(), String::new());
    if first > 0 {
        shown.push_str("...");
        marks.push_str("   ");
    }
    for (i, c) in line_text
        .chars()
        .enumerate()
        .skip(first)
        .take(EXCERPT_CHARS)
    {
        let before = shown.len();
        match c {
            '\t' => shown.push(' '),
            c if c.is_control() => shown.extend(c.escape_unicode()),
            c => shown.push(c),
        }
        let width = if c.is_control() || c.is_ascii() {
            shown.len() - before
        } else {
            1
        };
        let mark = if (column - 1..marked_end).contains(&i) {
            '^'
        } else {
            ' '
        };
        marks.extend(std::iter::repeat_n(mark, width));
    }
    if first + EXCERPT_CHARS < length {
        shown.push_str("...");
    }
    if !marks.contains('^') {
        marks.push('^'); // the span starts at the line's end
    }
    let gutter = " ".repeat(line.to_string().len());
    let excerpt = format!(
        "{gutter} |\n{line} | {shown}\n{gutter} | {}",
        marks.trim_end()
    );
    (line, column, excerpt)
}

/// Longest stretch of a message without a blank that is shown whole (a cell, a name).
pub const LONGEST_WORD: usize = 60;

/// Longest message [`printable`] returns, in characters (plus a note of the length cut).
pub const LONGEST_MESSAGE: usize = 1000;

/// `text` safe to print: control characters (a terminal escape sequence, a NUL) escaped as
/// `\u{1b}`, any stretch without a blank longer than [`LONGEST_WORD`] characters (a
/// megabyte-long cell) cut, with its length shown, and the whole cut after
/// [`LONGEST_MESSAGE`] characters.
pub fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(4096));
    let mut shown = 0usize; // characters pushed
    let mut word = 0usize; // characters of the current stretch without a blank
    let mut cut = false; // the current stretch is being skipped
    for (i, c) in text.char_indices() {
        if shown >= LONGEST_MESSAGE {
            let rest = text[i..].chars().count();
            out.push_str(&format!("... ({rest} more characters)"));
            break;
        }
        if c == ' ' || c == '\n' {
            word = 0;
            cut = false;
            out.push(c);
            shown += 1;
            continue;
        }
        word += 1;
        if cut {
            continue;
        }
        if word > LONGEST_WORD {
            let rest = text[i..]
                .chars()
                .take_while(|c| *c != ' ' && *c != '\n')
                .count();
            let note = format!("... ({} characters)", word - 1 + rest);
            shown += note.len();
            out.push_str(&note);
            cut = true;
            continue;
        }
        if c.is_control() {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
        shown += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_past_the_limit_fails_with_its_number() {
        let text = format!("short\nok\n{}\n", "x".repeat(100));
        let mut reader = LineLimit::new(text.as_bytes(), 50);
        let mut out = Vec::new();
        let e = reader.read_to_end(&mut out).unwrap_err();
        let too_long = LineTooLong::inside(&e).unwrap();
        assert_eq!(too_long.line, 3);
        let mut reader = LineLimit::new(text.as_bytes(), 100);
        out.clear();
        reader.read_to_end(&mut out).unwrap();
        assert_eq!(out, text.as_bytes());
    }

    #[test]
    fn an_excerpt_is_cut_around_the_column() {
        let line = format!("key = {}!{}", "a".repeat(5000), "b".repeat(5000));
        let text = format!("[t]\n{line}\n");
        let (l, c, excerpt) = locate(&text, 4 + 6 + 5000..4 + 6 + 5001);
        assert_eq!((l, c), (2, 5007));
        assert!(excerpt.len() < 3 * EXCERPT_CHARS, "{excerpt}");
        let mut rows = excerpt.lines().skip(1);
        let (shown, caret) = (rows.next().unwrap(), rows.next().unwrap());
        assert_eq!(shown.find('!'), caret.find('^'), "{excerpt}");
        assert!(
            shown.contains("...a") && shown.ends_with("b..."),
            "{excerpt}"
        );
    }

    #[test]
    fn a_span_in_a_lines_trailing_carriage_returns_is_located() {
        // The line trims to `a = 1`; a span starting on its second `\r` lies past that.
        let text = "a = 1\r\r\nb = 2\n";
        for start in 5..=7 {
            let (l, c, _) = locate(text, start..start + 1);
            assert_eq!((l, c), (1, start + 1), "span at {start}");
        }
    }

    #[test]
    fn a_message_is_cut_to_a_bounded_length() {
        let m = printable(&"a ".repeat(1 << 20));
        assert!(m.len() < LONGEST_MESSAGE + 100, "{}", m.len());
        assert!(m.ends_with("more characters)"));
        assert_eq!(printable("x\u{1b}y"), "x\\u{1b}y");
    }
}
