//! Feedback while rendering: a progress bar with ETA (indicatif) when
//! stderr is a terminal, else plain or JSON lines; the live preview window;
//! and Ctrl-C, which cancels the render (or the script) in progress.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{LazyLock, Mutex};
use std::time::{Duration, Instant};

use glam::Vec3;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::preview::Preview;
use crate::render::{Job, Rect};

/// Set by Ctrl-C (SIGINT, SIGTERM, SIGHUP); renders and the interpreter
/// stop soon after. The REPL clears it once it has reported the interrupt.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Set while the REPL runs a line: a second Ctrl-C then does not end the
/// session (the first is on its way).
pub static IN_REPL: AtomicBool = AtomicBool::new(false);

/// Set for the whole of a REPL session: the grace after Ctrl-C never ends
/// it (a terminal in line mode sends SIGINT at the prompt too).
pub static REPL_SESSION: AtomicBool = AtomicBool::new(false);

/// Temporary files being written (`AtomicFile`), removed by `exit_now`.
static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Standard output's buffer, shared so that `exit_now` can flush it.
pub static STDOUT: LazyLock<Mutex<std::io::BufWriter<std::io::Stdout>>> =
    LazyLock::new(|| Mutex::new(std::io::BufWriter::with_capacity(1 << 16, std::io::stdout())));

/// Set when `--time-limit` ran out (then `INTERRUPTED` is set too): the
/// run ends with `EXIT_TIMED_OUT`.
pub static TIMED_OUT: AtomicBool = AtomicBool::new(false);

/// How long a run has, after the first Ctrl-C (or its time limit), to
/// stop by itself, with its messages at their lines, before the process
/// ends at once (`exit_now`): whatever it was waiting on (a FIFO with no
/// writer, `gets` on an endless line, a program run by `exec`) cannot
/// hold it longer. Not in the REPL, which must keep its session.
const GRACE: Duration = Duration::from_millis(450);

/// Routes Ctrl-C (SIGINT, SIGTERM, SIGHUP) to `INTERRUPTED`; a second one
/// while the first is still pending (outside the REPL) ends the process at
/// once, cleanly (`exit_now`), and so does the first when the run has not
/// stopped within `GRACE`. Writes past `ulimit -f` fail with an error
/// instead of SIGXFSZ killing the process.
pub fn catch_interrupts() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            if !IN_REPL.load(Ordering::SeqCst) {
                exit_now();
            }
            return;
        }
        watchdog();
    });
    let ignored = std::sync::Arc::new(AtomicBool::new(false));
    let _ = signal_hook::flag::register(signal_hook::consts::SIGXFSZ, ignored);
}

/// Ends the process after `GRACE` unless it is in a REPL session.
fn watchdog() {
    let _ = std::thread::Builder::new().name("watchdog".into()).spawn(|| {
        std::thread::sleep(GRACE);
        let in_repl = IN_REPL.load(Ordering::SeqCst) || REPL_SESSION.load(Ordering::SeqCst);
        if !in_repl && INTERRUPTED.load(Ordering::SeqCst) {
            exit_now();
        }
    });
}

/// `--time-limit`: after `seconds` of wall-clock time the run is ended
/// as by Ctrl-C, with status 124.
pub fn limit_time(seconds: f64) {
    let _ = std::thread::Builder::new().name("time-limit".into()).spawn(move || {
        std::thread::sleep(Duration::from_secs_f64(seconds));
        TIMED_OUT.store(true, Ordering::SeqCst);
        if !INTERRUPTED.swap(true, Ordering::SeqCst) {
            watchdog();
        }
    });
}

