//! Progress of long coefficient stages, reported to the one
//! [`StageObserver`] a front end installs ([`set_stage_observer`]; the
//! command line draws a bar on stderr once a stage has run a while).
//! Without one, stages report nothing: the library prints nothing itself.

use std::sync::OnceLock;

/// Counts the steps of one stage; shared across rayon tasks.
pub trait StageTicker: Send + Sync {
    /// One step done.
    fn inc(&self);
    /// The stage is over.
    fn finish(&self);
}

/// Hears about long coefficient stages.
pub trait StageObserver: Send + Sync {
    /// A stage called `label` of `total` steps starts.
    fn stage(&self, label: &str, total: u64) -> Box<dyn StageTicker>;
}

static OBSERVER: OnceLock<Box<dyn StageObserver>> = OnceLock::new();

/// Install the process's stage observer (the first one installed stays).
pub fn set_stage_observer(observer: Box<dyn StageObserver>) {
    let _ = OBSERVER.set(observer);
}

/// Progress of one stage of `total` steps; shareable across rayon tasks.
pub(crate) struct Progress {
    ticker: Option<Box<dyn StageTicker>>,
}

impl Progress {
    /// A stage called `label`, reported to the installed observer if any.
    pub(crate) fn new(label: &str, total: u64) -> Self {
        Self {
            ticker: OBSERVER.get().map(|o| o.stage(label, total)),
        }
    }

    /// One step done.
    pub(crate) fn inc(&self) {
        if let Some(t) = &self.ticker {
            t.inc();
        }
    }

    /// The stage is over.
    pub(crate) fn finish(&self) {
        if let Some(t) = &self.ticker {
            t.finish();
        }
    }
}
