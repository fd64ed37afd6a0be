//! The terminal's progress bars of a long run.

/// The terminal's progress display of a long run: a bar per scene (its references and
/// techniques) that stays when the scene is done, and under it a bar of the running technique's
/// steps (prepare, warm-up, error and timed frames). Hidden when `show` is false or stderr is
/// no terminal; lines printed through [`Progress::say`] appear above the bars.
pub struct Progress {
    multi: indicatif::MultiProgress,
    show: bool,
}

impl Progress {
    pub fn new(show: bool) -> Self {
        let multi = match show {
            true => indicatif::MultiProgress::new(),
            false => {
                indicatif::MultiProgress::with_draw_target(indicatif::ProgressDrawTarget::hidden())
            }
        };
        Progress { multi, show }
    }

    fn bar(&self, len: u64, template: &str) -> indicatif::ProgressBar {
        if !self.show {
            return indicatif::ProgressBar::hidden();
        }
        let bar = self.multi.add(indicatif::ProgressBar::new(len));
        if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        // Keeps the clock moving during long steps (a CPU reference takes seconds).
        bar.enable_steady_tick(std::time::Duration::from_millis(250));
        bar
    }

    /// A scene's bar: `len` steps (its reference and each technique), named by `prefix`.
    pub fn scene(&self, prefix: &str, len: u64) -> indicatif::ProgressBar {
        let bar = self.bar(
            len,
            "{elapsed_precise} {prefix:24!} [{bar:24}] {pos}/{len} {wide_msg}",
        );
        bar.set_prefix(prefix.to_string());
        bar
    }

    /// The running technique's bar (cleared when it finishes).
    pub fn technique(&self, name: &str) -> indicatif::ProgressBar {
        let bar = self.bar(1, "         {prefix:24!} [{bar:24}] {pos}/{len} {wide_msg}");
        bar.set_prefix(format!("  {name}"));
        bar
    }

    /// Shows a technique's step on its bar: what `run::run_technique` tells its `on_frame`.
    pub fn step(bar: &indicatif::ProgressBar, step: &str, done: usize, total: usize) {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(step.to_string());
    }

    /// Prints a line above the bars.
    pub fn say(&self, line: &str) {
        self.multi.suspend(|| eprintln!("{line}"));
    }
}
