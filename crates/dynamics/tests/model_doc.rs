//! Every equation the code or the README cites exists in `docs/model.md`, and so does every
//! section it names.
//!
//! Definitions: in `docs/model.md`, a line inside a fenced code block that ends with at least
//! two spaces and a number in parentheses defines that equation; the numbers must run 1, 2,
//! 3, ... in order, each once.
//!
//! Citations, in every `.rs` file under `crates/` and in README.md, on one line each:
//! `docs/model.md eq. (N)`, `docs/model.md eqs. (N)-(M)`, `docs/model.md eqs. (N), (M)`
//! (items separated by `, ` or ` and `, a range by `-`), and `docs/model.md, "Heading"` for a
//! section. An equation cited without `docs/model.md` in front, or in the old style (the word
//! followed by a bare number), is an error, so a wrong or stale citation cannot hide. In the
//! prose of `docs/model.md` itself, its own equations are `eq. (N)` and the paper's
//! `paper (N)`; a bare number in parentheses is an error there.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

const DOC: &str = "docs/model.md";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// What `docs/model.md` defines: its equation numbers and its section titles.
struct Defined {
    equations: BTreeSet<u32>,
    headings: BTreeSet<String>,
}

/// The equation numbers and headings of the document, or what is wrong with its numbering.
fn definitions(doc: &str) -> Result<Defined, Vec<String>> {
    let mut equations = BTreeSet::new();
    let mut headings = BTreeSet::new();
    let mut errors = Vec::new();
    let mut in_code = false;
    let mut expected = 1;
    for (i, line) in doc.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if !in_code {
            if line.starts_with('#') {
                headings.insert(line.trim_start_matches('#').trim().to_string());
            }
            continue;
        }
        if let Some(n) = defined_number(line) {
            if n != expected {
                errors.push(format!(
                    "{DOC}:{}: equation ({n}) defined where ({expected}) comes next",
                    i + 1
                ));
            }
            expected = n + 1;
            if !equations.insert(n) {
                errors.push(format!("{DOC}:{}: equation ({n}) defined twice", i + 1));
            }
        }
    }
    if errors.is_empty() {
        Ok(Defined {
            equations,
            headings,
        })
    } else {
        Err(errors)
    }
}

/// `N` when a code-block line ends with two spaces or more and `(N)`.
fn defined_number(line: &str) -> Option<u32> {
    let body = line.trim_end().strip_suffix(')')?;
    let open = body.rfind('(')?;
    let digits = &body[open + 1..];
    let before = &body[..open];
    (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) && before.ends_with("  "))
        .then(|| digits.parse().ok())
        .flatten()
}

/// A number in parentheses at the start of `s`: its value and length.
fn number_at(s: &str) -> Option<(u32, usize)> {
    let rest = s.strip_prefix('(')?;
    let len = rest.bytes().take_while(u8::is_ascii_digit).count();
    if len == 0 || rest.as_bytes().get(len) != Some(&b')') {
        return None;
    }
    Some((rest[..len].parse().ok()?, len + 2))
}

/// A list of numbers at the start of `s` (`(N)`, `(N)-(M)`, items joined by `, ` or ` and `):
/// the ranges and the length consumed.
fn list_at(s: &str) -> Option<(Vec<(u32, u32)>, usize)> {
    let mut items = Vec::new();
    let mut pos = 0;
    loop {
        let (a, len) = number_at(&s[pos..])?;
        pos += len;
        let mut b = a;
        if let Some((m, len)) = s[pos..].strip_prefix('-').and_then(number_at) {
            b = m;
            pos += 1 + len;
        }
        items.push((a, b));
        let next = [", and ", ", ", " and "]
            .into_iter()
            .find(|sep| number_at(s[pos..].strip_prefix(sep).unwrap_or("")).is_some());
        match next {
            Some(sep) => pos += sep.len(),
            None => return Some((items, pos)),
        }
    }
}

/// The equation keywords, longest first: `(keyword, accepted before a parenthesis)`.
const KEYWORDS: [(&str, bool); 6] = [
    ("equations", false),
    ("equation", false),
    ("eqs.", true),
    ("eqs", false),
    ("eq.", true),
    ("eq", false),
];

