//! The live terminal dashboard of `tactile log --live`: the hand as a grid of fingers, each with
//! its current Fz, Mx, My, a sparkline of each over the last seconds, and its status: the
//! measured sample rate, the samples lost, its clock's rate error against the host (ppm) and
//! the alignment's uncertainty, and every other counter of damage (dropped, CRC errors,
//! reconnects) with the last gap.

use std::collections::VecDeque;
use std::io::{BufWriter, Stdout};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use crossterm::event::{self, Event as TermEvent, KeyCode, KeyModifiers};
use crossterm::terminal::{
    disable_raw_mode, enable_raw_mode, EnterAlternateScreen, LeaveAlternateScreen,
};
use ratatui::backend::CrosstermBackend;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Style, Stylize};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Sparkline};
use ratatui::{Frame as TermFrame, Terminal};

use host::device::{Counters, Event, GapKind, Scale};

/// Points kept per sparkline.
const HISTORY: usize = 600;
/// One sparkline point per this interval: a 50-column sparkline spans five seconds.
const POINT_EVERY: Duration = Duration::from_millis(100);

/// What the dashboard shows of one sensor, updated from its events.
#[derive(Debug, Clone)]
pub struct SensorView {
    pub label: String,
    scale: Scale,
    nominal_rate_hz: u32,
    pub loads: [f64; 3],
    pub volts: [f64; 3],
    history: [VecDeque<f64>; 3],
    arrivals: VecDeque<(Instant, usize)>,
    last_point: Option<Instant>,
    pub last_gap: Option<String>,
    /// The device clock against the host's.
    pub clock: ClockView,
}

/// A device clock as shown: its rate against the host's, whether that rate is still settling
/// (`host::clock::DeviceClock::settling`: its uncertainty above a ppm), and the alignment's
/// uncertainty.
#[derive(Debug, Clone, Copy)]
pub struct ClockView {
    pub ppm: f64,
    pub settling: bool,
    pub uncertainty_us: f64,
}

impl ClockView {
    /// Before the first frame: nothing known.
    pub const UNKNOWN: Self = Self {
        ppm: f64::NAN,
        settling: true,
        uncertainty_us: f64::NAN,
    };

    pub fn of(c: &host::clock::DeviceClock) -> Self {
        Self {
            ppm: c.ppm(),
            settling: c.settling(),
            uncertainty_us: c.uncertainty_s() * 1e6,
        }
    }

    /// `clock +35.2 ppm (settling) ±71 µs`: the status line's and the live view's words.
    pub fn text(&self) -> String {
        let settling = if self.settling { " (settling)" } else { "" };
        format!(
            "clock {:+.1} ppm{settling} ±{:.0} µs",
            self.ppm, self.uncertainty_us
        )
    }
}

impl SensorView {
    pub fn new(label: String, scale: Scale, nominal_rate_hz: u32) -> Self {
        Self {
            label,
            scale,
            nominal_rate_hz,
            loads: [0.0; 3],
            volts: [0.0; 3],
            history: Default::default(),
            arrivals: VecDeque::new(),
            last_point: None,
            last_gap: None,
            clock: ClockView::UNKNOWN,
        }
    }

    pub fn on_event(&mut self, ev: &Event) {
        match ev {
            Event::Frame(f) => {
                let now = Instant::now();
                if let Some(s) = f.frame.samples().last() {
                    self.loads = self.scale.loads(s);
                    self.volts = self.scale.adc_volts(s);
                    if self
                        .last_point
                        .is_none_or(|t| now.duration_since(t) >= POINT_EVERY)
                    {
                        self.last_point = Some(now);
                        for (h, v) in self.history.iter_mut().zip(self.loads) {
                            if h.len() == HISTORY {
                                h.pop_front();
                            }
                            h.push_back(v);
                        }
                    }
                }
                self.arrivals.push_back((now, f.frame.len()));
                while self
                    .arrivals
                    .front()
                    .is_some_and(|(t, _)| now.duration_since(*t) > Duration::from_secs(1))
                {
                    self.arrivals.pop_front();
                }
            }
            Event::Gap(g) => {
                self.last_gap = Some(match &g.kind {
                    GapKind::Sequence { missing, .. } => format!("{missing} frames missing"),
                    GapKind::Disconnected => "disconnected".into(),
                    GapKind::Reconnected { downtime, missing } => {
                        format!(
                            "reconnected after {:.1} s ({} frames missed)",
                            downtime.as_secs_f64(),
                            missing.unwrap_or(0)
                        )
                    }
                    GapKind::DeviceRestart { .. } => "device restarted".into(),
                    GapKind::HostQueueFull { frames } => {
                        format!("host fell behind: {frames} frames")
                    }
                });
            }
            Event::Info(i) => {
                self.scale = Scale::from_info(i);
                self.nominal_rate_hz = i.sample_rate_hz;
            }
        }
    }

