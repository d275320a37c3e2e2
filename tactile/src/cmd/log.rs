//! `tactile log`: record one or several sensors to the recording CSV and an MCAP file.

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};
use sysexit::ResultExt as _;

use anyhow::Context;

use super::common::{finite, positive_seconds};
use crate::live::{ClockView, Dashboard, SensorView};
use host::device::{Device, Event, OpenOptions, PortSpec, Scale};
use host::logger::mcap_io::McapSink;
use host::logger::reference::{merge_file, Align};
use host::logger::{metadata, per_sensor_path, Recorder, Setup};

/// Record sensors until --duration has passed or Ctrl-C: the recording CSV
/// (`docs/recording-format.md`, plus seq, both timestamps, gap marks and loads) and an
/// MCAP file (raw frames, decoded samples, gaps; opens in Foxglove). Files are flushed four
/// times a second, so a crash loses at most the last quarter second. An unplugged sensor is
/// reopened when it returns, and the outage is marked in both files.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Serial port(s): device path or `serial:<USB serial number>`; repeat for several sensors.
    #[arg(
        long,
        short = 'p',
        value_name = "PORT",
        required_unless_present = "hand"
    )]
    pub port: Vec<String>,
    /// A hand file (TOML, `[fingers]` name = "serial:SN" or port path; docs/hand.md): one CSV
    /// per finger named by finger, one MCAP with a topic per finger.
    #[arg(long, value_name = "TOML", conflicts_with = "port")]
    pub hand: Option<PathBuf>,
    /// Output CSV; with several sensors, one file per sensor named after it.
    #[arg(long, short = 'o', default_value = "recording.csv")]
    pub out: PathBuf,
    /// MCAP output (default: the CSV path with .mcap).
    #[arg(long)]
    pub mcap: Option<PathBuf>,
    /// Do not write an MCAP file.
    #[arg(long, conflicts_with = "mcap")]
    pub no_mcap: bool,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, short = 'd', value_parser = positive_seconds, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Set this sample rate (Hz) before starting.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64_000))]
    pub rate: Option<u32>,
    /// Contact angle theta_p of the load axis in degrees (default: hardware/fingertip.toml).
    #[arg(long, value_parser = finite)]
    pub contact_angle_deg: Option<f64>,
    /// Azimuth phi of the tilt plane in degrees (default: hardware/fingertip.toml).
    #[arg(long, value_parser = finite)]
    pub azimuth_deg: Option<f64>,
    /// A test machine's CSV export (time, rod position, load) merged into rod_mm and load_N at
    /// the end.
    #[arg(long, value_name = "CSV")]
    pub reference: Option<PathBuf>,
    /// How to align the reference: by timestamps, by cross-correlation of load with Fz, or
    /// `start`: the machine was started by the stream's start, its time zero is the first sample.
    #[arg(long, value_enum, default_value = "time", requires = "reference")]
    pub align: AlignArg,
    /// Reference time minus recording time, s (with --align time).
    #[arg(long, default_value_t = 0.0, value_parser = finite, requires = "reference")]
    pub reference_offset_s: f64,
    /// Largest lag searched by --align xcorr, s.
    #[arg(long, default_value_t = 30.0, value_parser = positive_seconds)]
    pub max_lag_s: f64,
    /// Give up on a vanished sensor after this many seconds.
    #[arg(long, default_value_t = 30.0, value_parser = positive_seconds, value_name = "SECONDS")]
    pub reconnect_for: f64,
    /// Fail as soon as a sensor vanishes instead of waiting for it.
    #[arg(long)]
    pub no_reconnect: bool,
    /// Time the rows by the device's own clock (its stamps, from the first frame's receipt)
    /// instead of mapping it onto the host's: for a device whose clock does not run in real
    /// time, as an emulator on a virtual clock.
    #[arg(long)]
    pub device_clock: bool,
    /// Show the live terminal dashboard instead of the status line (q quits).
    #[arg(long)]
    pub live: bool,
    /// No status line.
    #[arg(long, short = 'q')]
    pub quiet: bool,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum AlignArg {
    Time,
    Xcorr,
    Start,
}

