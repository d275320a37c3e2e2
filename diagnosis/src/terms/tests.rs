//! Each term on an analytical case: a recording whose model is known exactly (a load that is a
//! power of the travel, outputs proportional to it, white noise), with the term added, must give
//! the term's own parameters back; without it, the search must keep nothing.

use super::fitting::Context;
use super::{search, Nested, Term, TermKind};
use crate::data::Data;
use recording::{Channels, Meta, Recording};

const RATE_HZ: f64 = 100.0;
/// Output gains per newton of load (V/N) and the noise of each channel.
const GAINS: [f64; 4] = [1.0, 0.01, 0.004, -0.003];
const NOISE: [f64; 4] = [0.01, 1e-4, 1e-4, 1e-4];

/// Two cycles: 30 s ramp to 4 mm, 10 s hold, 2 s release, 13 s rest, from 5 s and 60 s.
fn rod_mm(t: f64) -> f64 {
    let local = if t >= 60.0 { t - 60.0 } else { t };
    match local {
        x if x < 5.0 => 0.0,
        x if x < 35.0 => 4.0 * (x - 5.0) / 30.0,
        x if x < 45.0 => 4.0,
        x if x < 47.0 => 4.0 * (47.0 - x) / 2.0,
        _ => 0.0,
    }
}

/// The clean model of channel `c` at time t.
fn clean(t: f64, c: usize) -> f64 {
    let d = rod_mm(t);
    let load = 5.0 * d.max(0.0).powf(1.5);
    GAINS[c] * load
}

/// A temperature that swings by 2 K over 80 s.
fn temp_c(t: f64) -> f64 {
    25.0 + 2.0 * (std::f64::consts::TAU * t / 80.0).sin()
}

/// The recording with `extra(t, c, clean)` added to channel c, and white noise (a fixed LCG).
pub(crate) fn recording(extra: impl Fn(f64, usize, f64) -> f64) -> Recording {
    let n = (120.0 * RATE_HZ) as usize;
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut gauss = move || {
        // Sum of 12 uniforms less 6: unit variance, good enough for white noise here.
        (0..12)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            })
            .sum::<f64>()
            - 6.0
    };
    let mut ch = Channels::default();
    for k in 0..n {
        let t = k as f64 / RATE_HZ;
        ch.t_s.push(t);
        ch.rod_mm.push(rod_mm(t));
        let mut y = [0.0; 4];
        for (c, v) in y.iter_mut().enumerate() {
            let m = clean(t, c);
            *v = m + extra(t, c, m) + NOISE[c] * gauss();
        }
        ch.load_n.push(y[0]);
        ch.fz_v.push(y[1]);
        ch.mx_v.push(y[2]);
        ch.my_v.push(y[3]);
    }
    let mut rec = Recording::new(Meta {
        sample_rate_hz: RATE_HZ,
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        fingertip_radius_mm: 20.0,
        gain_fz: 1.0,
        gain_mx: 1.0,
        gain_my: 1.0,
        excitation_v: 3.3,
        rod_speed_mm_per_min: None,
        source: None,
        other: Vec::new(),
    });
    rec.temp_c = Some(rec_temp(&ch.t_s));
    rec.channels = ch;
    rec
}

fn rec_temp(t_s: &[f64]) -> Vec<f64> {
    t_s.iter().map(|&t| temp_c(t)).collect()
}

/// The masks of the held-out stretch (the second cycle) on `data`.
fn masks(data: &Data) -> (Vec<bool>, Vec<bool>) {
    let held: Vec<bool> = data.fit.t_s.iter().map(|&t| t >= 58.0).collect();
    (held.iter().map(|h| !h).collect(), held)
}

/// A context whose model is the clean signal.
fn with_context<R>(data: &Data, f: impl FnOnce(&mut Context, Nested) -> R) -> R {
    with_context_beside(data, false, f)
}

