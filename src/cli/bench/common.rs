//! What the file benchmarks share: their input/folder/repeat arguments and the best-of-N timer
//! that also records each step's peak memory.

use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct FileArgs {
    /// The mesh to read (any encoding); what is written goes into --dir and is read back.
    pub input: PathBuf,
    /// Folder for the files written (default: beside the input).
    #[arg(long)]
    pub dir: Option<PathBuf>,
    /// Runs per step; the best time is reported.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Print JSON (for the scripts/bench_*.py drivers) instead of a table.
    #[arg(long)]
    pub json: bool,
}

impl FileArgs {
    /// The folder to write into, created if missing.
    pub fn out_dir(&self) -> anyhow::Result<PathBuf> {
        let dir = match &self.dir {
            Some(d) => d.clone(),
            None => self
                .input
                .parent()
                .map(|p| p.to_path_buf())
                .unwrap_or_default(),
        };
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        Ok(dir)
    }
}

/// Returns freed heap to the system and resets the kernel's peak-RSS mark (Linux: `5` into
/// /proc/self/clear_refs), so each step's peak is its own and not the last step's leftovers.
fn reset_peak() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free memory held by the allocator.
    unsafe {
        libc::malloc_trim(0);
    }
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory since the last reset, in bytes (Linux VmHWM).
fn peak_rss() -> Option<usize> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// One timed step: its best time over the runs and the largest peak memory of any run.
pub struct Step {
    pub name: String,
    pub best_s: f64,
    pub peak: Option<usize>,
}

/// Runs `f` `repeat` times (at least once) and keeps the best time and the last value; the
/// previous run's value is dropped before the next starts so runs do not hold two results.
pub fn time<T>(
    name: &str,
    repeat: usize,
    mut f: impl FnMut() -> anyhow::Result<T>,
) -> anyhow::Result<(Step, T)> {
    let mut best = f64::INFINITY;
    let mut peak = None;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        drop(last.take());
        reset_peak();
        let t = Instant::now();
        let v = f()?;
        best = best.min(t.elapsed().as_secs_f64());
        if let Some(p) = peak_rss() {
            peak = Some(peak.map_or(p, |e: usize| e.max(p)));
        }
        last = Some(v);
    }
    let v = last.context("no run")?;
    Ok((
        Step {
            name: name.to_string(),
            best_s: best,
            peak,
        },
        v,
    ))
}
