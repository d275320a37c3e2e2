//! The recording as the diagnosis sees it: gaps dropped, the four compared channels, a noise
//! estimate per channel, and a block-averaged copy for fitting. The blocks follow the rod's
//! moves and still stretches ([`crate::regimes::motion`]): 20 ms blocks (50 Hz) around the
//! edges of every move, at least [`MOVE_BLOCKS`] blocks along each move (20 ms to 200 ms), and
//! 200 ms blocks (5 Hz) in still stretches away from the edges. A block is never shorter than
//! one sample (10 Hz data keeps every sample where it needs fine blocks) and never straddles the
//! edge of a move. Blocks of whole mains periods also cancel 50 Hz pickup and its harmonics.

use rayon::prelude::*;
use recording::Recording;

use crate::noise::Noise;
use crate::quantisation::Lattice;
use crate::regimes::{self, Regime, Segment};

/// Compared channels, in contract order.
pub const CHANNELS: [&str; 4] = ["load_N", "fz_V", "mx_V", "my_V"];
/// Block length around the edges of moves, and in still stretches.
pub const FINE_BLOCK_S: f64 = 0.02;
pub const COARSE_BLOCK_S: f64 = 0.2;
/// Fine blocks this long before and after each edge of a move, and after its end: the load
/// turns at an edge (contact, reversal, the fast start of a relaxation) within the response
/// times the catalogue fits, fractions of a second to seconds.
const MARGIN_BEFORE_S: f64 = 0.5;
const MARGIN_AFTER_S: f64 = 3.0;
/// Blocks along a move at least: a block mean differs from the curve at its centre by
/// f'' T^2 / 24, a relative 1e-4 of a power-law load over a twentieth of its move.
pub const MOVE_BLOCKS: f64 = 20.0;
/// Fewest samples at a still rod to read the sample-scale noise from (its deviation then has a
/// standard error of 5 %).
const MIN_STILL_SAMPLES: usize = 200;

/// One rate's worth of the signals.
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub t_s: Vec<f64>,
    pub rod_mm: Vec<f64>,
    /// load_N, fz_V, mx_V, my_V.
    pub y: [Vec<f64>; 4],
    pub temp_c: Option<Vec<f64>>,
    /// Full-rate samples behind each sample (1 at full rate).
    pub count: Vec<usize>,
}

impl Series {
    pub fn len(&self) -> usize {
        self.t_s.len()
    }
}

/// Both rates plus per-channel scales.
#[derive(Debug, Clone)]
pub struct Data {
    pub full: Series,
    pub fit: Series,
    /// Peak-to-peak range of each recorded channel (the contract's RMSE normaliser).
    pub range: [f64; 4],
    /// The full-rate samples `start..end` behind each sample of `fit`.
    pub bounds: Vec<(usize, usize)>,
    /// Full sample rate, Hz: from the time column, the metadata's only where time stands still.
    pub rate_hz: f64,
    /// Each channel's noise at full rate ([`Noise`]).
    pub noise: [Noise; 4],
    /// Channels whose values show no noise at all (a simulation's load cell): a model can
    /// reproduce them to the arithmetic's precision, and their noise is taken as the most
    /// precise noisy channel's, relative to the range (`as_precise_as_the_best`).
    pub noiseless: [bool; 4],
    /// The lattice each channel's values sit on, where they do ([`Lattice`]).
    pub lattice: [Option<Lattice>; 4],
    /// Channels of real values ([`real_valued`]), whose exact repeats are readings held.
    real: [bool; 4],
    /// The regimes found at the full rate, with the load telling a start in contact, as index
    /// runs on `fit` (its blocks never straddle a segment's edge). Finer than detecting them on
    /// `fit` itself, where block means blur the encoder's quanta.
    pub segments: Vec<Segment>,
    /// Channels the baseline does not model (a user's simulation that leaves them empty): never
    /// compared, whatever they hold.
    unmodelled: [bool; 4],
    /// [`Data::weight`] of every decimated sample, computed once: every residual of every fit
    /// asks for it, and its `powf` was a sixth of a diagnosis's time.
    weights: [Vec<f64>; 4],
    /// The rod's periodic drive over the fitting stretch: its periodogram's size and the
    /// fundamental's bin, if it has one. Worked out once by `terms::line` (every channel and every
    /// candidate described asks for it, and the rod is the same).
    pub drive_bin: std::sync::OnceLock<(usize, Option<usize>)>,
}

