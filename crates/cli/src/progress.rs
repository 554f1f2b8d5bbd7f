//! A progress bar that appears only when work takes more than a second and
//! stderr is a terminal: short runs and scripts stay quiet.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

/// Shows progress of one long task.
pub struct Progress {
    start: Instant,
    label: String,
    bar: Mutex<Option<ProgressBar>>,
    enabled: bool,
    /// Where the bar goes when several run at once (`batch`).
    multi: Option<MultiProgress>,
}

impl Progress {
    /// A progress display for `label`; `enabled` false keeps it silent.
    pub fn new(label: &str, enabled: bool) -> Self {
        Progress {
            start: Instant::now(),
            label: label.to_string(),
            bar: Mutex::new(None),
            enabled: enabled && std::io::IsTerminal::is_terminal(&std::io::stderr()),
            multi: None,
        }
    }

    /// A progress display for `label` shown among the bars of `multi`.
    pub fn in_multi(label: &str, multi: &MultiProgress, enabled: bool) -> Self {
        Progress {
            multi: Some(multi.clone()),
            ..Progress::new(label, enabled)
        }
    }

    /// Reports the fraction done.
    pub fn set(&self, fraction: f64) {
        if !self.enabled || self.start.elapsed() < Duration::from_secs(1) {
            return;
        }
        let Ok(mut guard) = self.bar.lock() else {
            return;
        };
        let bar = guard.get_or_insert_with(|| {
            let b = ProgressBar::new(1000);
            if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:30}] {percent}% {elapsed}")
            {
                b.set_style(style.progress_chars("=> "));
            }
            b.set_message(self.label.clone());
            match &self.multi {
                Some(m) => m.add(b),
                None => b,
            }
        });
        bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
    }

    /// Removes the bar, if one was shown.
    pub fn finish(&self) {
        if let Ok(mut g) = self.bar.lock() {
            if let Some(b) = g.take() {
                b.finish_and_clear();
            }
        }
    }
}

impl wildlod_pipeline::MeshProgress for Progress {
    fn set(&self, fraction: f64) {
        Progress::set(self, fraction);
    }

    fn finish(&self) {
        Progress::finish(self);
    }
}
