//! The spinner of a study's solves on stderr (refine, magnification): it
//! shows each active-set iteration, and the study's own lines print above
//! it.

use indicatif::{ProgressBar, ProgressStyle};

use crate::solver::Observer;

/// A steadily ticking spinner whose message is the solve's latest
/// active-set iteration.
pub(super) struct StudySpinner {
    pub(super) bar: ProgressBar,
}

impl StudySpinner {
    /// A spinner on stderr, ticking every 200 ms until it is cleared.
    pub(super) fn start() -> Self {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .expect("valid template"),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        Self { bar }
    }
}

impl Observer for StudySpinner {
    fn iteration(&mut self, iteration: usize, matvecs: usize, residual: f64, contact_cells: usize) {
        super::solve::show_iteration(&self.bar, iteration, matvecs, residual, contact_cells);
    }
}
