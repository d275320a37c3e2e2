//! Random valid messages for the property and robustness tests.
#![allow(dead_code)]

use protocol::*;
use rand::Rng;

fn code(rng: &mut impl Rng) -> Code {
    rng.random_range(CODE_MIN..=CODE_MAX)
}

fn finite(rng: &mut impl Rng) -> f32 {
    rng.random_range(-1.0e6f32..1.0e6)
}

pub fn status(rng: &mut impl Rng) -> Status {
    let null_state = [
        NullState::Off,
        NullState::Searching,
        NullState::Nulled,
        NullState::Failed,
    ][rng.random_range(0..4)];
    Status {
        saturated: rng.random_range(0..16),
        null_state,
        tare_active: rng.random(),
        drift_tracking: rng.random(),
        sample_overrun: rng.random(),
        adc_error: rng.random(),
        config_epoch: rng.random(),
        dropped: rng.random(),
    }
}

pub fn sample_frame(rng: &mut impl Rng) -> SampleFrame {
    let mut f = SampleFrame::new(rng.random(), rng.random(), status(rng), code(rng));
    for _ in 0..rng.random_range(1..=MAX_BATCH) {
        f.push(Sample {
            ch: [code(rng), code(rng), code(rng)],
        })
        .unwrap();
    }
    f
}

pub fn filter(rng: &mut impl Rng) -> FilterConfig {
    FilterConfig {
        smoother_alpha: finite(rng),
        butterworth_order: rng.random(),
        cutoff_hz: finite(rng),
    }
}

fn matrix(rng: &mut impl Rng) -> Calibration {
    let mut m = [[0.0; 3]; 3];
    m.iter_mut().flatten().for_each(|v| *v = finite(rng));
    m
}

pub fn info(rng: &mut impl Rng) -> Info {
    Info {
        protocol_version: rng.random(),
        fw_version: rng.random(),
        chip_serial: rng.random(),
        sample_rate_hz: rng.random(),
        batch: rng.random(),
        pga_gain: rng.random(),
        vref_mv: rng.random(),
        amp_gain: [finite(rng), finite(rng), finite(rng)],
        excitation_v: finite(rng),
        filter: filter(rng),
        calibration: matrix(rng),
        dac_codes: rng.random(),
        tare: rng.random(),
        drift: rng.random(),
        null_state: NullState::Failed,
        drift_tracking: rng.random(),
        streaming: rng.random(),
        config_epoch: rng.random(),
    }
}

pub fn command(rng: &mut impl Rng) -> Command {
    match rng.random_range(0..12) {
        0 => Command::Start,
        1 => Command::Stop,
        2 => Command::SetRate { hz: rng.random() },
        3 => Command::SetFilter(filter(rng)),
        4 => Command::Tare {
            samples: rng.random(),
        },
        5 => Command::ClearTare,
        6 => Command::AutoNull,
        7 => Command::GetInfo,
        8 => Command::SetCalibration(matrix(rng)),
        9 => Command::Ping {
            nonce: rng.random(),
        },
        10 => Command::SetDriftTracking {
            enabled: rng.random(),
        },
        _ => Command::SetBatch {
            samples: rng.random(),
        },
    }
}

pub fn reply(rng: &mut impl Rng) -> Reply {
    match rng.random_range(0..3) {
        0 => Reply::Ack {
            tag: rng.random(),
            opcode: rng.random(),
        },
        1 => Reply::Nack {
            tag: rng.random(),
            opcode: rng.random(),
            code: NackCode::from_byte(rng.random()),
        },
        _ => Reply::Pong {
            tag: rng.random(),
            nonce: rng.random(),
        },
    }
}

/// Mostly sample frames, as on a real link.
pub fn message(rng: &mut impl Rng) -> Message {
    match rng.random_range(0..20) {
        0 => Message::Info(info(rng)),
        1 => Message::Reply(reply(rng)),
        2 => Message::Request(Request {
            tag: rng.random(),
            command: command(rng),
        }),
        _ => Message::Sample(sample_frame(rng)),
    }
}
