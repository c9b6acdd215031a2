//! Names a user gives that become paths, and any user text echoed in a message.

/// Checks that `name` (a study's or dataset's name, the last part of its default results
/// folder) is a plain name: 1 to 100 ASCII letters, digits, `-`, `_` or `.`, not starting
/// with `.`. Anything else (`../x`, `/tmp/x`, `""`, a control character) would write outside
/// `results/`. `key` names the setting in the message.
///
/// ```
/// use navkf_report::names::plain_name;
/// assert!(plain_name("study.name", "paper-2009_v1.2").is_ok());
/// for bad in ["", "../x", "/tmp/x", "a/b", ".hidden", "a\u{1b}[31m"] {
///     assert!(plain_name("study.name", bad).is_err(), "{bad:?}");
/// }
/// ```
pub fn plain_name(key: &str, name: &str) -> Result<(), String> {
    let ok_char = |c: char| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.');
    if name.is_empty() || name.len() > 100 || name.starts_with('.') || !name.chars().all(ok_char) {
        return Err(format!(
            "{key} = {}: expected a plain name (1 to 100 letters, digits, '-', '_' or '.', not starting with '.'); it names the folder under results/",
            shown(name)
        ));
    }
    Ok(())
}

/// `text` quoted for a message: control characters escaped, and cut after 40 characters
/// with its length shown.
pub fn shown(text: &str) -> String {
    const MAX: usize = 40;
    let count = text.chars().count();
    let head: String = text.chars().take(MAX).collect();
    let escaped = format!("{head:?}");
    if count > MAX {
        format!("{escaped}... ({count} characters)")
    } else {
        escaped
    }
}