/// [`with_context`], the terms searched beside the whole catalogue model with `beside`.
fn with_context_beside<R>(
    data: &Data,
    beside: bool,
    f: impl FnOnce(&mut Context, Nested) -> R,
) -> R {
    let (fit, held) = masks(data);
    let model: [Vec<f64>; 4] = std::array::from_fn(|c| {
        data.fit
            .t_s
            .iter()
            .map(|&t| clean(t, c))
            .collect::<Vec<f64>>()
    });
    let full: [Vec<f64>; 4] =
        std::array::from_fn(|c| data.full.t_s.iter().map(|&t| clean(t, c)).collect());
    let mut ctx = Context::new(
        data,
        (&fit, &held),
        [true; 4],
        model,
        std::array::from_fn(|c| full[c].as_slice()),
        [0.0; 4],
    );
    ctx.beside_catalogue = beside;
    let n: usize = (0..4).map(|_| fit.iter().filter(|&&b| b).count()).sum();
    let nested = Nested {
        n,
        k: 19,
        fit_chi2: (0..4).map(|c| ctx.chi2(c, None, &fit)).sum(),
        heldout_chi2: (0..4).map(|c| ctx.chi2(c, None, &held)).sum(),
    };
    f(&mut ctx, nested)
}

/// The search's terms on a recording with `extra`.
fn found(extra: impl Fn(f64, usize, f64) -> f64) -> Vec<Term> {
    found_on([true; 4], extra)
}

/// [`found`] with only the `used` channels compared (the load cell alone: a test of the
/// material). Every term found keeps an amplitude its physics admits, however it was refitted.
fn found_on(used: [bool; 4], extra: impl Fn(f64, usize, f64) -> f64) -> Vec<Term> {
    let rec = recording(extra);
    let data = Data::new(&rec).expect("the analytical recording is usable");
    let terms = with_context(&data, |ctx, nested| {
        ctx.used = used;
        search(ctx, nested).terms
    });
    for t in &terms {
        assert!(
            t.kind.admits(t.beta[0]),
            "{:?} turned: {:?}",
            t.kind,
            t.beta
        );
    }
    terms
}

fn only(terms: &[Term], kind: TermKind, channel: usize) -> &Term {
    assert!(
        terms.iter().any(|t| t.kind == kind && t.channel == channel),
        "{kind:?} on {channel} not among {:?}",
        terms
            .iter()
            .map(|t| (t.kind, t.channel))
            .collect::<Vec<_>>()
    );
    terms
        .iter()
        .find(|t| t.kind == kind && t.channel == channel)
        .unwrap()
}

#[test]
fn nothing_is_described_without_a_term() {
    let terms = found(|_, _, _| 0.0);
    assert!(
        terms.is_empty(),
        "{:?}",
        terms.iter().map(|t| t.kind).collect::<Vec<_>>()
    );
}

#[test]
fn an_offset_step_gives_its_time_and_size() {
    let terms = found(|t, c, _| if c == 2 && t >= 20.0 { 0.004 } else { 0.0 });
    let s = only(&terms, TermKind::OffsetStep, 2);
    assert!((s.shape[0] - 20.0).abs() < 0.3, "{:?}", s.shape);
    let all: Vec<_> = terms
        .iter()
        .map(|t| (t.kind, t.channel, t.shape.clone(), t.beta.clone()))
        .collect();
    assert!((s.beta[0] - 0.004).abs() < 2e-4, "{all:?}");
}

/// A step at rest just before the held-out stretch: on the fitting stretch a freeze fits it
/// exactly as well (the model is constant there), and the held-out stretch refutes the freeze.
/// The step it stood in front of must still be offered and kept.
#[test]
fn a_step_at_rest_is_not_lost_to_the_freeze_that_ties_with_it() {
    let terms = found(|t, c, _| if c == 0 && t >= 55.0 { 0.3 } else { 0.0 });
    let s = only(&terms, TermKind::OffsetStep, 0);
    assert!((s.shape[0] - 55.0).abs() < 0.3, "{:?}", s.shape);
    assert!((s.beta[0] - 0.3).abs() < 0.02, "{:?}", s.beta);
    assert!(terms.iter().all(|t| t.kind != TermKind::StuckChannel));
}

