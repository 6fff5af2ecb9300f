//! Progress of a report run: a bar on a terminal; off one (CI, `| tee`, stderr to a file), plain
//! lines on stderr saying what runs, `n of N`, the time elapsed and an estimate of the time left,
//! at most one every [`LINE_INTERVAL`] (and the first and last).

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Shortest time between two plain progress lines.
pub const LINE_INTERVAL: Duration = Duration::from_secs(10);

/// A bar or plain lines, with the same calls.
pub struct Progress {
    bar: Option<ProgressBar>,
    total: u64,
    pos: u64,
    message: String,
    start: Instant,
    last_line: Option<Instant>,
}

impl Progress {
    /// Progress over `total` steps: a bar when stderr is a terminal, plain lines otherwise.
    pub fn new(total: u64) -> Self {
        Self::with_mode(total, std::io::stderr().is_terminal())
    }

    /// Progress over `total` steps, as a bar or as plain lines.
    pub fn with_mode(total: u64, bar: bool) -> Self {
        let bar = bar.then(|| {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b
        });
        Self {
            bar,
            total,
            pos: 0,
            message: String::new(),
            start: Instant::now(),
            last_line: None,
        }
    }

    /// What runs now.
    pub fn set_message(&mut self, message: String) {
        if let Some(b) = &self.bar {
            b.set_message(message.clone());
        }
        self.message = message;
        if self.last_line.is_none() {
            self.line();
        }
    }

    /// One step done.
    pub fn inc(&mut self) {
        self.pos += 1;
        if let Some(b) = &self.bar {
            b.inc(1);
        } else if self.pos == self.total
            || self.last_line.is_none_or(|t| t.elapsed() >= LINE_INTERVAL)
        {
            self.line();
        }
    }

    /// Runs `f` (which prints) without the bar drawn over it.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(b) => b.suspend(f),
            None => f(),
        }
    }

    /// Ends the bar (plain lines end with the last step's line).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_with_message("done");
        }
    }

    /// The plain line for the current state.
    pub fn status_line(&self) -> String {
        let elapsed = self.start.elapsed();
        let left = if self.pos == 0 {
            "estimating".to_string()
        } else {
            let per = elapsed.as_secs_f64() / self.pos as f64;
            format!(
                "about {} left",
                clock(per * self.total.saturating_sub(self.pos) as f64)
            )
        };
        format!(
            "[{} of {}] {} elapsed, {left}: {}",
            self.pos,
            self.total,
            clock(elapsed.as_secs_f64()),
            self.message
        )
    }

    fn line(&mut self) {
        eprintln!("{}", self.status_line());
        self.last_line = Some(Instant::now());
    }
}

/// `1h02m03s`, `4m05s` or `6s`.
fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}m{s:02}s"),
        (h, m, s) => format!("{h}h{m:02}m{s:02}s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_lines_say_n_of_n_elapsed_and_time_left() {
        let mut p = Progress::with_mode(4, false);
        p.set_message("torus: pcss 7x7-9x9 cpu 256".into());
        p.inc();
        let line = p.status_line();
        assert!(line.starts_with("[1 of 4] "), "{line}");
        assert!(
            line.contains("elapsed, about ") && line.ends_with("left: torus: pcss 7x7-9x9 cpu 256"),
            "{line}"
        );
        assert_eq!(clock(3723.0), "1h02m03s");
        assert_eq!(clock(245.0), "4m05s");
        assert_eq!(clock(6.4), "6s");
    }
}
