//! Progress bars, one per task: runs done / total, elapsed time and estimated time left.
//! Shown only when stdout is a terminal (so logs and CI output stay clean); the bars themselves
//! are drawn on stderr, which indicatif also hides when it is not a terminal.
//!
//! ```ignore
//! let progress = Progress::for_stdout();
//! let bar = progress.start("Task I", 4 * 10);   // methods × seeds
//! bar.skip_already_done(finished_before);        // runs found in <out>/runs/ (resume)
//! // in each finished run (TaskProgress is Clone + Send + Sync):
//! bar.inc();
//! bar.finish();
//! ```

use std::io::IsTerminal as _;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The bar layout: task name, bar, runs done / total, elapsed, estimated time left.
const TEMPLATE: &str =
    "{prefix:>8} [{bar:30}] {pos:>4}/{len} runs  elapsed {elapsed_precise}  left ~{eta_precise}";

/// A set of per-task progress bars drawn together.
#[derive(Debug, Clone)]
pub(crate) struct Progress {
    bars: MultiProgress,
}

/// The progress bar of one task; clones share the bar, so parallel workers can each hold one.
#[derive(Debug, Clone)]
pub(crate) struct TaskProgress {
    bar: ProgressBar,
}

impl Progress {
    /// Bars on stderr when stdout is a terminal, hidden otherwise.
    pub(crate) fn for_stdout() -> Self {
        if std::io::stdout().is_terminal() {
            Self::with_target(ProgressDrawTarget::stderr())
        } else {
            Self::hidden()
        }
    }

    /// Bars that count but never draw (tests, redirected output).
    pub(crate) fn hidden() -> Self {
        Self::with_target(ProgressDrawTarget::hidden())
    }

    fn with_target(target: ProgressDrawTarget) -> Self {
        Self {
            bars: MultiProgress::with_draw_target(target),
        }
    }

    /// Starts the bar of `task`, which has `total` runs to do.
    pub(crate) fn start(&self, task: &str, total: u64) -> TaskProgress {
        let style = ProgressStyle::with_template(TEMPLATE)
            .expect("TEMPLATE is a valid constant (checked by a test)")
            .progress_chars("=> ");
        let bar = self.bars.add(
            ProgressBar::new(total)
                .with_style(style)
                .with_prefix(task.to_owned()),
        );
        TaskProgress { bar }
    }
}

impl TaskProgress {
    /// Counts one more finished run.
    pub(crate) fn inc(&self) {
        self.bar.inc(1);
    }

    /// Counts `runs` found finished by an earlier, interrupted invocation (resume), without
    /// letting their instant completion distort the estimate of the time left.
    pub(crate) fn skip_already_done(&self, runs: u64) {
        self.bar.inc(runs);
        self.bar.reset_eta();
    }

    /// Marks the task finished, leaving its final state on screen.
    pub(crate) fn finish(&self) {
        self.bar.finish();
    }

    #[cfg_attr(
        not(test),
        expect(dead_code, reason = "only tests read the counts back")
    )]
    /// Runs counted so far.
    pub(crate) fn done(&self) -> u64 {
        self.bar.position()
    }

    #[cfg_attr(
        not(test),
        expect(dead_code, reason = "only tests read the counts back")
    )]
    /// Whether [`TaskProgress::finish`] was called.
    pub(crate) fn is_finished(&self) -> bool {
        self.bar.is_finished()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn template_is_valid() {
        assert!(ProgressStyle::with_template(TEMPLATE).is_ok());
    }

    #[test]
    fn bars_count_runs_per_task() {
        let progress = Progress::hidden();
        let maze = progress.start("Task I", 3);
        let robot = progress.start("robot", 2);
        let worker = maze.clone();
        std::thread::scope(|scope| {
            scope.spawn(|| worker.inc());
            scope.spawn(|| maze.inc());
        });
        robot.skip_already_done(1);
        robot.inc();
        assert_eq!(maze.done(), 2);
        assert_eq!(robot.done(), 2);
        assert!(!maze.is_finished());
        maze.finish();
        assert!(maze.is_finished());
    }
}
