//! Progress of long coefficient stages: a bar with an ETA on stderr that
//! appears only once a stage has run for [`SHOW_AFTER`] (and only when
//! stderr is a terminal), so quick tables print nothing.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A stage shows its bar once it has run this long.
pub const SHOW_AFTER: Duration = Duration::from_secs(2);

/// Progress of one stage of `total` steps; shareable across rayon tasks.
pub(crate) struct Progress {
    bar: ProgressBar,
    start: Instant,
    shown: AtomicBool,
}

impl Progress {
    /// A hidden bar for a stage called `label`.
    pub(crate) fn new(label: &str, total: u64) -> Self {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} {bar:30} {pos}/{len} rows, {elapsed_precise} elapsed, ETA {eta_precise}",
            )
            .expect("valid template"),
        );
        bar.set_message(label.to_string());
        Self {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(false),
        }
    }

    /// One step done; shows the bar once the stage is older than
    /// [`SHOW_AFTER`].
    pub(crate) fn inc(&self) {
        self.bar.inc(1);
        if !self.shown.load(Ordering::Relaxed)
            && self.start.elapsed() >= SHOW_AFTER
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Clear the bar.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
