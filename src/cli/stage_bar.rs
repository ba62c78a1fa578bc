//! The bar of long coefficient stages ([`crate::kernel::progress`]) on
//! stderr: hidden until a stage has run for [`SHOW_AFTER`] (and only when
//! stderr is a terminal), so quick tables print nothing.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::kernel::progress::{StageObserver, StageTicker};

/// A stage shows its bar once it has run this long.
pub const SHOW_AFTER: Duration = Duration::from_secs(2);

/// Draws every stage as a bar.
pub struct StageBars;

struct StageBar {
    bar: ProgressBar,
    start: Instant,
    shown: AtomicBool,
}

impl StageObserver for StageBars {
    fn stage(&self, label: &str, total: u64) -> Box<dyn StageTicker> {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} {bar:30} {pos}/{len} rows, {elapsed_precise} elapsed, ETA {eta_precise}",
            )
            .expect("valid template"),
        );
        bar.set_message(label.to_string());
        Box::new(StageBar {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(false),
        })
    }
}

impl StageTicker for StageBar {
    fn inc(&self) {
        self.bar.inc(1);
        if !self.shown.load(Ordering::Relaxed)
            && self.start.elapsed() >= SHOW_AFTER
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