struct Sensor {
    dev: Device,
    rec: Recorder,
    view: SensorView,
    ended: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let stop = Arc::new(AtomicBool::new(false));
    let s2 = stop.clone();
    // A second Ctrl-C falls through to the default (the files are flushed often anyway).
    let _ = ctrlc::set_handler(move || s2.store(true, Ordering::Relaxed));
    let start = SystemTime::now();
    let (mut sensors, mcap) = open_all(&args, start)?;
    let deadline = args
        .duration
        .map(|d| Instant::now() + Duration::from_secs_f64(d));
    let mut dash = if args.live {
        Some(Dashboard::enter()?)
    } else {
        None
    };
    let started = Instant::now();
    let result = pump(
        &mut sensors,
        &stop,
        deadline,
        dash.as_mut(),
        args.quiet || args.live,
    );
    if let Some(d) = dash.take() {
        close_dashboard(d, &sensors, started.elapsed(), args.quiet);
    }
    let finished = finish_files(&mut sensors, mcap);
    let mut gone = None;
    for s in sensors {
        if s.ended {
            gone = gone.or(s.dev.gone_error());
        }
        s.dev.close();
    }
    result?;
    finished?;
    if let Some(reference) = &args.reference {
        let align = match args.align {
            AlignArg::Time => Align::Time {
                offset_s: args.reference_offset_s,
            },
            AlignArg::Xcorr => Align::Xcorr {
                max_lag_s: args.max_lag_s,
            },
            AlignArg::Start => Align::Start,
        };
        for path in csv_paths(&args)? {
            let off = merge_file(&path, reference, align).coded()?;
            eprintln!("{}: reference merged (offset {off:.3} s)", path.display());
        }
    }
    match gone {
        Some(e) => Err(sysexit::Coded::new(e).into()),
        None => Ok(()),
    }
}

/// Leave the dashboard's screen; its counters vanish with it, so unless `quiet` the totals are
/// left in the scrollback, with the refreshes a slow terminal made it skip.
fn close_dashboard(dash: Dashboard, sensors: &[Sensor], elapsed: Duration, quiet: bool) {
    let skipped = dash.skipped();
    drop(dash);
    if !quiet {
        eprintln!("{}", status_line(sensors, elapsed));
        if skipped > 0 {
            eprintln!("live view: {skipped} refreshes skipped (the terminal was slow)");
        }
    }
}

/// The sensors to log: (label, port), from `--hand` (fingers by name) or the `-p` list.
fn targets(args: &Args) -> anyhow::Result<Vec<(String, PortSpec)>> {
    if let Some(hand) = &args.hand {
        let fingers = host::hand::load(hand).coded()?;
        return Ok(fingers.into_iter().map(|f| (f.name, f.port)).collect());
    }
    Ok(args
        .port
        .iter()
        .map(|p| {
            let spec = PortSpec::parse(p);
            (spec.label(), spec)
        })
        .collect())
}

fn csv_paths(args: &Args) -> anyhow::Result<Vec<PathBuf>> {
    let targets = targets(args)?;
    let several = targets.len() > 1 || args.hand.is_some();
    Ok(targets
        .iter()
        .map(|(label, _)| per_sensor_path(&args.out, label, several))
        .collect())
}

type SharedSink = Rc<RefCell<McapSink>>;

/// How long the pump sleeps after each pass over the queues. A pass takes everything queued,
/// so the work per pass grows with the pause and the passes' fixed cost (a look at every
/// queue, clock and flush timer) shrinks: a pump that went round again whenever a pass had
/// found anything ran a pass for every few frames the I/O thread delivered. The queues hold
/// seconds of frames ([`MIN_QUEUE`]): the pause costs only its latency on the files, a fifth
/// of their flush interval, while each pass's wake-up (some 35 µs of a core in the hand bench) is paid
/// twenty times a second rather than fifty.
const IDLE: Duration = Duration::from_millis(50);

/// Fewest frames queued per sensor between its I/O thread and the files: 20 s at 1 kHz, 2.3 s
/// at the link's top rate (8.8 kHz in batches of 10), while the logger empties every queue
/// every few milliseconds.
const MIN_QUEUE: usize = 2048;

/// Frames queued per sensor. A queue is allocated whole when its port opens (~280 bytes an
/// entry): the driver's default is 4.5 MiB per sensor, 72 MiB for a hand of sixteen. The hand
/// together keeps what one sensor has.
fn queue_per_sensor(sensors: usize) -> usize {
    (OpenOptions::default().queue / sensors.max(1)).max(MIN_QUEUE)
}