    /// Samples received during the last second.
    pub fn rate_hz(&self) -> f64 {
        self.arrivals.iter().map(|(_, n)| *n as f64).sum()
    }

    /// The newest `width` points of channel `i` scaled to 1..=100 between their minimum and
    /// maximum, which are returned too.
    fn spark(&self, i: usize, width: usize) -> (Vec<u64>, f64, f64) {
        let h = &self.history[i];
        let shown: Vec<f64> = h
            .iter()
            .skip(h.len().saturating_sub(width))
            .copied()
            .collect();
        let (lo, hi) = shown
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            });
        let span = (hi - lo).max(1e-12);
        (
            shown
                .iter()
                .map(|v| 1 + ((v - lo) / span * 99.0) as u64)
                .collect(),
            lo,
            hi,
        )
    }
}

/// How often the screen is redrawn at most: twice a second, about as fast as a person reads a
/// changing number (the sparklines keep their ten points a second and move by five). A
/// redraw builds the whole screen, so its cost is the rate times the terminal's size: a
/// sixteen-finger screen of 200x150 took 1.7 % of a core at five a second (issue #29).
const REFRESH_EVERY: Duration = Duration::from_millis(500);
/// How often the screen thread looks at the keyboard between refreshes: a key is answered
/// within a tenth of a second, and the thread wakes ten times a second, not twenty.
const KEY_POLL: Duration = Duration::from_millis(100);
/// Bytes of screen output gathered before a write (a full refresh of a large terminal fits).
const SCREEN_BUFFER: usize = 256 * 1024;
/// How long closing the dashboard waits for the screen thread to restore the terminal.
const CLOSE_WAIT: Duration = Duration::from_secs(1);

/// What one refresh shows: copies, so that the screen thread draws while recording goes on.
struct Snapshot {
    views: Vec<SensorView>,
    counters: Vec<Counters>,
    elapsed: Duration,
    skipped: u64,
}

/// The dashboard. A thread of its own owns the terminal, because writing to a terminal can
/// block for as long as the terminal pleases (a paused ssh session, Ctrl-S, a slow emulator
/// with sixteen sensors' panels), and the recording must not wait for it: the logger hands the
/// screen a snapshot at most every `REFRESH_EVERY`, and when the screen is still busy with
/// the previous one that refresh is dropped (and counted in the title), never a sample.
pub struct Dashboard {
    snapshots: Option<mpsc::SyncSender<Snapshot>>,
    quit: Arc<AtomicBool>,
    /// The screen thread's end, with its error if drawing failed.
    done: mpsc::Receiver<std::io::Result<()>>,
    ended: bool,
    last_refresh: Instant,
    skipped: u64,
}

