//! Progress of a run: a bar on a terminal, plain lines on stderr otherwise (a cluster job's
//! log, `| tee log`).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Share of the simulated time between two progress lines.
const LINE_FRACTION: f64 = 0.1;
/// Longest wall time between two progress lines.
const LINE_WALL_INTERVAL: Duration = Duration::from_secs(30);

/// How a run reports its progress.
pub enum Progress {
    /// A progress bar, redrawn in place (stderr is a terminal).
    Bar(indicatif::ProgressBar),
    /// One line every 10 % of the simulated time or every 30 s of wall time.
    Lines(ProgressLines),
}

impl Progress {
    /// The bar on a terminal, lines otherwise; `None` when `enabled` is false (`--quiet`).
    pub fn start(enabled: bool, case: &str, duration: f64) -> Option<Progress> {
        if !enabled {
            return None;
        }
        if !std::io::stderr().is_terminal() {
            return Some(Progress::Lines(ProgressLines::new(case, duration)));
        }
        let pb = indicatif::ProgressBar::new((duration * 1000.0) as u64);
        pb.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} t = {pos} / {len} ms  {msg}  ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(Progress::Bar(pb))
    }

    /// Reports the simulated time `sim_time` (s) reached after `steps` steps.
    pub fn update(&mut self, sim_time: f64, steps: u64, started: Instant) {
        match self {
            Progress::Bar(pb) => {
                pb.set_position((sim_time * 1000.0) as u64);
                if steps.is_multiple_of(50) {
                    let el = started.elapsed().as_secs_f64();
                    pb.set_message(format!("{:.0} steps/s", steps as f64 / el.max(1e-9)));
                }
            }
            Progress::Lines(lines) => {
                if let Some(line) = lines.line_due(sim_time, steps, started.elapsed()) {
                    eprintln!("{line}");
                }
            }
        }
    }

    /// Clears the bar (the lines need no closing).
    pub fn finish(&self) {
        if let Progress::Bar(pb) = self {
            pb.finish_and_clear();
        }
    }
}

/// Plain progress lines: when the next one is due and what it says.
pub struct ProgressLines {
    case: String,
    duration: f64,
    next_fraction: f64,
    last_line: Duration,
}

impl ProgressLines {
    /// Lines for a run of `duration` simulated seconds.
    pub fn new(case: &str, duration: f64) -> Self {
        ProgressLines {
            case: case.to_string(),
            duration,
            next_fraction: LINE_FRACTION,
            last_line: Duration::ZERO,
        }
    }

    /// The line to print at `sim_time` after `steps` steps and `elapsed` wall time, when one
    /// is due: the simulated time passed the next 10 % mark, or 30 s passed since the last.
    pub fn line_due(&mut self, sim_time: f64, steps: u64, elapsed: Duration) -> Option<String> {
        let fraction = (sim_time / self.duration).clamp(0.0, 1.0);
        let mark_passed = fraction >= self.next_fraction - 1e-9;
        let wall_passed = elapsed >= self.last_line + LINE_WALL_INTERVAL;
        if !mark_passed && !wall_passed {
            return None;
        }
        while self.next_fraction <= fraction + 1e-9 {
            self.next_fraction += LINE_FRACTION;
        }
        self.last_line = elapsed;
        Some(self.format(sim_time, steps, elapsed))
    }

    fn format(&self, sim_time: f64, steps: u64, elapsed: Duration) -> String {
        let wall = elapsed.as_secs_f64();
        let steps_per_s = steps as f64 / wall.max(1e-9);
        let eta = if sim_time > 0.0 {
            wall * (self.duration - sim_time).max(0.0) / sim_time
        } else {
            f64::NAN
        };
        format!(
            "{}: t = {:.3} / {} s ({:.0} %), {:.0} steps/s, ETA {}",
            self.case,
            sim_time,
            self.duration,
            100.0 * sim_time / self.duration,
            steps_per_s,
            format_eta(eta)
        )
    }
}

/// A remaining time as `1 h 02 min`, `3 min 05 s` or `12 s`.
fn format_eta(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "unknown".into();
    }
    let s = seconds.round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_per_tenth_of_the_simulated_time() {
        let mut lines = ProgressLines::new("case", 2.0);
        let mut printed = Vec::new();
        for step in 1..=2000u64 {
            let t = step as f64 * 0.001;
            let elapsed = Duration::from_millis(step);
            if let Some(line) = lines.line_due(t, step, elapsed) {
                printed.push(line);
            }
        }
        assert_eq!(printed.len(), 10, "{printed:#?}");
        assert!(
            printed[0].contains("t = 0.200 / 2 s (10 %)"),
            "{}",
            printed[0]
        );
        assert!(printed[0].contains("1000 steps/s"), "{}", printed[0]);
        assert!(printed[0].contains("ETA 2 s"), "{}", printed[0]);
        assert!(printed[9].contains("(100 %)"), "{}", printed[9]);
    }

    #[test]
    fn a_line_every_30_s_of_wall_time_in_between() {
        let mut lines = ProgressLines::new("case", 100.0);
        assert!(lines.line_due(0.1, 10, Duration::from_secs(29)).is_none());
        let line = lines.line_due(0.2, 20, Duration::from_secs(30)).unwrap();
        assert!(line.contains("ETA 4 h 09 min"), "{line}");
        assert!(lines.line_due(0.3, 30, Duration::from_secs(31)).is_none());
        assert!(lines.line_due(0.4, 40, Duration::from_secs(60)).is_some());
    }

    #[test]
    fn eta_reads_as_hours_minutes_seconds() {
        assert_eq!(format_eta(12.4), "12 s");
        assert_eq!(format_eta(185.0), "3 min 05 s");
        assert_eq!(format_eta(3720.0), "1 h 02 min");
        assert_eq!(format_eta(f64::NAN), "unknown");
    }
}