/// Ends the process as interrupted (status 130, or 124 past the time
/// limit): temporary files removed, buffered output flushed.
pub fn exit_now() -> ! {
    // Programs `exec` waits for get the signal the terminal would have
    // sent them (a SIGINT to raytrace alone reached only it).
    #[cfg(target_os = "linux")]
    for pid in crate::interp::waited_children() {
        if let Some(pid) = rustix::process::Pid::from_raw(pid as i32) {
            let _ = rustix::process::kill_process(pid, rustix::process::Signal::INT);
        }
    }
    for p in TEMPS.lock().unwrap_or_else(|e| e.into_inner()).drain(..) {
        let _ = std::fs::remove_file(p);
    }
    if let Ok(mut out) = STDOUT.try_lock() {
        let _ = out.flush();
    }
    let (code, why) = if TIMED_OUT.load(Ordering::SeqCst) {
        (super::EXIT_TIMED_OUT, "time limit reached")
    } else {
        (super::EXIT_INTERRUPTED, "interrupted")
    };
    let _ = std::io::stderr().write_all(format!("\nraytrace: {why}\n").as_bytes());
    std::process::exit(code)
}

pub fn add_temp(p: &Path) {
    TEMPS.lock().unwrap_or_else(|e| e.into_inner()).push(p.to_path_buf());
}

pub fn remove_temp(p: &Path) {
    TEMPS.lock().unwrap_or_else(|e| e.into_inner()).retain(|t| t != p);
}

/// Runs `f`, an open or read of `path`, so that Ctrl-C can end the wait:
/// a FIFO with no writer blocks for ever. Regular files, directories and
/// names that are not there are read here; FIFOs, devices and sockets on a
/// thread of their own, left behind (blocked, or done later) on an
/// interrupt, which is `Err`.
pub fn blocking<T: Send + 'static>(
    path: &str,
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<T, Interrupted> {
    match std::fs::metadata(path) {
        Ok(m) if !(m.is_file() || m.is_dir()) => {}
        _ => return Ok(f()),
    }
    let (tx, rx) = std::sync::mpsc::channel();
    let spawned = std::thread::Builder::new().name("open".into()).spawn(move || {
        let _ = tx.send(f());
    });
    if spawned.is_err() {
        return Err(Interrupted);
    }
    loop {
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(v) => return Ok(v),
            Err(_) if INTERRUPTED.load(Ordering::Relaxed) => return Err(Interrupted),
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => return Err(Interrupted),
        }
    }
}

/// A wait ended by Ctrl-C.
#[derive(Debug)]
pub struct Interrupted;

/// A writer that fails once Ctrl-C has come: a long PNG encode stops.
pub struct Cancellable<W>(pub W);

impl<W: Write> Write for Cancellable<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if INTERRUPTED.load(Ordering::Relaxed) {
            return Err(std::io::Error::other("interrupted"));
        }
        self.0.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

/// How progress is reported on stderr.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ProgressMode {
    /// A bar when stderr is a terminal, else a plain line per batch frame.
    #[default]
    Auto,
    /// Progress bars with ETA (for renders longer than about a second).
    Bar,
    /// One line per finished render.
    Plain,
    /// One JSON object per line: progress, finished renders, skips, the batch.
    Json,
    /// Nothing.
    None,
}

/// A render's place in a `--frames` batch.
#[derive(Clone, Copy, Debug)]
pub struct FrameInfo {
    pub frame: i64,
    /// 1-based position among this run's frames, and their number.
    pub index: usize,
    pub count: usize,
}

/// What a finished render reports.
pub struct Finished<'a> {
    pub file: &'a str,
    pub width: u32,
    pub height: u32,
    pub seconds: f64,
    pub rays: u64,
    /// False when the picture was written again without tracing (the
    /// scene had not changed since it was traced).
    pub traced: bool,
}

pub struct Feedback {
    pub mode: ProgressMode,
    /// Trace in coarse-to-fine passes.
    pub progressive: bool,
    /// Render only this part of the picture.
    pub crop: Option<Rect>,
    pub preview: Option<Preview>,
    /// `preview term`: draw each finished render in the terminal.
    pub show_in_terminal: bool,
    pub frame: Option<FrameInfo>,
    multi: MultiProgress,
    /// `--progress bar` (not `auto`): bars at once, also into a file.
    forced_bar: bool,
    batch_bar: Option<ProgressBar>,
}