/// Why a recording cannot be analysed although it parsed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// Fewer usable rows than a fit needs.
    #[error("only {0} rows without gaps; the diagnosis needs at least 200")]
    TooShort(usize),
    /// The rod never presses into the fingertip.
    #[error("column `rod_mm` never rises above 0: no compression in this recording")]
    NoContact,
    /// The FE-backed fingertip response for the recording's angles and radius failed.
    #[error(transparent)]
    Fingertip(#[from] baseline::fe_response::FeResponseError),
    /// The user's simulation cannot be the recording's baseline.
    #[error(transparent)]
    Simulation(#[from] crate::simulation::SimulationError),
}

impl Data {
    pub fn new(rec: &Recording) -> Result<Self, DataError> {
        // Copied without its gaps only where it has any.
        let whole;
        let rec = if rec.has_gaps() {
            whole = rec.without_gaps();
            &whole
        } else {
            rec
        };
        let c = &rec.channels;
        if c.len() < 200 {
            return Err(DataError::TooShort(c.len()));
        }
        if !c.rod_mm.iter().any(|&r| r > 0.0) {
            return Err(DataError::NoContact);
        }
        let full = Series {
            t_s: c.t_s.clone(),
            rod_mm: c.rod_mm.clone(),
            y: [
                c.load_n.clone(),
                c.fz_v.clone(),
                c.mx_v.clone(),
                c.my_v.clone(),
            ],
            temp_c: rec
                .temp_c
                .clone()
                .filter(|t| t.iter().all(|v| v.is_finite())),
            count: vec![1; c.len()],
        };
        let span = full.t_s[full.len() - 1] - full.t_s[0];
        let rate = if span > 0.0 {
            (full.len() - 1) as f64 / span
        } else {
            rec.meta.sample_rate_hz
        };
        let (_, full_segments) =
            regimes::detect_with_load(&full.t_s, &full.rod_mm, Some(&full.y[0]));
        let (block, cut) = blocks(&full.t_s, &full_segments, rate);
        let bounds = block_bounds(&block, &cut);
        let fit = decimate(&full, &bounds);
        let segments = on_blocks(&full_segments, &bounds);
        let range: [f64; 4] = std::array::from_fn(|k| peak_to_peak(full.y[k].iter().copied()));
        let lattice: [Option<Lattice>; 4] = std::array::from_fn(|k| Lattice::of(&full.y[k]));
        let real = std::array::from_fn(|k| real_valued(lattice[k].as_ref(), &full.y[k], range[k]));
        let (noise, noiseless) = channel_noise(&full, &full_segments, rate, (&range, &real));
        let weights = std::array::from_fn(|c| {
            fit.count
                .iter()
                .map(|&n| 1.0 / noise[c].mean_sd(n))
                .collect()
        });
        Ok(Self {
            full,
            fit,
            range,
            rate_hz: rate,
            noise,
            noiseless,
            lattice,
            real,
            bounds,
            segments,
            unmodelled: [false; 4],
            weights,
            drive_bin: Default::default(),
        })
    }

    /// Whether channel `c` is worth comparing: the baseline models it, and its peak-to-peak
    /// range stands ten noise deviations above its noise.
    pub fn compared(&self, c: usize) -> bool {
        !self.unmodelled[c] && self.range[c] > 10.0 * self.noise[c].sd()
    }

    /// Whether the baseline models channel `c` (a user's simulation may leave it out).
    pub fn modelled(&self, c: usize) -> bool {
        !self.unmodelled[c]
    }

    /// The same data with the channels `lacks` marks left uncompared: the baseline (a user's
    /// simulation) does not model them.
    pub(crate) fn unmodelled(self, lacks: [bool; 4]) -> Self {
        Self {
            unmodelled: lacks,
            ..self
        }
    }

    /// Weight of decimated sample `k` of channel `c`: one over its noise level.
    pub fn weight(&self, c: usize, k: usize) -> f64 {
        self.weights[c][k]
    }

    /// The data with every block weighed at zero where its channel read one value over and
    /// over (`None` where no channel did): a channel of real values ([`real_valued`]) never
    /// repeats a value while it reads, so a block made of repeats is a reading held (a cell
    /// clipped at its limit, a frozen output) and tells a fit nothing of the sensor there.
    pub(crate) fn without_held(&self) -> Option<Data> {
        let mut d = self.clone();
        let mut any = false;
        for c in (0..4).filter(|&c| self.real[c]) {
            let y = &self.full.y[c];
            for (k, &(a, b)) in self.bounds.iter().enumerate() {
                if b > a && (a..b).all(|i| repeats(y, i)) {
                    d.weights[c][k] = 0.0;
                    any = true;
                }
            }
        }
        any.then_some(d)
    }

    /// The data with channel `c` weighed at zero from `from_s` on: a channel that froze there
    /// carries nothing about the sensor after it, and a fit must not be asked to follow it.
    pub(crate) fn frozen_from(&self, c: usize, from_s: f64) -> Data {
        let mut d = self.clone();
        for (w, &t) in d.weights[c].iter_mut().zip(&self.fit.t_s) {
            if t >= from_s {
                *w = 0.0;
            }
        }
        d
    }
}

/// Each channel's noise ([`Noise`]) over the full-rate series `full` with its `segments`, and
/// whether it is noiseless: neither noise nor a lattice shows in its still stretches.
fn channel_noise(
    full: &Series,
    segments: &[Segment],
    rate: f64,
    (range, real): (&[f64; 4], &[bool; 4]),
) -> ([Noise; 4], [bool; 4]) {
    // The noise is estimated without a mains line: its second differences are large and
    // strongly correlated, and read as AR(1) noise they weighed a channel down tenfold and could
    // hide it as one carrying no signal. The line itself is fitted later.
    let quiet: Vec<Option<Vec<f64>>> = (0..4)
        .into_par_iter()
        .map(|k| crate::mains::without_line(&full.t_s, &full.y[k], rate))
        .collect();
    // Slow noise is looked for where nothing but noise moves the channels: from a still start
    // (not one the load shows in contact) up to the first contact, where the contract puts
    // `rod_mm` = 0.
    let free = match segments.first() {
        Some(first) if first.regime == Regime::Rest => {
            0..full.rod_mm.iter().position(|&r| r > 0.0).unwrap_or(0)
        }
        _ => 0..0,
    };
    // The sample-scale noise is read where the rod stands still: at a low rate a moving rod
    // bends the load between neighbouring samples, and its second differences would read as
    // noise (at 20 Hz, as noise correlated at 0.99). All of it where the still stretches are
    // too short.
    let still_runs: Vec<std::ops::Range<usize>> = segments
        .iter()
        .filter(|s| matches!(s.regime, Regime::Rest | Regime::Hold | Regime::Recovery))
        .map(|s| s.start..s.end)
        .filter(|r| r.len() >= 3)
        .collect();
    let still = if still_runs.iter().map(|r| r.len()).sum::<usize>() >= MIN_STILL_SAMPLES {
        still_runs
    } else {
        std::iter::once(0..full.len()).collect()
    };
    let mut noiseless = [false; 4];
    let noise = std::array::from_fn(|k| {
        let x = quiet[k].as_deref().unwrap_or(&full.y[k]);
        let pieces: Vec<&[f64]> = still.iter().map(|r| &x[r.clone()]).collect();
        let live: Vec<&[f64]> = live_runs(&full.y[k], real[k], &still)
            .into_iter()
            .map(|r| &x[r])
            .collect();
        let mut n = Noise::estimate(&live, &x[free.clone()]);
        // A series quantised coarser than its noise mostly repeats its values: the median of
        // its second differences is then zero, though every value it takes is off by up to half
        // a quantum q. That error is uniform, of deviation q / sqrt(12) (Widrow), and no less is
        // assumed (a load cell read to 0.05 N over 0.02 N of noise had weighed the load 400
        // times over the outputs). Read on the raw channel: a fitted mains line takes the
        // values off the lattice.
        let q = crate::quantisation::quantum(&full.y[k]);
        // Noiseless only where no still stretch shows noise anywhere: the median of the
        // estimate ignores a channel that freezes for most of a test (a stuck output), the
        // mean square does not.
        noiseless[k] = q / 12f64.sqrt() < 1e-6 * range[k]
            && second_difference_rms(&pieces) / 6f64.sqrt() < 1e-6 * range[k];
        n.sample.sd = n
            .sample
            .sd
            .max(q / 12f64.sqrt())
            .max(1e-6 * range[k])
            .max(1e-12);
        n
    });
    (as_precise_as_the_best(noise, &noiseless, range), noiseless)
}

/// Whether channel `y` (of peak-to-peak `range`) holds real values: on no lattice, and with no
/// step between neighbours as coarse as a millionth of its range (finer than any converter or
/// export resolves, the floor the noise model keeps too). Such a channel never repeats a value
/// exactly while it reads. A converter's or an export's channel repeats its values at rest
/// (a Mach-1's load cell, 0.00085 N steps written to six decimals, off any one lattice).
fn real_valued(lattice: Option<&Lattice>, y: &[f64], range: f64) -> bool {
    lattice.is_none() && crate::quantisation::quantum(y) < 1e-6 * range
}

/// Whether sample `i` of `y` repeats a neighbour exactly.
fn repeats(y: &[f64], i: usize) -> bool {
    (i > 0 && y[i] == y[i - 1]) || (i + 1 < y.len() && y[i] == y[i + 1])
}

/// The runs of `ranges` where channel `y` is live: a channel of `real` values
/// ([`real_valued`]) never repeats a value exactly while it reads, and a frozen one does
/// nothing else, so the samples next to an exact repeat are left out. A stuck output's frozen
/// stretches had read as a channel without noise and weighed it a million-fold. Any other
/// channel, and one with too few live samples left, keeps `ranges` as they are (a dead sensor
/// is its own finding).
fn live_runs(
    y: &[f64],
    real: bool,
    ranges: &[std::ops::Range<usize>],
) -> Vec<std::ops::Range<usize>> {
    if !real {
        return ranges.to_vec();
    }
    let mut runs = Vec::new();
    for r in ranges {
        let mut start = r.start;
        for i in r.clone() {
            if repeats(y, i) {
                if i - start >= 3 {
                    runs.push(start..i);
                }
                start = i + 1;
            }
        }
        if r.end.saturating_sub(start) >= 3 {
            runs.push(start..r.end);
        }
    }
    if runs.iter().map(|r| r.len()).sum::<usize>() >= MIN_STILL_SAMPLES {
        runs
    } else {
        ranges.to_vec()
    }
}

/// The RMS of the second differences within each of `pieces`, leaving out a few samples at
/// either end, where a still stretch's detected edge can sit a sample from the rod's corner
/// (NaN where none remain).
fn second_difference_rms(pieces: &[&[f64]]) -> f64 {
    const EDGE: usize = 3;
    let (sum, count) = pieces
        .iter()
        .filter(|p| p.len() > 2 * EDGE + 2)
        .flat_map(|p| p[EDGE..p.len() - EDGE].windows(3))
        .map(|w| w[2] - 2.0 * w[1] + w[0])
        .filter(|d| d.is_finite())
        .fold((0.0, 0usize), |(s, n), d| (s + d * d, n + 1));
    (sum / count as f64).sqrt()
}

/// `noise` with each `noiseless` channel as precise, relative to its range, as the most
/// precise channel that carries noise. What a channel without noise can be trusted to is not
/// in its values; weighed at its floor (a millionth of its range) a noiseless load outweighed
/// the outputs a hundred-million-fold, and the fit followed its slightest misfit alone.
fn as_precise_as_the_best(
    mut noise: [Noise; 4],
    noiseless: &[bool; 4],
    range: &[f64; 4],
) -> [Noise; 4] {
    let best = (0..4)
        .filter(|&c| !noiseless[c] && range[c] > 0.0)
        .map(|c| noise[c].sample.sd / range[c])
        .fold(f64::INFINITY, f64::min);
    if best.is_finite() {
        for c in (0..4).filter(|&c| noiseless[c]) {
            noise[c].sample.sd = noise[c].sample.sd.max(best * range[c]);
        }
    }
    noise
}

/// The block length (samples) wanted at each sample, and where a block must end (the edges of
/// the segments).
fn blocks(t_s: &[f64], segments: &[Segment], rate_hz: f64) -> (Vec<usize>, Vec<bool>) {
    let n = t_s.len();
    let samples = |s: f64| ((rate_hz * s).round() as usize).max(1);
    let mut block = vec![samples(COARSE_BLOCK_S); n];
    let mut cut = vec![false; n];
    let finer = |from: f64, to: f64, len: usize, block: &mut Vec<usize>| {
        let a = t_s.partition_point(|&t| t < from);
        let b = t_s.partition_point(|&t| t <= to);
        block[a..b].iter_mut().for_each(|l| *l = (*l).min(len));
    };
    for s in segments {
        cut[s.start] = true;
        if !matches!(s.regime, Regime::Loading | Regime::Release) {
            continue;
        }
        let (t0, t1) = (t_s[s.start], t_s[s.end - 1]);
        // Whole fine blocks (whole mains periods), at most a coarse one.
        let along = ((t1 - t0) / MOVE_BLOCKS / FINE_BLOCK_S).floor().max(1.0) * FINE_BLOCK_S;
        finer(t0, t1, samples(along.min(COARSE_BLOCK_S)), &mut block);
        let fine = samples(FINE_BLOCK_S);
        finer(t0 - MARGIN_BEFORE_S, t0 + MARGIN_BEFORE_S, fine, &mut block);
        finer(t1 - MARGIN_BEFORE_S, t1 + MARGIN_AFTER_S, fine, &mut block);
    }
    (block, cut)
}

/// Blocks `start..end`, each as long as `block` asks at its first sample, ending early where
/// the wanted length changes or at a `cut`.
pub fn block_bounds(block: &[usize], cut: &[bool]) -> Vec<(usize, usize)> {
    let mut bounds = Vec::new();
    let mut k = 0;
    while k < block.len() {
        let mut end = k.saturating_add(block[k].max(1)).min(block.len());
        if let Some(j) = (k + 1..end).find(|&j| block[j] != block[k] || cut[j]) {
            end = j;
        }
        bounds.push((k, end));
        k = end;
    }
    bounds
}

/// `segments` (on the full series) as runs of the blocks `bounds`; each segment starts at a
/// block's start (a cut).
fn on_blocks(segments: &[Segment], bounds: &[(usize, usize)]) -> Vec<Segment> {
    let block_of = |k: usize| bounds.partition_point(|&(a, _)| a < k);
    segments
        .iter()
        .map(|s| Segment {
            start: block_of(s.start),
            end: block_of(s.end),
            ..*s
        })
        .filter(|s| s.end > s.start)
        .collect()
}

/// Block means over `bounds`.
pub fn decimate(s: &Series, bounds: &[(usize, usize)]) -> Series {
    let mean = |x: &[f64]| {
        bounds
            .iter()
            .map(|&(a, b)| x[a..b].iter().sum::<f64>() / (b - a) as f64)
            .collect::<Vec<f64>>()
    };
    Series {
        t_s: mean(&s.t_s),
        rod_mm: mean(&s.rod_mm),
        y: std::array::from_fn(|c| mean(&s.y[c])),
        temp_c: s.temp_c.as_ref().map(|t| mean(t)),
        count: bounds
            .iter()
            .map(|&(a, b)| s.count[a..b].iter().sum())
            .collect(),
    }
}

/// max - min of `values`, 0 for none.
pub fn peak_to_peak(values: impl IntoIterator<Item = f64>) -> f64 {
    let (lo, hi) = values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

impl Data {
    /// Channel `c`'s residual against the model's `model` on the decimated series, less the
    /// rounding bias where the channel is quantised coarser than its noise ([`Data::lattice`]).
    pub fn residual_without_rounding_bias(&self, c: usize, model: &[f64]) -> Vec<f64> {
        let fit = &self.fit;
        let r: Vec<f64> = fit.y[c].iter().zip(model).map(|(y, m)| y - m).collect();
        let Some(lattice) = self.lattice[c] else {
            return r;
        };
        let noise = &self.noise[c];
        let bin = fit.count.iter().copied().max().unwrap_or(1);
        let bins = fit.count.iter().sum::<usize>() / bin.max(1);
        let sigma = lattice.noise_before_rounding(noise.sd());
        let harmonics = lattice.harmonics(sigma, noise.mean_sd(bin), bins);
        let rate = self.rate_hz;
        // Each block's sweep: the model's slope there (from its neighbours) over the block's time.
        let sweep: Vec<f64> = (0..model.len())
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(model.len() - 1));
                let dt = fit.t_s[b] - fit.t_s[a];
                let slope = if dt > 0.0 {
                    (model[b] - model[a]) / dt
                } else {
                    0.0
                };
                slope.abs() * fit.count[i] as f64 / rate
            })
            .collect();
        let weight: Vec<f64> = fit.count.iter().map(|&n| n as f64).collect();
        crate::quantisation::without_rounding_bias(&r, model, &sweep, &weight, &lattice, harmonics)
    }
}