#[test]
fn a_stuck_channel_gives_its_time_and_value() {
    let terms = found(|t, c, m| if c == 3 && t >= 40.0 { -m } else { 0.0 });
    let s = only(&terms, TermKind::StuckChannel, 3);
    assert!((s.shape[0] - 40.0).abs() < 0.3, "{:?}", s.shape);
    assert!(s.beta[0].abs() < 2e-4, "{:?}", s.beta);
}

/// A channel that leaves the model at 40 s but keeps moving after it (here a drift of 3 times
/// its noise over the 80 s left, as a load still relaxing on a time scale the model lacks does
/// on a real Mach-1 hold) does not read a constant: it is not frozen.
#[test]
fn a_channel_that_still_moves_is_not_frozen() {
    let terms = found(|t, c, m| {
        if c == 3 && t >= 40.0 {
            -m + 3e-4 * (t - 40.0) / 80.0
        } else {
            0.0
        }
    });
    assert!(
        terms.iter().all(|t| t.kind != TermKind::StuckChannel),
        "{:?}",
        terms
            .iter()
            .map(|t| (t.kind, t.channel))
            .collect::<Vec<_>>()
    );
}

#[test]
fn a_line_gives_its_frequency_and_amplitude() {
    let line = |t: f64| 0.05 * (std::f64::consts::TAU * 0.7 * t).sin();
    let terms = found(|t, c, _| if c == 0 { line(t) } else { 0.0 });
    let s = only(&terms, TermKind::Line, 0);
    assert!((s.shape[0] - 0.7).abs() < 0.01, "{:?}", s.shape);
    // Block means of up to 200 ms attenuate a 0.7 Hz line by at most a few percent.
    assert!(
        (s.beta[0].hypot(s.beta[1]) - 0.05).abs() < 0.005,
        "{:?}",
        s.beta
    );
}

/// The search's terms on a recording with `extra`, beside the whole catalogue model.
fn found_beside(extra: impl Fn(f64, usize, f64) -> f64) -> Vec<Term> {
    let rec = recording(extra);
    let data = Data::new(&rec).expect("the analytical recording is usable");
    with_context_beside(&data, true, |ctx, nested| search(ctx, nested).terms)
}

#[test]
fn beside_the_catalogue_a_periodic_line_is_found_and_a_slow_one_or_a_step_is_not() {
    let line = |t: f64, f: f64| 0.05 * (std::f64::consts::TAU * f * t).sin();
    let terms = found_beside(|t, c, _| if c == 0 { line(t, 0.7) } else { 0.0 });
    let s = only(&terms, TermKind::Line, 0);
    assert!((s.shape[0] - 0.7).abs() < 0.01, "{:?}", s.shape);
    // A wander (period 20 s) and an offset step are what a catalogue effect's own misfit can
    // look like: alone, they are described; beside the whole catalogue model, not.
    for extra in [
        Box::new(move |t: f64, c: usize, _: f64| if c == 0 { line(t, 0.05) } else { 0.0 })
            as Box<dyn Fn(f64, usize, f64) -> f64>,
        Box::new(|t: f64, c: usize, _: f64| if c == 2 && t >= 20.0 { 0.004 } else { 0.0 }),
    ] {
        assert!(!found(&extra).is_empty());
        let beside = found_beside(&extra);
        assert!(
            beside.iter().all(|t| t.kind == TermKind::Recalibration),
            "{:?}",
            beside
                .iter()
                .map(|t| (t.kind, t.channel, t.shape.clone()))
                .collect::<Vec<_>>()
        );
    }
}

