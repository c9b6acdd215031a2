//! A figure's section of a report: its heading, the one question it answers, then the image
//! (or why it was not drawn).
//!
//! A figure that does not say what it answers leaves its reader to guess what to look at, and
//! a reviewer to guess whether it shows what the text claims. So every report writes its
//! figures through [`FigureOutcome::markdown`], and [`embeds_without_question`] lets a test
//! prove that no image of a report stands without its question.
//!
//! ```
//! use navkf_report::figure::{embeds_without_question, FigureOutcome};
//! let f = FigureOutcome {
//!     name: "step_cost".into(),
//!     caption: "Cost of one filter step".into(),
//!     question: "What does one predict + update cost with each filter?".into(),
//!     result: Ok(()),
//! };
//! let md = f.markdown(3);
//! assert_eq!(
//!     md,
//!     "### Cost of one filter step\n\n*Answers:* What does one predict + update cost with \
//!      each filter?\n\n![Cost of one filter step](step_cost.png)\n"
//! );
//! assert!(embeds_without_question(&md).is_empty());
//! assert_eq!(embeds_without_question("![x](x.png)\n"), vec!["x.png".to_string()]);
//! ```

use super::FigureOutcome;

/// The words that open a figure's question in a report.
pub const ANSWERS: &str = "*Answers:*";

impl FigureOutcome {
    /// The figure's section at heading `level` (1-6): heading (its caption), then
    /// [`FigureOutcome::embed`].
    pub fn markdown(&self, level: usize) -> String {
        let hashes = "#".repeat(level.clamp(1, 6));
        format!("{hashes} {}\n\n{}", self.caption, self.embed())
    }

    /// The question the figure answers, then its PNG embed, or the reason it was not drawn:
    /// for a report that writes its own heading and text above.
    pub fn embed(&self) -> String {
        let body = match &self.result {
            Ok(()) => format!("![{}]({}.png)", self.caption, self.name),
            Err(e) => format!("Not drawn: {e}"),
        };
        format!("{ANSWERS} {}\n\n{body}\n", self.question)
    }
}

/// The images embedded in `md` (`![..](target)`) that no question introduces: the nearest
/// non-blank line above the embed must open with [`ANSWERS`] and name a question (end in
/// `?`). Returns their targets, in order.
pub fn embeds_without_question(md: &str) -> Vec<String> {
    let lines: Vec<&str> = md.lines().collect();
    let mut missing = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let mut rest = *line;
        while let Some(at) = rest.find("![") {
            let after = &rest[at..];
            let target = after
                .find("](")
                .and_then(|open| after[open + 2..].find(')').map(|c| (open, c)))
                .map(|(open, close)| after[open + 2..open + 2 + close].to_string());
            let Some(target) = target else { break };
            let asked = at == 0
                && lines[..i]
                    .iter()
                    .rev()
                    .find(|l| !l.trim().is_empty())
                    .is_some_and(|l| {
                        let l = l.trim();
                        l.starts_with(ANSWERS) && l.ends_with('?')
                    });
            if !asked {
                missing.push(target);
            }
            rest = &after[2..];
        }
    }
    missing
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fig(result: Result<(), String>) -> FigureOutcome {
        FigureOutcome {
            name: "nis".into(),
            caption: "NIS per degree of freedom".into(),
            question: "Is the model consistent?".into(),
            result,
        }
    }

    #[test]
    fn a_section_that_was_not_drawn_says_why_and_embeds_nothing() {
        let md = fig(Err("no data".into())).markdown(2);
        assert!(md.starts_with("## NIS per degree of freedom\n"));
        assert!(md.contains("Not drawn: no data"));
        assert!(!md.contains("!["));
    }

    #[test]
    fn an_embed_inside_a_paragraph_or_after_a_statement_is_found() {
        let md = "Some text ![d](detection.png)\n\n*Answers:* not a question.\n\n![e](e.png)\n";
        assert_eq!(embeds_without_question(md), vec!["detection.png", "e.png"]);
        let ok = format!("{}\n{}", fig(Ok(())).markdown(3), fig(Ok(())).markdown(3));
        assert!(embeds_without_question(&ok).is_empty());
    }

    #[test]
    fn a_question_serves_only_the_embed_right_under_it() {
        let md = "*Answers:* What?\n\n![a](a.png)\n\n![b](b.png)\n";
        assert_eq!(embeds_without_question(md), vec!["b.png"]);
    }
}
