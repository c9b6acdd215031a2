//! What a user watches while a study or a diagnosis works: a bar over the units of a study
//! (runs, points, datasets), fed by the [`crate::executor`]'s observer, and a spinner with the
//! elapsed time for one long task. Both draw only on a terminal and are cleared when dropped,
//! however the command ends.

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over `total` `what` (`runs`, `datasets`), hidden with `quiet`.
pub fn bar(quiet: bool, total: usize, what: &str) -> Progress {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{prefix}} [{{bar:40}}] {{pos}}/{{len}} {what}, {{elapsed}} elapsed, ETA {{eta}}"
        ))
        .expect("a valid template")
        .progress_chars("=> "),
    );
    Progress(bar)
}

/// A spinner with a message and the elapsed time, ticking on its own.
pub fn spinner(message: String) -> Progress {
    let spinner = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("{spinner} {msg} ({elapsed})").expect("a valid template"),
    );
    spinner.enable_steady_tick(std::time::Duration::from_millis(200));
    spinner.set_message(message);
    Progress(spinner)
}

/// A bar or spinner, removed from the terminal when dropped (an error's early return
/// included).
pub struct Progress(ProgressBar);

impl std::ops::Deref for Progress {
    type Target = ProgressBar;
    fn deref(&self) -> &ProgressBar {
        &self.0
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}
