//! A simulated hand on a virtual clock: sixteen fingertips whose crystals are off by up to
//! ±`max_ppm`, each behind a jittered link, through the logger's own time mapping
//! ([`host::clock::DeviceClock`], used exactly as `host::logger::Recorder` uses it: observe
//! each frame, hold a new session's frames until it settles, then map every sample's device
//! time onto the host's). The truth is known, so the misalignment between any two fingers at the
//! same true instant is measured at every point of the run; an hour takes seconds.
//!
//! One finger's device restarts mid-run (unplugged for a few seconds, its clock back at zero)
//! and another reconnects with its clock still running; every device clock starts at a random
//! reading, so some wrap their u32 µs counter during the hour.

use host::clock::DeviceClock;
use rand::Rng;
use sim::clock::{rng, Crystal, LinkJitter};

/// Device seconds per frame: 10 samples at 1 kHz.
const FRAME_S: f64 = 0.01;
/// The device's u32 µs counter wraps after this many seconds.
const WRAP_S: f64 = 4_294.967_296;
/// The misalignment is compared on a grid of this many true seconds (one frame).
const GRID_S: f64 = FRAME_S;

/// What to simulate.
#[derive(Debug, Clone)]
pub struct HandSim {
    pub fingers: usize,
    pub seconds: f64,
    pub max_ppm: f64,
    pub jitter: LinkJitter,
    pub seed: u64,
    /// The true time at which finger 0 is unplugged (its device restarts) and finger 1 loses
    /// its link (its clock keeps running), both for `outage_s`.
    pub reconnect_at_s: f64,
    pub outage_s: f64,
    /// The driver's mean pause between rounds of reads ([`host::device::OpenOptions::coalesce`]).
    pub coalesce_s: f64,
    /// The driver's catch window after each pause ([`host::device::OpenOptions::catch`]).
    pub catch_s: f64,
}

impl HandSim {
    /// The benchmark's hour: 16 fingers, ±100 ppm, a busy USB link, reconnects at half time.
    pub fn hour() -> Self {
        Self {
            fingers: 16,
            seconds: 3600.0,
            max_ppm: 100.0,
            jitter: LinkJitter::USB_BUSY,
            seed: 29,
            reconnect_at_s: 1800.0,
            outage_s: 5.0,
            coalesce_s: host::device::OpenOptions::default().coalesce.as_secs_f64(),
            catch_s: host::device::OpenOptions::default().catch.as_secs_f64(),
        }
    }
}

/// What the simulation found.
#[derive(Debug, Clone, Default)]
pub struct HandResult {
    /// Largest difference between two fingers' mapped times of the same true instant, s.
    pub worst_s: f64,
    /// The true time at which it happened.
    pub worst_at_s: f64,
    /// Largest |estimated − true| ppm over the fingers at the end.
    pub worst_ppm_error: f64,
    /// The change of each reconnected finger's time error across its outage, s (restart, continue).
    pub reconnect_steps_s: [f64; 2],
    /// Samples mapped and compared.
    pub frames: u64,
}

/// One finger's device: its crystal, and when it is connected.
struct Device {
    crystal: Crystal,
    /// A restart (`true`) or a link loss (`false`) at the reconnection time.
    outage: Option<bool>,
}

/// Per grid point: the least and greatest time error of the fingers present, and how many.
struct Grid {
    lo: Vec<f64>,
    hi: Vec<f64>,
    n: Vec<u8>,
}

impl Grid {
    fn new(points: usize) -> Self {
        Self {
            lo: vec![f64::INFINITY; points],
            hi: vec![f64::NEG_INFINITY; points],
            n: vec![0; points],
        }
    }

    fn add(&mut self, true_s: f64, err: f64) {
        let i = (true_s / GRID_S) as usize;
        if i < self.n.len() {
            self.lo[i] = self.lo[i].min(err);
            self.hi[i] = self.hi[i].max(err);
            self.n[i] = self.n[i].saturating_add(1);
        }
    }
}

/// Run the simulation.
pub fn simulate(sim: &HandSim) -> HandResult {
    let mut r = rng(sim.seed);
    let mut grid = Grid::new((sim.seconds / GRID_S) as usize + 1);
    let mut result = HandResult::default();
    for i in 0..sim.fingers {
        let dev = Device {
            crystal: Crystal {
                ppm: r.random_range(-sim.max_ppm..=sim.max_ppm),
                offset_s: r.random_range(0.0..2.0 * WRAP_S),
            },
            outage: [Some(true), Some(false)].get(i).copied().flatten(),
        };
        let (clock, steps) = run_finger(sim, &dev, sim.seed + 1 + i as u64, &mut grid);
        result.worst_ppm_error = result
            .worst_ppm_error
            .max((clock.ppm() - dev.crystal.ppm).abs());
        result.frames += steps.frames;
        if let Some(restart) = dev.outage {
            result.reconnect_steps_s[usize::from(!restart)] = steps.step_s;
        }
    }
    for k in 0..grid.n.len() {
        // Compare only where at least two fingers were heard.
        if grid.n[k] >= 2 && grid.hi[k] - grid.lo[k] > result.worst_s {
            result.worst_s = grid.hi[k] - grid.lo[k];
            result.worst_at_s = k as f64 * GRID_S;
        }
    }
    result
}

/// What one finger's run reports besides its clock.
struct FingerRun {
    frames: u64,
    /// Its time error just after the outage minus just before.
    step_s: f64,
}