/// A bar appears only for renders longer than this.
const BAR_DELAY: Duration = Duration::from_secs(1);

impl Feedback {
    pub fn new(mode: ProgressMode) -> Feedback {
        let forced_bar = mode == ProgressMode::Bar;
        let mode = match mode {
            ProgressMode::Auto if std::io::stderr().is_terminal() => ProgressMode::Bar,
            ProgressMode::Auto => ProgressMode::Plain,
            m => m,
        };
        Feedback {
            mode,
            progressive: false,
            crop: None,
            preview: None,
            show_in_terminal: false,
            frame: None,
            // Asked for by name, the bar is drawn even into a file or pipe.
            multi: MultiProgress::with_draw_target(
                if forced_bar && !std::io::stderr().is_terminal() {
                    ProgressDrawTarget::term_like(Box::new(Stderr))
                } else {
                    ProgressDrawTarget::stderr()
                },
            ),
            batch_bar: None,
            forced_bar,
        }
    }

    /// Runs `work` (a render of a `width`×`height` camera) on another
    /// thread while this one reports progress, updates the preview and
    /// passes Ctrl-C on as cancellation. Returns what `work` returns.
    /// `progressive` asks for passes even when `self.progressive` is off.
    pub fn watch<R: Send>(
        &mut self,
        file: &str,
        (width, height): (u32, u32),
        progressive: bool,
        work: impl FnOnce(&Job) -> R + Send,
    ) -> R {
        let rect = self.crop.unwrap_or(Rect::full(width, height));
        let canvas =
            self.preview.as_ref().map(|_| Mutex::new(vec![Vec3::ZERO; rect.pixels() as usize]));
        let job = Job {
            crop: self.crop,
            progressive: progressive || self.progressive,
            cancel: Some(&INTERRUPTED),
            canvas: canvas.as_ref(),
            ..Job::default()
        };
        let total = rect.pixels().max(1);
        let start = Instant::now();
        let mut bar: Option<ProgressBar> = None;
        let mut last_json = start;
        let mut rate = Rate::default();
        let me = std::thread::current();
        let finished = AtomicBool::new(false);
        let result = std::thread::scope(|s| {
            let worker = s.spawn(|| {
                let r = work(&job);
                // Said before the thread ends: `is_finished` turns true
                // only once this closure has returned, after the unpark,
                // and a wait begun in between slept its whole 40 ms (a
                // render of 512x512 took 6 or 46 ms at random).
                finished.store(true, Ordering::Release);
                me.unpark();
                r
            });
            // (`is_finished` too, for a worker that panicked.)
            while !finished.load(Ordering::Acquire) && !worker.is_finished() {
                std::thread::park_timeout(Duration::from_millis(40));
                let done = job.done.load(Ordering::Relaxed);
                match self.mode {
                    ProgressMode::Bar
                        if bar.is_none() && (self.forced_bar || start.elapsed() > BAR_DELAY) =>
                    {
                        let b =
                            self.multi.add(ProgressBar::new(total).with_elapsed(start.elapsed()));
                        b.set_style(
                            ProgressStyle::with_template(
                                "{prefix} [{bar:30}] {percent:>3}% {elapsed_precise} {msg}",
                            )
                            .expect("a valid template")
                            .progress_chars("=> "),
                        );
                        b.set_prefix(file.to_string());
                        bar = Some(b);
                    }
                    ProgressMode::Json if last_json.elapsed() >= Duration::from_secs(1) => {
                        last_json = Instant::now();
                        let f = done as f64 / total as f64;
                        let elapsed = start.elapsed().as_secs_f64();
                        let eta = rate.eta(done, total).unwrap_or(-1.0);
                        self.line(&format!(
                            "{{\"event\":\"progress\",\"file\":{},{}\"fraction\":{f:.4},\"elapsed_s\":{elapsed:.3},\"eta_s\":{eta:.3}}}",
                            json_str(file),
                            self.frame_fields()
                        ));
                    }
                    _ => {}
                }
                rate.sample(start.elapsed().as_secs_f64(), done);
                if let Some(b) = &bar {
                    b.set_position(done);
                    b.set_message(match rate.eta(done, total) {
                        Some(s) => format!("ETA {}", human_seconds(s)),
                        None => "ETA ?".into(),
                    });
                }
                if let (Some(p), Some(c)) = (&mut self.preview, &canvas) {
                    let pass = job.pass_done.load(Ordering::Relaxed) as u32;
                    let pixels = c.lock().unwrap_or_else(|e| e.into_inner()).clone();
                    p.show(&pixels, rect.width(), rect.height(), pass, job.progressive);
                }
            }
            worker.join()
        });
        if let Some(b) = bar {
            b.finish_and_clear();
            self.multi.remove(&b);
        }
        match result {
            Ok(r) => r,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }

    /// Shows the finished picture in the preview window, if one is open.
    pub fn show_final(&mut self, pixels: &[Vec3], width: u32, height: u32) {
        if let Some(p) = &mut self.preview {
            p.show(pixels, width, height, 1, false);
        }
    }

    fn frame_fields(&self) -> String {
        match self.frame {
            Some(f) => {
                format!("\"frame\":{},\"index\":{},\"count\":{},", f.frame, f.index, f.count)
            }
            None => String::new(),
        }
    }

    /// A line on stderr that does not tear the bars.
    fn line(&self, text: &str) {
        if self.batch_bar.is_some() {
            let _ = self.multi.println(text);
        } else {
            say!("{text}");
        }
    }

    /// Reports a finished render.
    pub fn finished(&self, r: &Finished) {
        let mrays = r.rays as f64 / r.seconds.max(1e-9) / 1e6;
        match self.mode {
            ProgressMode::Json => self.line(&format!(
                "{{\"event\":\"render\",\"file\":{},{}\"width\":{},\"height\":{},\"seconds\":{:.3},\"mrays_per_s\":{mrays:.2}}}",
                json_str(r.file),
                self.frame_fields(),
                r.width,
                r.height,
                r.seconds
            )),
            ProgressMode::Plain | ProgressMode::Bar => {
                let what = match self.frame {
                    Some(f) => format!("frame {} ({}/{}): ", f.frame, f.index, f.count),
                    None => String::new(),
                };
                let how = if r.traced {
                    format!("in {:.2} s ({mrays:.1} Mrays/s)", r.seconds)
                } else {
                    "(the scene had not changed since it was traced)".into()
                };
                self.line(&format!("{what}wrote {} {}×{} {how}", r.file, r.width, r.height));
            }
            ProgressMode::Auto | ProgressMode::None => {}
        }
        if let Some(b) = &self.batch_bar {
            b.inc(1);
        }
    }

    /// Reports a frame left alone because its file exists.
    pub fn skipped(&self, file: &str) {
        match self.mode {
            ProgressMode::Json => self.line(&format!(
                "{{\"event\":\"skip\",\"file\":{},{}\"reason\":\"exists\"}}",
                json_str(file),
                self.frame_fields()
            )),
            ProgressMode::Plain | ProgressMode::Bar => {
                if let Some(f) = self.frame {
                    self.line(&format!(
                        "frame {} ({}/{}): {file} exists, skipped",
                        f.frame, f.index, f.count
                    ));
                }
            }
            _ => {}
        }
        if let Some(b) = &self.batch_bar {
            b.inc(1);
        }
    }

    /// Starts a batch of `count` frames (a bar of its own in bar mode).
    pub fn start_batch(&mut self, count: usize) {
        if self.mode == ProgressMode::Bar {
            let b = self.multi.add(ProgressBar::new(count as u64));
            b.set_style(
                ProgressStyle::with_template(
                    "frames {pos}/{len} [{bar:30}] {elapsed_precise} ETA {eta}",
                )
                .expect("a valid template")
                .progress_chars("=> "),
            );
            self.batch_bar = Some(b);
        }
    }

    /// Ends the batch: a summary line in JSON mode.
    pub fn end_batch(&mut self, rendered: usize, skipped: usize, seconds: f64) {
        if let Some(b) = self.batch_bar.take() {
            b.finish_and_clear();
        }
        match self.mode {
            ProgressMode::Json => self.line(&format!(
                "{{\"event\":\"batch\",\"rendered\":{rendered},\"skipped\":{skipped},\"seconds\":{seconds:.3}}}"
            )),
            ProgressMode::Plain | ProgressMode::Bar => say!(
                "{rendered} frame(s) rendered, {skipped} skipped, in {seconds:.2} s"
            ),
            _ => {}
        }
    }
}

/// `s` as a JSON string literal.
pub fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The recent rate of progress: pixels done over about the last two
/// seconds, so the ETA follows how fast the picture goes now (parts of a
/// picture cost very different amounts), not the average since the start.
#[derive(Default)]
pub(crate) struct Rate {
    /// (seconds since the start, pixels done), oldest first.
    samples: std::collections::VecDeque<(f64, u64)>,
}

impl Rate {
    const WINDOW: f64 = 2.0;