/// A recording the diagnosis cannot use is bad data.
impl sysexit::ExitStatus for DataError {
    fn exit_code(&self) -> u8 {
        match self {
            // A simulation that is not there is a missing input, not bad data.
            Self::Simulation(e) => e.exit_code(),
            _ => sysexit::DATA,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A channel that freezes for most of its still stretches is not noiseless: the mean square
    /// of its second differences keeps the noise of the rest, which a median would not.
    #[test]
    fn a_channel_that_freezes_is_not_noiseless_and_a_smooth_one_is() {
        let noisy: Vec<f64> = (0..1000).map(|k| ((k * 7919) % 13) as f64 * 1e-3).collect();
        let frozen = vec![0.25; 3000];
        let smooth: Vec<f64> = (0..4000).map(|k| 1e-3 * k as f64).collect();
        assert!(second_difference_rms(&[&noisy, &frozen]) > 1e-4);
        assert!(second_difference_rms(&[&smooth]) < 1e-12);
    }

    /// A channel of real values is live where it never repeats a value: its frozen tail is
    /// left out of the noise's stretches; a channel a converter resolves keeps them whole.
    #[test]
    fn a_frozen_tail_is_left_out_of_the_noise_and_a_lattice_is_not() {
        let live: Vec<f64> = (0..600).map(|k| (k as f64 * 0.7).sin() * 1e-3).collect();
        let mut y = live.clone();
        y.extend(std::iter::repeat_n(live[599], 600));
        let real = |y: &[f64], range: f64| real_valued(Lattice::of(y).as_ref(), y, range);
        let runs = live_runs(&y, real(&y, 10.0), &[0..300, 300..1200]);
        assert_eq!(runs, [0..300, 300..599]);
        let counts: Vec<f64> = (0..1200).map(|k| ((k / 7) % 3) as f64 * 0.5).collect();
        let whole = [0..600, 600..1200];
        assert_eq!(live_runs(&counts, real(&counts, 1.0), &whole), whole);
        // A converter's steps of 0.00085049 N written to six decimals: off any one lattice,
        // but as coarse as a converter resolves; its repeats are readings.
        let written: Vec<f64> = (0..1200)
            .map(|k| (((k / 3) % 5) as f64 * 0.000_850_49 * 1e6).round() / 1e6)
            .collect();
        assert_eq!(live_runs(&written, real(&written, 5.0), &whole), whole);
    }

    /// Blocks over the standard test at `rate_hz`: the bounds, the full-rate segments and the
    /// segments carried onto the blocks.
    fn blocked(rate_hz: f64) -> (Vec<(usize, usize)>, Vec<Segment>, Vec<Segment>) {
        let h = sim::compression::RodSchedule {
            sample_rate_hz: rate_hz,
            ..Default::default()
        }
        .rod_history(&[1.5, 1.0]);
        let (_, full) = regimes::detect(&h.t_s, &h.rod_mm);
        let (block, cut) = blocks(&h.t_s, &full, rate_hz);
        let bounds = block_bounds(&block, &cut);
        let carried = on_blocks(&full, &bounds);
        (bounds, full, carried)
    }

    #[test]
    fn blocks_follow_the_segments_from_10_hz_to_5_khz() {
        for rate in [10.0, 100.0, 1000.0, 5000.0] {
            let (bounds, full, carried) = blocked(rate);
            // Contiguous, never empty, covering everything.
            assert_eq!(bounds[0].0, 0);
            assert!(bounds.windows(2).all(|w| w[0].1 == w[1].0));
            assert!(bounds.iter().all(|&(a, b)| b > a));
            // Every segment survives, in order, on block edges.
            let names = |s: &[Segment]| s.iter().map(|s| (s.regime, s.cycle)).collect::<Vec<_>>();
            assert_eq!(names(&full), names(&carried), "{rate} Hz");
            for (f, c) in full.iter().zip(&carried) {
                assert_eq!(bounds[c.start].0, f.start, "{rate} Hz");
            }
            // Fine blocks (20 ms, at least a sample) in the moves, coarse (200 ms) deep in the
            // recovery, 3 s after the release.
            let len = |k: usize| bounds[k].1 - bounds[k].0;
            let fine = ((rate * FINE_BLOCK_S).round() as usize).max(1);
            let coarse = ((rate * COARSE_BLOCK_S).round() as usize).max(1);
            let release = carried
                .iter()
                .find(|s| s.regime == Regime::Release)
                .unwrap();
            assert!(
                (release.start..release.end).all(|k| len(k) <= fine),
                "{rate} Hz"
            );
            let recovery = carried
                .iter()
                .find(|s| s.regime == Regime::Recovery)
                .unwrap();
            let deep = recovery.start + (recovery.end - recovery.start) / 2;
            assert_eq!(len(deep), coarse, "{rate} Hz");
        }
    }
}