/// Checks one line. `prose` is the document's own text (citations need no prefix, `paper
/// (N)` is allowed, bare numbers are not); otherwise it is code or README.
fn check_line(line: &str, prose: bool, defined: &Defined, at: &str, errors: &mut Vec<String>) {
    let lower = line.to_ascii_lowercase();
    let bytes = lower.as_bytes();
    let mut covered = vec![false; line.len()];
    let mut check_list = |start: usize, what: &str, errors: &mut Vec<String>| -> Option<usize> {
        let (items, len) = list_at(&line[start..])?;
        for (a, b) in items {
            if a > b {
                errors.push(format!("{at}: {what} range ({a})-({b}) runs backwards"));
            }
            for n in a..=b.max(a) {
                if !defined.equations.contains(&n) {
                    errors.push(format!("{at}: {what} ({n}), which {DOC} does not define"));
                }
            }
        }
        covered[start..start + len].fill(true);
        Some(len)
    };
    for i in 0..bytes.len() {
        if !line.is_char_boundary(i) {
            continue;
        }
        if i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_') {
            continue;
        }
        if prose && lower[i..].starts_with("paper ") {
            check_list(i + 6, "paper", &mut Vec::new());
            continue;
        }
        let Some(&(word, accepted)) = KEYWORDS.iter().find(|(k, _)| lower[i..].starts_with(k))
        else {
            continue;
        };
        let after = &line[i + word.len()..];
        if after.trim().is_empty() && line[..i].trim_end().ends_with("model.md") {
            errors.push(format!(
                "{at}: a citation split across lines: keep it on one"
            ));
            continue;
        }
        let Some(rest) = after.strip_prefix(' ') else {
            continue;
        };
        let first = rest.as_bytes().first().copied();
        let second = rest.as_bytes().get(1).copied();
        let cites = first.is_some_and(|b| b.is_ascii_digit())
            || (first == Some(b'(') && second.is_some_and(|b| b.is_ascii_digit()));
        if !cites {
            continue;
        }
        let shown: String = line[i..].chars().take(word.len() + 12).collect();
        if !accepted || first != Some(b'(') {
            errors.push(format!(
                "{at}: `{shown}...`: cite as `{DOC} eq. (N)` or `{DOC} eqs. (N)-(M)`"
            ));
            continue;
        }
        if !prose && !line[..i].trim_end().ends_with(DOC) {
            errors.push(format!(
                "{at}: `{shown}...` cites an equation without `{DOC}` in front"
            ));
            continue;
        }
        if check_list(i + word.len() + 1, "cites", errors).is_none() {
            errors.push(format!("{at}: `{shown}...`: malformed list of equations"));
        }
    }
    if prose {
        for (i, _) in line.match_indices('(') {
            let glued = i > 0 && line.as_bytes()[i - 1].is_ascii_alphanumeric();
            if !covered[i] && !glued && number_at(&line[i..]).is_some() {
                errors.push(format!(
                    "{at}: bare `{}`: write `eq. (N)` or `paper (N)`",
                    &line[i..i + number_at(&line[i..]).unwrap().1]
                ));
            }
        }
        return;
    }
    for (i, _) in line.match_indices(DOC) {
        if let Some(title) = line[i + DOC.len()..].strip_prefix(", \"") {
            let title = title.split('"').next().unwrap_or("");
            if !defined.headings.contains(title) {
                errors.push(format!(
                    "{at}: section \"{title}\" is not a heading of {DOC}"
                ));
            }
        }
    }
    if line.contains("shared/spec/model.md") {
        errors.push(format!(
            "{at}: `shared/spec/model.md` is not in the repository; cite `{DOC}`"
        ));
    }
}

/// The errors of the document's own prose and of every file's citations.
fn check(doc: &str, files: &[(String, String)]) -> Vec<String> {
    let defined = match definitions(doc) {
        Ok(d) => d,
        Err(e) => return e,
    };
    let mut errors = Vec::new();
    let mut in_code = false;
    for (i, line) in doc.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        } else if !in_code {
            check_line(
                line,
                true,
                &defined,
                &format!("{DOC}:{}", i + 1),
                &mut errors,
            );
        }
    }
    for (path, text) in files {
        for (i, line) in text.lines().enumerate() {
            check_line(
                line,
                false,
                &defined,
                &format!("{path}:{}", i + 1),
                &mut errors,
            );
        }
    }
    errors
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_string_lossy();
        if path.is_dir() && name != "target" && !name.starts_with('.') {
            rust_files(&path, out);
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_citation_names_an_equation_or_section_the_model_document_defines() {
    let root = root();
    let doc = read(&root.join(DOC));
    let mut paths = Vec::new();
    rust_files(&root.join("crates"), &mut paths);
    // This file, whose examples are wrong on purpose.
    paths.retain(|p| !p.ends_with("dynamics/tests/model_doc.rs"));
    assert!(paths.len() > 50, "found only {} .rs files", paths.len());
    paths.push(root.join("README.md"));
    let files: Vec<(String, String)> = paths
        .iter()
        .map(|p| {
            let shown = p.strip_prefix(&root).unwrap_or(p).display().to_string();
            (shown, read(p))
        })
        .collect();
    let defined = definitions(&doc).unwrap_or_else(|e| panic!("{}", e.join("\n")));
    assert!(
        defined.equations.len() >= 40,
        "{DOC} defines too few equations"
    );
    let errors = check(&doc, &files);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    let cited = files
        .iter()
        .filter(|(_, t)| t.contains("docs/model.md eq"))
        .count();
    assert!(cited >= 20, "only {cited} files cite {DOC}'s equations");
}

#[test]
fn the_checker_catches_wrong_citations() {
    let doc = "# Model\n\n## Earth\n\n```text\nx = 1      (1)\ny = 2      (2)\n```\n\
               Prose cites eq. (2) and paper (7).\n";
    let ok = |line: &str| check(doc, &[("a.rs".into(), line.into())]).is_empty();
    assert!(ok("//! docs/model.md eq. (1)"));
    assert!(ok("//! docs/model.md eqs. (1)-(2)"));
    assert!(ok(
        "//! docs/model.md eqs. (1), (2) and docs/model.md eq. (2)"
    ));
    assert!(ok(
        "//! docs/model.md, \"Earth\"; assert_eq!(a, b); impl Eq for X; (3)"
    ));
    // An undefined number, alone, in a range or in a list.
    assert!(!ok("//! docs/model.md eq. (3)"));
    assert!(!ok("//! docs/model.md eqs. (1)-(3)"));
    assert!(!ok("//! docs/model.md eqs. (2) and (9)"));
    // No document in front, the old style, an unknown section, the spec's path.
    assert!(!ok("//! see eq. (1)"));
    assert!(!ok("//! model.md eqs 1-2"));
    assert!(!ok("//! the rates of docs/model.md eqs."));
    assert!(!ok("//! docs/model.md, \"Gravity\""));
    assert!(!ok("//! as shared/spec/model.md says"));
    // The document: numbers out of order, a bare number in its prose.
    assert!(!check(&doc.replace("(1)\n", "(3)\n"), &[]).is_empty());
    assert!(!check(&format!("{doc}See (2).\n"), &[]).is_empty());
    assert!(check(doc, &[]).is_empty());
}