impl Dashboard {
    /// Raw mode, the alternate screen, and the screen thread.
    pub fn enter() -> std::io::Result<Self> {
        enable_raw_mode()?;
        crossterm::execute!(std::io::stdout(), EnterAlternateScreen)?;
        // One write per refresh: stdout alone is line-buffered in 1 KiB, and a screen of sixteen
        // panels would go out in a few hundred writes, each a trip through the tty layer.
        let out = BufWriter::with_capacity(SCREEN_BUFFER, std::io::stdout());
        let term = match Terminal::new(CrosstermBackend::new(out)) {
            Ok(t) => t,
            Err(e) => {
                restore_terminal();
                return Err(e);
            }
        };
        let (tx, rx) = mpsc::sync_channel(1);
        let (done_tx, done) = mpsc::channel();
        let quit = Arc::new(AtomicBool::new(false));
        let q = quit.clone();
        let spawned = std::thread::Builder::new()
            .name("tactile-live".into())
            .spawn(move || {
                let r = screen_loop(term, &rx, &q);
                restore_terminal();
                let _ = done_tx.send(r);
            });
        if let Err(e) = spawned {
            restore_terminal();
            return Err(e);
        }
        Ok(Self {
            snapshots: Some(tx),
            quit,
            done,
            ended: false,
            last_refresh: Instant::now() - REFRESH_EVERY,
            skipped: 0,
        })
    }

    /// Offer the screen a refresh (at most every `REFRESH_EVERY`; `take` copies the sensors'
    /// views and counters, and is called only then); `true` when the user asked to quit (q,
    /// Esc, Ctrl-C). Never waits for the terminal.
    pub fn draw(
        &mut self,
        take: impl FnOnce() -> (Vec<SensorView>, Vec<Counters>),
        elapsed: Duration,
    ) -> std::io::Result<bool> {
        if self.quit.load(Ordering::Relaxed) {
            return Ok(true);
        }
        if let Ok(r) = self.done.try_recv() {
            self.ended = true;
            r?;
            return Ok(true);
        }
        if self.last_refresh.elapsed() < REFRESH_EVERY {
            return Ok(false);
        }
        self.last_refresh = Instant::now();
        let (views, counters) = take();
        let snapshot = Snapshot {
            views,
            counters,
            elapsed,
            skipped: self.skipped,
        };
        if let Some(Err(mpsc::TrySendError::Full(_))) =
            self.snapshots.as_ref().map(|s| s.try_send(snapshot))
        {
            self.skipped += 1;
        }
        Ok(false)
    }

    /// Refreshes dropped because the screen was still drawing the previous one.
    pub fn skipped(&self) -> u64 {
        self.skipped
    }
}

impl Drop for Dashboard {
    fn drop(&mut self) {
        // The screen thread restores the terminal once it sees no more snapshots can come.
        self.snapshots = None;
        if !self.ended && self.done.recv_timeout(CLOSE_WAIT).is_err() {
            // Still blocked on the terminal: leave raw mode at least (no write needed for it).
            let _ = disable_raw_mode();
        }
    }
}

fn restore_terminal() {
    let _ = disable_raw_mode();
    let _ = crossterm::execute!(std::io::stdout(), LeaveAlternateScreen);
}

/// The screen thread: draw each snapshot as it comes, watch the keyboard in between.
fn screen_loop(
    mut term: Terminal<CrosstermBackend<BufWriter<Stdout>>>,
    snapshots: &mpsc::Receiver<Snapshot>,
    quit: &AtomicBool,
) -> std::io::Result<()> {
    loop {
        while event::poll(Duration::ZERO)? {
            if let TermEvent::Key(k) = event::read()? {
                let ctrl_c =
                    k.code == KeyCode::Char('c') && k.modifiers.contains(KeyModifiers::CONTROL);
                if matches!(k.code, KeyCode::Char('q') | KeyCode::Esc) || ctrl_c {
                    quit.store(true, Ordering::Relaxed);
                }
            }
        }
        match snapshots.recv_timeout(KEY_POLL) {
            Ok(s) => {
                term.draw(|f| render(f, &s))?;
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => return Ok(()),
        }
    }
}

fn render(f: &mut TermFrame<'_>, s: &Snapshot) {
    let area = f.area();
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Length(1), Constraint::Min(0)])
        .split(area);
    let mut title = format!(" tactile log — {:.1} s — q quits ", s.elapsed.as_secs_f64());
    if s.skipped > 0 {
        title.push_str(&format!(
            "— {} refreshes skipped (slow terminal; recording unaffected) ",
            s.skipped
        ));
    }
    f.render_widget(Paragraph::new(title).bold(), rows[0]);
    for (cell, (v, c)) in grid(rows[1], s.views.len())
        .into_iter()
        .zip(s.views.iter().zip(&s.counters))
    {
        render_finger(f, cell, v, c);
    }
}

