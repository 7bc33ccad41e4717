//! The progress bar: an observer of the run, and the Ctrl-C switch.

use indicatif::{ProgressBar, ProgressStyle};
use junta::{Flow, Increment, Observer, RunLog};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// A spinner with the phase or the last increment; asks the run to stop
/// after Ctrl-C.
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A spinner showing `msg` (hidden when `enabled` is false). Installs
    /// the Ctrl-C handler.
    pub fn new(enabled: bool, msg: String) -> Self {
        let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
        if !enabled {
            return Progress {
                bar: ProgressBar::hidden(),
            };
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}") {
            bar.set_style(style);
        }
        bar.set_message(msg);
        bar.enable_steady_tick(Duration::from_millis(200));
        Progress { bar }
    }

    /// Run `f` with the spinner hidden (for messages).
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    /// Remove the spinner.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Observer for Progress {
    fn on_increment(&mut self, inc: &Increment<'_>, _log: &RunLog) -> junta::Result<Flow> {
        let r = inc.report;
        self.bar.set_message(format!(
            "increment {} lambda = {:.5} ({} iterations{}), {}/{} interface points failed",
            r.increment_index,
            r.lambda,
            r.iterations,
            if r.small_increment_mode {
                ", small increments"
            } else {
                ""
            },
            inc.row.failed,
            inc.row.points
        ));
        let mut stop = INTERRUPTED.load(Ordering::SeqCst);
        if let Some(c) = junta_core::distributed::collective() {
            // over MPI ranks: all stop at the same increment
            stop = c.any(stop);
        }
        if stop {
            return Ok(Flow::Interrupt);
        }
        Ok(Flow::Continue)
    }
    fn on_phase(&mut self, phase: &junta::Phase) {
        self.bar.set_message(phase.to_string());
    }
}
