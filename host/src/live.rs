//! The live terminal dashboard of `tactile log --live`: per sensor the current Fz, Mx, My and
//! bridge volts, a sparkline of each over the last seconds, the measured sample rate, and every
//! counter of damage (lost, dropped, CRC errors, resyncs, reconnects), with the link state.

use std::collections::VecDeque;
use std::io::Stdout;
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

use crate::device::{Counters, Event, GapKind, Scale};

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

/// The terminal, in raw mode on the alternate screen while the dashboard lives.
pub struct Dashboard {
    term: Terminal<CrosstermBackend<Stdout>>,
    last_draw: Instant,
}

impl Dashboard {
    pub fn enter() -> std::io::Result<Self> {
        enable_raw_mode()?;
        crossterm::execute!(std::io::stdout(), EnterAlternateScreen)?;
        let term = Terminal::new(CrosstermBackend::new(std::io::stdout()))?;
        Ok(Self {
            term,
            last_draw: Instant::now() - Duration::from_secs(1),
        })
    }

    /// Redraw (at most ten times a second); `true` when the user asked to quit (q, Esc, Ctrl-C).
    pub fn draw(
        &mut self,
        views: &[&SensorView],
        counters: &[Counters],
        elapsed: Duration,
    ) -> std::io::Result<bool> {
        while event::poll(Duration::ZERO)? {
            if let TermEvent::Key(k) = event::read()? {
                let ctrl_c =
                    k.code == KeyCode::Char('c') && k.modifiers.contains(KeyModifiers::CONTROL);
                if matches!(k.code, KeyCode::Char('q') | KeyCode::Esc) || ctrl_c {
                    return Ok(true);
                }
            }
        }
        if self.last_draw.elapsed() < Duration::from_millis(100) {
            return Ok(false);
        }
        self.last_draw = Instant::now();
        self.term.draw(|f| render(f, views, counters, elapsed))?;
        Ok(false)
    }
}

impl Drop for Dashboard {
    fn drop(&mut self) {
        let _ = disable_raw_mode();
        let _ = crossterm::execute!(std::io::stdout(), LeaveAlternateScreen);
    }
}

fn render(f: &mut TermFrame<'_>, views: &[&SensorView], counters: &[Counters], elapsed: Duration) {
    let area = f.area();
    let mut constraints = vec![Constraint::Length(1)];
    constraints.extend(views.iter().map(|_| Constraint::Min(9)));
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints(constraints)
        .split(area);
    let title = format!(" tactile log — {:.1} s — q quits ", elapsed.as_secs_f64());
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
