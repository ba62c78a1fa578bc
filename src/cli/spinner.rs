//! The progress line on stderr of a solve and of the studies made of
//! solves (refine, magnification), and of `heat --from-run`: a steadily
//! ticking spinner whose message is the latest active-set iteration, under
//! the stage of a heated solve it belongs to; lines of the caller's print
//! above it.

use indicatif::{ProgressBar, ProgressStyle};

use crate::solver::Observer;

/// A spinner on stderr (hidden where stderr is not a terminal), and the
/// stage of a heated solve the iterations belong to.
pub(super) struct Spinner {
    pub(super) bar: ProgressBar,
    stage: Option<String>,
}

impl Spinner {
    /// A spinner showing `message`, ticking every 200 ms until cleared.
    pub(super) fn start(message: impl Into<String>) -> Self {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .expect("valid template"),
        );
        bar.set_message(message.into());
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        Self { bar, stage: None }
    }

    /// A finished level's or point's line and its warnings, printed above
    /// the spinner.
    pub(super) fn finished(&self, line: &str, warnings: &[String]) {
        self.bar.suspend(|| {
            eprintln!("{line}");
            for w in warnings {
                eprintln!("  warning: {w}");
            }
        });
    }
}

impl Observer for Spinner {
    fn iteration(&mut self, iteration: usize, matvecs: usize, residual: f64, contact_cells: usize) {
        let line = format!(
            "active-set iteration {iteration}: {contact_cells} cells in contact, residual {residual:.2e}, {matvecs} matvecs"
        );
        match &self.stage {
            Some(stage) => self.bar.set_message(format!("{stage}; {line}")),
            None => self.bar.set_message(line),
        }
        self.bar.tick();
    }

    fn stage(&mut self, label: &str) {
        self.bar.set_message(label.to_string());
        self.bar.tick();
        self.stage = Some(label.to_string());
    }
}