    pub(crate) fn sample(&mut self, t: f64, done: u64) {
        self.samples.push_back((t, done));
        while self.samples.len() > 2 && t - self.samples[1].0 > Self::WINDOW {
            self.samples.pop_front();
        }
    }

    /// Seconds left at the recent rate; `None` until there is one.
    pub(crate) fn eta(&self, done: u64, total: u64) -> Option<f64> {
        let (&(t0, d0), &(t1, d1)) = (self.samples.front()?, self.samples.back()?);
        if t1 - t0 < 0.2 || d1 <= d0 {
            return None;
        }
        Some(total.saturating_sub(done) as f64 * (t1 - t0) / (d1 - d0) as f64)
    }
}

fn human_seconds(s: f64) -> String {
    match s {
        s if s < 10.0 => format!("{s:.1}s"),
        s if s < 60.0 => format!("{s:.0}s"),
        s if s < 3600.0 => format!("{}m{:02.0}s", (s / 60.0) as u64, s % 60.0),
        s => format!("{}h{:02}m", (s / 3600.0) as u64, ((s % 3600.0) / 60.0) as u64),
    }
}

/// Standard error as indicatif's terminal, for a bar asked for by name
/// when standard error is not a terminal (a log file still shows it).
#[derive(Debug)]
struct Stderr;

impl indicatif::TermLike for Stderr {
    fn width(&self) -> u16 {
        100
    }
    fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        use std::io::Write;
        writeln!(std::io::stderr(), "{s}")
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        use std::io::Write;
        write!(std::io::stderr(), "{s}")
    }
    fn clear_line(&self) -> std::io::Result<()> {
        use std::io::Write;
        write!(std::io::stderr(), "\r")
    }
    fn flush(&self) -> std::io::Result<()> {
        use std::io::Write;
        std::io::stderr().flush()
    }
}

#[cfg(test)]
mod tests {
    use super::Rate;

    #[test]
    fn eta_follows_the_recent_rate() {
        // Slow for 4 s (10 px/s), then fast (100 px/s): half-way through a
        // 1,000-pixel picture the ETA is what the fast rate needs, not the
        // average since the start.
        let mut r = Rate::default();
        let mut done = 0;
        for k in 0..=40 {
            done = k;
            r.sample(k as f64 * 0.1, done);
        }
        for k in 1..=30 {
            done = 40 + k * 10;
            r.sample(4.0 + k as f64 * 0.1, done);
        }
        let eta = r.eta(done, 1000).unwrap();
        assert!((eta - (1000 - done) as f64 / 100.0).abs() < 0.5, "{eta}");
        assert_eq!(Rate::default().eta(0, 10), None);
    }
}