/// The driver's one I/O thread for every port ([`host::device`]) as it reads, in rounds: a
/// pause of `U(0, 2·coalesce)`, one read of every port that has bytes, then a catch window of
/// `catch` in which every frame is read the moment it arrives. The rounds do not depend on any
/// one port's frames and are the same for every finger (each finger's `Reader` draws them from
/// the hand's seed), so each finger can be simulated on its own. The link is FIFO: a frame
/// never arrives before the one sent ahead of it.
struct Reader {
    last_arrival_s: f64,
    /// The current round's read after its pause, and the next round's.
    round_s: f64,
    next_round_s: f64,
    rounds: rand_chacha::ChaCha8Rng,
    coalesce_s: f64,
    catch_s: f64,
}

impl Reader {
    /// `seed` is the hand's: every finger's reader sees the same rounds.
    fn new(coalesce_s: f64, catch_s: f64, seed: u64) -> Self {
        Self {
            last_arrival_s: f64::NEG_INFINITY,
            round_s: f64::NEG_INFINITY,
            next_round_s: 0.0,
            rounds: rng(seed ^ 0x0052_4f55_4e44),
            coalesce_s,
            catch_s,
        }
    }

    /// The host time at which a frame reaching the link's end at `arrival_s` is read.
    fn read(&mut self, arrival_s: f64) -> f64 {
        let a = arrival_s.max(self.last_arrival_s);
        self.last_arrival_s = a;
        if self.coalesce_s <= 0.0 {
            return a; // no pause: every frame is read as it comes
        }
        while self.next_round_s < a {
            self.round_s = self.next_round_s;
            let pause_s = self.rounds.random_range(0.0..=2.0 * self.coalesce_s);
            self.next_round_s = self.round_s + self.catch_s + pause_s;
        }
        if a <= self.round_s + self.catch_s {
            a // in the catch window: read as it comes
        } else {
            self.next_round_s
        }
    }
}

/// One finger, frame by frame, as the recorder handles it; its time errors go to `grid`.
fn run_finger(sim: &HandSim, dev: &Device, seed: u64, grid: &mut Grid) -> (DeviceClock, FingerRun) {
    let mut link = rng(seed);
    let mut reader = Reader::new(sim.coalesce_s, sim.catch_s, sim.seed);
    let mut clock = DeviceClock::new();
    let mut held: Vec<(f64, f64)> = Vec::new();
    let mut run = FingerRun {
        frames: 0,
        step_s: 0.0,
    };
    let (mut before, mut after) = (None::<f64>, None::<f64>);
    let mut session = 0u32;
    let mut crystal = dev.crystal;
    // The stamps' origin within a session: the tracker unwraps the u32 counter from the
    // session's first frame on.
    let mut base: Option<f64> = None;
    // Frames by the device's clock: the first after true time zero, then one every FRAME_S.
    let next_frame = |c: &Crystal, t: f64| (c.device_s(t) / FRAME_S).ceil() * FRAME_S;
    let mut d = next_frame(&crystal, 0.0);
    loop {
        let t_frame = crystal.true_s(d);
        // It leaves when its last sample is taken.
        let t = crystal.true_s(d + FRAME_S);
        d += FRAME_S;
        if t >= sim.seconds {
            break;
        }
        if let Some(restart) = dev.outage {
            if session == 0 && t >= sim.reconnect_at_s {
                session = 1;
                base = None;
                let back = sim.reconnect_at_s + sim.outage_s;
                if restart {
                    // Powered up again: the device clock starts from zero.
                    crystal.offset_s = -(1.0 + crystal.ppm * 1e-6) * back;
                }
                d = next_frame(&crystal, back);
                continue;
            }
        }
        let d = d - FRAME_S;
        let b = *base.get_or_insert((d / WRAP_S).floor() * WRAP_S);
        let stamp = d - b;
        let host = reader.read(t + sim.jitter.draw(&mut link));
        clock.observe(session, stamp, host);
        held.push((stamp, t_frame));
        if !clock.settled() {
            continue;
        }
        for (stamp, t_true) in held.drain(..) {
            // Time error of the mapping against the truth: the constant floor of the link (and
            // the frame's own duration) is the same for every finger and cancels between them.
            let err = clock.host_s(stamp).unwrap_or(f64::NAN) - t_true;
            grid.add(t_true, err);
            run.frames += 1;
            if session == 0 {
                before = Some(err);
            } else if after.is_none() {
                after = Some(err);
            }
        }
    }
    if let (Some(b), Some(a)) = (before, after) {
        run.step_s = a - b;
    }
    (clock, run)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bench's hour, shortened to five minutes with the reconnections in the middle: any
    /// two fingers stay within a millisecond, and a reconnection moves a finger's time by far
    /// less.
    #[test]
    fn five_minutes_of_a_hand_stay_aligned_within_a_millisecond() {
        for seed in [29, 1, 2, 3] {
            let sim = HandSim {
                seconds: 300.0,
                reconnect_at_s: 150.0,
                seed,
                ..HandSim::hour()
            };
            let r = simulate(&sim);
            eprintln!("seed {seed}: {r:?}");
            assert!(r.frames > 16 * 29_000, "{r:?}");
            assert!(r.worst_s < 1e-3, "{r:?}");
            assert!(r.reconnect_steps_s.iter().all(|s| s.abs() < 1e-3), "{r:?}");
            assert!(r.worst_ppm_error < 1.0, "{r:?}");
        }
    }
}