#[test]
fn an_output_relaxation_gives_its_time_constant_and_fraction() {
    let rec = recording(|_, _, _| 0.0);
    let t: Vec<f64> = rec.channels.t_s.clone();
    let relaxed = |c: usize| {
        let mut x: Vec<f64> = t.iter().map(|&t| clean(t, c)).collect();
        sim::effects::ViscoelasticRelaxation {
            tau_s: 5.0,
            fraction: 0.2,
        }
        .apply(&t, &mut x);
        x
    };
    let fz = relaxed(1);
    let terms = found(|time, c, m| {
        if c == 1 {
            fz[(time * RATE_HZ).round() as usize] - m
        } else {
            0.0
        }
    });
    let s = only(&terms, TermKind::OutputRelaxation, 1);
    assert!((s.shape[0] / 5.0 - 1.0).abs() < 0.25, "{:?}", s.shape);
    // tau on a grid of 33 steps over 0.2-500 s (4.89 s nearest 5 s), the scale refitted beside
    // it: the fraction within a fifth.
    assert!((s.beta[0] - 0.2).abs() < 0.04, "{:?} {:?}", s.shape, s.beta);
}

#[test]
fn a_force_with_the_square_of_the_speed_gives_its_power() {
    // 4 mm in 30 s on loading, 2 s on release: the release is 15 times faster.
    let v_max = 2.0;
    let terms = found(|t, c, m| {
        let v = (rod_mm(t + 0.005) - rod_mm(t - 0.005)) / 0.01;
        if c == 0 {
            0.3 * m * (v.abs() / v_max).powi(2)
        } else {
            0.0
        }
    });
    let s = only(&terms, TermKind::SpeedPower, 0);
    assert_eq!(s.shape[0], 2.0, "{:?}", s.shape);
}

#[test]
fn a_load_cell_lag_gives_its_lag() {
    let terms = found(|t, c, m| if c == 0 { clean(t - 0.1, 0) - m } else { 0.0 });
    let s = only(&terms, TermKind::LoadLag, 0);
    assert!((s.beta[0] - 0.1).abs() < 0.02, "{:?}", s.beta);
    // Where the protocol cannot show a lag (the catalogue's `time_offset` precondition), the
    // load cell's lag is not offered either.
    let rec = recording(|t, c, m| if c == 0 { clean(t - 0.1, 0) - m } else { 0.0 });
    let data = Data::new(&rec).expect("the analytical recording is usable");
    let terms = with_context(&data, |ctx, nested| {
        ctx.forbidden = vec![sim::effects::EffectKind::TimeOffset];
        search(ctx, nested).terms
    });
    assert!(terms.iter().all(|t| t.kind != TermKind::LoadLag));
}

#[test]
fn a_span_that_follows_the_temperature_gives_its_coefficient() {
    let terms = found(|t, c, m| {
        if c == 1 {
            m * 0.02 * (temp_c(t) - 25.0)
        } else {
            0.0
        }
    });
    let s = only(&terms, TermKind::TemperatureSpan, 1);
    assert!((s.beta[0] - 0.02).abs() < 0.003, "{:?}", s.beta);
}

#[test]
fn a_permanent_set_gives_its_size() {
    // From the first reversal (45 s) on the load follows the travel less 0.05 mm.
    let terms = found(|t, c, m| {
        if c == 0 && t >= 45.0 {
            5.0 * (rod_mm(t) - 0.05).max(0.0).powf(1.5) - m
        } else {
            0.0
        }
    });
    let s = only(&terms, TermKind::PermanentSet, 0);
    assert!((s.beta[0] - 0.05).abs() < 0.015, "{:?}", s.beta);
}

#[test]
fn a_load_that_stiffens_gives_its_exponent() {
    // The load becomes the catalogue's stiffening law of itself: peak (load / peak)^2.5.
    let peak = 5.0 * 4.0_f64.powf(1.5);
    let stiffens = |_, c, m: f64| {
        if c == 0 {
            peak * (m / peak).powf(2.5) - m
        } else {
            0.0
        }
    };
    // Where the outputs are compared and follow the model, a stiffening the load alone shows
    // is not the material's (it would press the chip harder too): not offered.
    let beside_outputs = found(stiffens);
    assert!(beside_outputs
        .iter()
        .all(|t| t.kind != TermKind::LoadStiffening));
    // A test of the material alone.
    let terms = found_on([true, false, false, false], stiffens);
    let s = only(&terms, TermKind::LoadStiffening, 0);
    assert!((s.shape[0] - 2.5).abs() < 0.15, "{:?}", s.shape);
    // The recording goes up to its peak: no ceiling, so no clipping described.
    assert!(terms.iter().all(|t| t.kind != TermKind::LoadSaturation));
    assert!((s.beta[0] - 1.0).abs() < 0.1, "{:?}", s.beta);
}

