//! One message of every frame and command type, with values chosen so each field is visible in
//! the bytes (distinct, non-zero, negative codes, a zero byte for COBS to remove).
#![allow(dead_code)]

use protocol::*;

pub fn sample_frame() -> Message {
    let status = Status {
        saturated: 0b0101,
        null_state: NullState::Nulled,
        tare_active: true,
        drift_tracking: false,
        sample_overrun: true,
        adc_error: false,
        config_epoch: 3,
        dropped: 258,
    };
    let mut f = SampleFrame::new(0x0102_0304, 1_000_000, status, -2);
    f.push(Sample {
        ch: [1, -1, CODE_MAX],
    })
    .unwrap();
    f.push(Sample {
        ch: [CODE_MIN, 0x12_3456, 0],
    })
    .unwrap();
    Message::Sample(f)
}

pub fn info() -> Message {
    Message::Info(Info {
        protocol_version: PROTOCOL_VERSION,
        fw_version: [0, 1, 2],
        chip_serial: 0xDEAD_BEEF,
        sample_rate_hz: 1000,
        batch: 16,
        pga_gain: [1, 2, 4, 128],
        vref_mv: 1200,
        amp_gain: [3000.0, 1000.0, 1000.0],
        excitation_v: 3.3,
        filter: FilterConfig {
            smoother_alpha: 0.25,
            butterworth_order: 4,
            cutoff_hz: 50.0,
        },
        calibration: [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -0.5]],
        dac_codes: [2048, 1000, 3000, 0],
        tare: [-10, 20, -30],
        drift: [1, -2, 3],
        null_state: NullState::Nulled,
        drift_tracking: true,
        streaming: false,
        config_epoch: 9,
    })
}

pub fn request(tag: u8, command: Command) -> Message {
    Message::Request(Request { tag, command })
}

pub fn commands() -> Vec<(&'static str, Command)> {
    vec![
        ("start", Command::Start),
        ("stop", Command::Stop),
        ("set_rate", Command::SetRate { hz: 8000 }),
        (
            "set_filter",
            Command::SetFilter(FilterConfig {
                smoother_alpha: 1.0,
                butterworth_order: 2,
                cutoff_hz: 100.0,
            }),
        ),
        ("tare", Command::Tare { samples: 500 }),
        ("clear_tare", Command::ClearTare),
        ("auto_null", Command::AutoNull),
        ("get_info", Command::GetInfo),
        (
            "set_calibration",
            Command::SetCalibration([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        ),
        ("ping", Command::Ping { nonce: 0xCAFE_F00D }),
        (
            "set_drift_tracking",
            Command::SetDriftTracking { enabled: true },
        ),
        ("set_batch", Command::SetBatch { samples: 8 }),
    ]
}

pub fn replies() -> Vec<(&'static str, Reply)> {
    vec![
        (
            "ack",
            Reply::Ack {
                tag: 5,
                opcode: opcode::TARE,
            },
        ),
        (
            "nack",
            Reply::Nack {
                tag: 6,
                opcode: opcode::SET_RATE,
                code: NackCode::OutOfRange,
            },
        ),
        (
            "pong",
            Reply::Pong {
                tag: 7,
                nonce: 0xCAFE_F00D,
            },
        ),
    ]
}

pub fn all() -> Vec<(String, Message)> {
    let mut v = vec![
        ("sample".to_string(), sample_frame()),
        ("info".to_string(), info()),
    ];
    for (i, (name, c)) in commands().into_iter().enumerate() {
        v.push((format!("request_{name}"), request(i as u8 + 1, c)));
    }
    for (name, r) in replies() {
        v.push((format!("reply_{name}"), Message::Reply(r)));
    }
    v
}
