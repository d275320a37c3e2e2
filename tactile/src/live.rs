//! The live terminal dashboard of `tactile log --live`: per sensor the current Fz, Mx, My and
//! bridge volts, a sparkline of each over the last seconds, the measured sample rate, and every
//! counter of damage (lost, dropped, CRC errors, resyncs, reconnects), with the link state.

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

/// How often the screen is redrawn at most.
const REFRESH_EVERY: Duration = Duration::from_millis(100);
/// How often the screen thread looks at the keyboard between refreshes.
const KEY_POLL: Duration = Duration::from_millis(50);
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

    /// Offer the screen a refresh (at most ten a second); `true` when the user asked to quit
    /// (q, Esc, Ctrl-C). Never waits for the terminal.
    pub fn draw(
        &mut self,
        views: &[&SensorView],
        counters: &[Counters],
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
        let snapshot = Snapshot {
            views: views.iter().map(|v| (*v).clone()).collect(),
            counters: counters.to_vec(),
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
    let (views, counters) = (&s.views, &s.counters);
    let area = f.area();
    let mut constraints = vec![Constraint::Length(1)];
    constraints.extend(views.iter().map(|_| Constraint::Min(9)));
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints(constraints)
        .split(area);
    let mut title = format!(" tactile log — {:.1} s — q quits ", s.elapsed.as_secs_f64());
    if s.skipped > 0 {
        title.push_str(&format!(
            "— {} refreshes skipped (slow terminal; recording unaffected) ",
            s.skipped
        ));
    }
    f.render_widget(Paragraph::new(title).bold(), rows[0]);
    for (i, (v, c)) in views.iter().zip(counters).enumerate() {
        render_sensor(f, rows[i + 1], v, c);
    }
}

/// Rate, frames and every loss counter, red where it is not zero.
fn stats_line(v: &SensorView, c: &Counters) -> Line<'static> {
    let bad = |n: u64| {
        if n > 0 {
            Style::default().fg(Color::Red)
        } else {
            Style::default().fg(Color::Green)
        }
    };
    Line::from(vec![
        Span::raw(format!(
            "rate {:6.0}/{} S/s  frames {}  ",
            v.rate_hz(),
            v.nominal_rate_hz,
            c.frames
        )),
        Span::styled(format!("lost {}  ", c.lost_on_link), bad(c.lost_on_link)),
        Span::styled(
            format!("dropped {}  ", c.dropped_by_device),
            bad(c.dropped_by_device),
        ),
        Span::styled(format!("crc {}  ", c.crc_errors), bad(c.crc_errors)),
        Span::styled(
            format!("resyncs {}  reconnects {}  ", c.resyncs, c.reconnects),
            bad(c.reconnects),
        ),
        Span::raw(
            v.last_gap
                .clone()
                .map(|g| format!("last gap: {g}"))
                .unwrap_or_default(),
        ),
    ])
}

fn render_sensor(f: &mut TermFrame<'_>, area: Rect, v: &SensorView, c: &Counters) {
    let block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {} ", v.label));
    let inner = block.inner(area);
    f.render_widget(block, area);
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Length(2), Constraint::Min(3)])
        .split(inner);
    let values = Line::from(vec![
        Span::raw(format!(
            "Fz {:+9.3} N   Mx {:+9.5} N·m   My {:+9.5} N·m   ",
            v.loads[0], v.loads[1], v.loads[2]
        )),
        Span::raw(format!(
            "({:+.5} {:+.5} {:+.5} V)",
            v.volts[0], v.volts[1], v.volts[2]
        )),
    ]);
    f.render_widget(Paragraph::new(vec![values, stats_line(v, c)]), parts[0]);
    let sparks = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Ratio(1, 3); 3])
        .split(parts[1]);
    let names = ["Fz [N]", "Mx [N·m]", "My [N·m]"];
    let colors = [Color::Cyan, Color::Yellow, Color::Magenta];
    for i in 0..3 {
        // The sparkline draws from the left: keep the newest points that fit.
        let fit = usize::from(sparks[i].width.saturating_sub(2));
        let (data, lo, hi) = v.spark(i, fit);
        let title = format!(
            " {} {:.4} … {:.4}, last {:.0} s ",
            names[i],
            lo,
            hi,
            data.len() as f64 * POINT_EVERY.as_secs_f64()
        );
        let w = Sparkline::default()
            .block(Block::default().borders(Borders::ALL).title(title))
            .data(&data)
            .max(100)
            .style(Style::default().fg(colors[i]));
        f.render_widget(w, sparks[i]);
    }
}
