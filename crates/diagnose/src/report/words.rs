//! The report's small words: numbers, ratios and outcomes as `report.md` and the findings
//! write them.

use crate::candidates::evidence::Outcome;

/// A number in the report's tables: five significant digits, `-` when not finite.
pub fn fmt(v: f64) -> String {
    navkf_report::markdown::number(v, navkf_report::markdown::Number::Sci(4))
}

/// A sigma ratio in words: "12x", "1.3x", "0.2x".
pub fn times(r: f64) -> String {
    if r >= 10.0 {
        format!("{r:.0}x")
    } else if r >= 0.1 {
        format!("{r:.2}x")
    } else {
        format!("{r:.1e}x")
    }
}

/// `s` with its first letter in upper case.
pub fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// The outcome as the report's table shows it: in words, a named candidate in bold.
pub fn outcome_words(o: Outcome) -> String {
    match o {
        Outcome::Named => format!("**{o}**"),
        _ => o.to_string(),
    }
}