fn open_all(args: &Args, start: SystemTime) -> anyhow::Result<(Vec<Sensor>, Option<SharedSink>)> {
    let targets = targets(args)?;
    let opts = OpenOptions {
        reconnect: !args.no_reconnect,
        reconnect_for: Duration::from_secs_f64(args.reconnect_for),
        queue: queue_per_sensor(targets.len()),
        ..OpenOptions::default()
    };
    let mut setup = Setup::from_hardware(String::new())
        .coded()
        .context("hardware parameters")?;
    setup.device_clock = args.device_clock;
    if let Some(a) = args.contact_angle_deg {
        setup.contact_angle_deg = a;
    }
    if let Some(a) = args.azimuth_deg {
        setup.azimuth_deg = a;
    }
    // Open every sensor before creating any file: a wrong port leaves nothing behind. One I/O
    // thread serves them all (host::device::Device::open_all).
    let specs: Vec<PortSpec> = targets.iter().map(|(_, spec)| spec.clone()).collect();
    let mut devices = Vec::new();
    for ((label, _), dev) in targets.into_iter().zip(Device::open_all(&specs, opts)) {
        let named = args
            .hand
            .as_ref()
            .map(|h| format!("{}: finger {label}", h.display()));
        let dev = match (dev.coded(), named) {
            (Ok(d), _) => d,
            (Err(e), Some(finger)) => return Err(anyhow::Error::from(e).context(finger)),
            (Err(e), None) => return Err(e.into()),
        };
        if let Some(hz) = args.rate {
            dev.set_rate(hz).coded()?;
        }
        let info = dev.get_info().coded()?;
        devices.push((label, dev, info));
    }
    let mcap = match (&args.mcap, args.no_mcap) {
        (_, true) => None,
        (Some(p), false) => Some(p.clone()),
        (None, false) => Some(args.out.with_extension("mcap")),
    };
    let mcap = mcap
        .map(|p| McapSink::create(&p))
        .transpose()
        .coded()?
        .map(|m| Rc::new(RefCell::new(m)));
    let mut sensors = Vec::new();
    for ((label, dev, info), csv) in devices.into_iter().zip(csv_paths(args)?) {
        setup.source = format!("tactile log {}", dev.port().display());
        let mut rec = Recorder::create(&csv, &info, &setup, start).coded()?;
        if let Some(m) = &mcap {
            let ch = m
                .borrow_mut()
                .add_sensor(&label, &metadata(&info, &setup, start).pairs())
                .coded()?;
            rec = rec.with_mcap((m.clone(), ch));
            rec.on_event(&Event::Info(info.clone())).coded()?;
        }
        let view = SensorView::new(label, Scale::from_info(&info), info.sample_rate_hz);
        sensors.push(Sensor {
            dev,
            rec,
            view,
            ended: false,
        });
    }
    for s in &sensors {
        s.dev.start().coded()?;
    }
    Ok((sensors, mcap))
}

/// Move events from the devices to the files until the deadline, Ctrl-C, `q` in the dashboard,
/// or every sensor is gone.
fn pump(
    sensors: &mut [Sensor],
    stop: &AtomicBool,
    deadline: Option<Instant>,
    mut dash: Option<&mut Dashboard>,
    quiet: bool,
) -> anyhow::Result<()> {
    let mut last_status = Instant::now();
    let t0 = Instant::now();
    loop {
        for s in sensors.iter_mut() {
            loop {
                match s.dev.events().try_recv() {
                    Ok(ev) => {
                        s.view.on_event(&ev);
                        s.rec.on_event(&ev).coded()?;
                    }
                    Err(std::sync::mpsc::TryRecvError::Empty) => break,
                    Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                        s.ended = true;
                        break;
                    }
                }
            }
            s.rec.maybe_flush().coded()?;
            s.view.clock = ClockView::of(s.rec.clock());
        }
        let all_ended = sensors.iter().all(|s| s.ended);
        if stop.load(Ordering::Relaxed)
            || deadline.is_some_and(|d| Instant::now() >= d)
            || all_ended
        {
            return Ok(());
        }
        if let Some(d) = dash.as_deref_mut() {
            let take = || {
                let views = sensors.iter().map(|s| s.view.clone()).collect();
                (views, sensors.iter().map(|s| s.dev.counters()).collect())
            };
            if d.draw(take, t0.elapsed())? {
                return Ok(());
            }
        } else if !quiet && last_status.elapsed() >= Duration::from_secs(1) {
            last_status = Instant::now();
            eprintln!("{}", status_line(sensors, t0.elapsed()));
        }
        std::thread::sleep(IDLE);
    }
}

fn status_line(sensors: &[Sensor], elapsed: Duration) -> String {
    let mut line = format!("{:7.1} s", elapsed.as_secs_f64());
    for s in sensors {
        let c = s.dev.counters();
        let state = if s.dev.is_connected() {
            ""
        } else {
            " DISCONNECTED"
        };
        line.push_str(&format!(
            " | {}{state}: {:.0} S/s, {} rows, {}, lost {} dropped {} crc {} reconnects {} queue {}",
            s.view.label,
            s.view.rate_hz(),
            s.rec.rows,
            ClockView::of(s.rec.clock()).text(),
            c.lost_on_link,
            c.dropped_by_device,
            c.crc_errors,
            c.reconnects,
            c.host_queue_drops
        ));
    }
    line
}

/// Flush every CSV and write the MCAP summary (the recorders let go of the writer first).
fn finish_files(sensors: &mut [Sensor], mcap: Option<SharedSink>) -> anyhow::Result<()> {
    for s in sensors.iter_mut() {
        s.rec.finish(&s.view.label).coded()?;
        s.rec.detach_mcap();
    }
    if let Some(m) = mcap {
        match Rc::try_unwrap(m) {
            Ok(sink) => sink.into_inner().finish()?,
            Err(_) => anyhow::bail!("internal: MCAP writer still shared"),
        }
    }
    Ok(())
}