#[test]
fn a_load_cell_that_clips_gives_its_limit() {
    let terms = found(|_, c, m| if c == 0 { m.min(25.0) - m } else { 0.0 });
    let s = only(&terms, TermKind::LoadSaturation, 0);
    assert!((s.shape[0] - 25.0).abs() < 0.1, "{:?}", s.shape);
}

#[test]
fn a_sensing_element_set_gives_its_times() {
    // The Fz output gains 0.002 V x a set that follows the load with 3 s and recovers with 75 s.
    let peak = GAINS[1] * 5.0 * 4.0_f64.powf(1.5);
    // The state at every sample of the recording, integrated once.
    let n = (120.0 * RATE_HZ) as usize + 1;
    let mut x = 0.0;
    let states: Vec<f64> = (0..n)
        .map(|k| {
            let u = clean(k as f64 / RATE_HZ, 1) / peak;
            let tau = if u > x { 3.0 } else { 75.0 };
            x += (u - x) * (1.0 - (-1.0 / (RATE_HZ * tau)).exp());
            x
        })
        .collect();
    let set = |t: f64| states[(t * RATE_HZ).round() as usize];
    let terms = found(|t, c, _| if c == 1 { 0.002 * set(t) } else { 0.0 });
    let s = only(&terms, TermKind::OutputSet, 1);
    // Within a step of the grids (a factor of about 1.5).
    let near = |got: f64, want: f64| (got / want).ln().abs() < 1.5f64.ln();
    assert!(
        near(s.shape[0], 3.0) && near(s.shape[1], 75.0),
        "{:?}",
        s.shape
    );
    assert!((s.beta[0] - 0.002).abs() < 3e-4, "{:?}", s.beta);
}

/// A load that recovers as the material dries, beside the whole catalogue model: found, with
/// its share and time constant.
#[test]
fn a_load_that_recovers_beside_the_catalogue_gives_its_share_and_time() {
    let terms = found_beside(|t, c, m| {
        if c == 0 {
            m * 0.1 * (1.0 - (-t / 40.0).exp())
        } else {
            0.0
        }
    });
    let s = only(&terms, TermKind::MaterialRecovery, 0);
    assert!((s.shape[0] / 40.0 - 1.0).abs() < 0.3, "{:?}", s.shape);
    assert!((s.beta[0] - 0.1).abs() < 0.03, "{:?}", s.beta);
}

/// The catalogue's directions are orthonormal on the fitting stretch (weighted by the noise),
/// and a column the others already span adds none.
#[test]
fn the_catalogue_directions_are_an_orthonormal_basis_of_what_they_span() {
    let rec = recording(|_, _, _| 0.0);
    let data = Data::new(&rec).expect("the analytical recording is usable");
    with_context(&data, |ctx, _| {
        let t: Vec<f64> = ctx.t_s().to_vec();
        let twice_t: Vec<f64> = t.iter().map(|x| 2.0 * x).collect();
        ctx.set_catalogue(std::array::from_fn(|_| vec![t.clone(), twice_t.clone()]));
        let basis = &ctx.catalogue[1];
        // The offset, the signal and time: three directions, the doubled time none.
        assert_eq!(basis.len(), 3);
        for (i, a) in basis.iter().enumerate() {
            for (j, b) in basis.iter().enumerate() {
                let dot: f64 = (0..ctx.len())
                    .filter(|&k| ctx.fit_mask[k])
                    .map(|k| a[k] * b[k] * ctx.data.weight(1, k).powi(2))
                    .sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-9, "{i} {j}: {dot}");
            }
        }
    });
}