/// `n` cells in a grid as square as the area's shape allows (a terminal cell is about twice as
/// tall as wide, and a finger's panel wants about three times its height in width).
fn grid(area: Rect, n: usize) -> Vec<Rect> {
    if n == 0 {
        return Vec::new();
    }
    let aspect = f64::from(area.width) / (3.0 * f64::from(area.height.max(1)));
    let cols = ((n as f64 * aspect).sqrt().round() as usize).clamp(1, n);
    let rows = n.div_ceil(cols);
    let row_areas = Layout::default()
        .direction(Direction::Vertical)
        .constraints(vec![Constraint::Ratio(1, rows as u32); rows])
        .split(area);
    let mut cells = Vec::with_capacity(n);
    for r in row_areas.iter() {
        let cs = Layout::default()
            .direction(Direction::Horizontal)
            .constraints(vec![Constraint::Ratio(1, cols as u32); cols])
            .split(*r);
        cells.extend(cs.iter().copied());
    }
    cells.truncate(n);
    cells
}

fn colour(bad: bool) -> Style {
    Style::default().fg(if bad { Color::Red } else { Color::Green })
}

/// The finger's status: rate, lost, clock; then the other counters and the last gap.
fn status_lines(v: &SensorView, c: &Counters) -> [Line<'static>; 2] {
    let slow = v.rate_hz() < 0.9 * f64::from(v.nominal_rate_hz);
    let status = Line::from(vec![
        Span::styled(format!("{:.0} S/s ", v.rate_hz()), colour(slow)),
        Span::styled(
            format!("lost {} ", c.lost_on_link),
            colour(c.lost_on_link > 0),
        ),
        Span::raw(v.clock.text()),
    ]);
    let damage = c.dropped_by_device + c.crc_errors + c.reconnects + c.host_queue_drops;
    let more = Line::from(vec![
        Span::styled(
            format!(
                "dropped {} crc {} reconn {} queue {} ",
                c.dropped_by_device, c.crc_errors, c.reconnects, c.host_queue_drops
            ),
            colour(damage > 0),
        ),
        Span::raw(v.last_gap.clone().unwrap_or_default()),
    ]);
    [status, more]
}

fn render_finger(f: &mut TermFrame<'_>, area: Rect, v: &SensorView, c: &Counters) {
    let block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {} ", v.label).bold());
    let inner = block.inner(area);
    f.render_widget(block, area);
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Length(4), Constraint::Min(0)])
        .split(inner);
    let values = Line::from(format!(
        "Fz {:+8.3} N  Mx {:+8.5}  My {:+8.5} N·m",
        v.loads[0], v.loads[1], v.loads[2]
    ));
    let volts = Line::from(format!(
        "   {:+.5} {:+.5} {:+.5} V",
        v.volts[0], v.volts[1], v.volts[2]
    ));
    let [status, more] = status_lines(v, c);
    f.render_widget(Paragraph::new(vec![values, volts, status, more]), parts[0]);
    if parts[1].height < 3 {
        return; // no room for the sparklines: the numbers are what matters
    }
    let sparks = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Ratio(1, 3); 3])
        .split(parts[1]);
    let names = ["Fz", "Mx", "My"];
    let colors = [Color::Cyan, Color::Yellow, Color::Magenta];
    for i in 0..3 {
        // The sparkline draws from the left: keep the newest points that fit.
        let fit = usize::from(sparks[i].width.saturating_sub(2));
        let (data, lo, hi) = v.spark(i, fit);
        let title = format!(" {} {:.3}…{:.3} ", names[i], lo, hi);
        let w = Sparkline::default()
            .block(Block::default().borders(Borders::ALL).title(title))
            .data(&data)
            .max(100)
            .style(Style::default().fg(colors[i]));
        f.render_widget(w, sparks[i]);
    }
}
