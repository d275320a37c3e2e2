//! What the logger writes besides the samples: every metadata key of recording-v1 it can know,
//! the firmware filter the diagnosis models (`firmware_smoother_alpha`), and `temp_C` from ADC
//! channel 3 through the board's temperature sensor of `hardware/frontend.toml`.

use std::time::{Duration, UNIX_EPOCH};

use hil::check::scratch;
use hil::emu::{info_for, truth_frame, EmuConfig};
use host::device::{Event, Frame, Scale};
use host::logger::{Recorder, Setup};
use protocol::{encode_vec, FilterConfig, Message, Status};

#[test]
fn the_logger_writes_contract_keys_filter_and_temperature() {
    let dir = scratch("logger-meta");
    let cfg = EmuConfig::new(dir.join("unused"));
    let mut info = info_for(&cfg);
    info.filter = FilterConfig {
        smoother_alpha: 0.2,
        butterworth_order: 2,
        cutoff_hz: 50.0,
    };
    info.pga_gain[3] = 2;
    let setup = Setup::from_hardware("unit test".into()).unwrap();
    let hw = hardware::Params::load_default().unwrap();
    let sensor = &hw.frontend.temperature;
    // The code the ADC gives for 31.5 degC at the sensor: V = V0 + S T, code = V / (V per code).
    let t_true_c = 31.5;
    let v = sensor.offset_v + sensor.slope_v_per_c * t_true_c;
    let code = (v / Scale::from_info(&info).temp_volts_per_code).round() as i32;

    let start = UNIX_EPOCH + Duration::from_secs(1_800_000_000);
    let path = dir.join("r.csv");
    let mut rec = Recorder::create(&path, &info, &setup, start).unwrap();
    let mut frame = truth_frame(1, cfg.batch, cfg.rate_hz, Status::default());
    frame.temp = code;
    let mut raw = encode_vec(&Message::Sample(frame.clone())).unwrap();
    raw.pop();
    rec.on_event(&Event::Frame(Frame {
        seq: 1,
        t_device_us: u64::from(frame.t_us),
        host_time: start,
        session: 0,
        frame,
        raw,
    }))
    .unwrap();
    rec.flush().unwrap();

    let r = recording::read(&path).unwrap();
    let m = &r.meta;
    assert_eq!(m.sample_rate_hz, f64::from(cfg.rate_hz));
    assert_eq!([m.gain_fz, m.gain_mx, m.gain_my], [3000.0, 1000.0, 1000.0]);
    assert_eq!(
        m.excitation_v, 3.3,
        "the f32 of the info frame as configured, not 3.2999…"
    );
    assert_eq!(m.contact_angle_deg, hw.fingertip.test.contact_angle_deg);
    assert_eq!(m.azimuth_deg, hw.fingertip.test.azimuth_deg);
    assert_eq!(m.fingertip_radius_mm, hw.fingertip.radius_mm);
    assert_eq!(
        m.rod_speed_mm_per_min,
        Some(hw.fingertip.test.rod_speed_mm_per_min)
    );
    assert_eq!(m.source.as_deref(), Some("unit test"));
    assert_eq!(m.get(recording::SMOOTHER_KEY), Some("0.2"));
    assert_eq!(m.get("firmware_butterworth_order"), Some("2"));
    assert_eq!(m.get("firmware_cutoff_hz"), Some("50"));
    assert_eq!(
        m.get("chip_serial"),
        Some(format!("{:08x}", cfg.chip_serial).as_str())
    );

    let temp = r.temp_c.as_ref().expect("a temp_C column");
    assert_eq!(temp.len(), usize::from(cfg.batch));
    // One code of the 24-bit ADC at PGA 2 is 0.07 uV, i.e. 7 u°C.
    assert!(temp.iter().all(|t| (t - t_true_c).abs() < 1e-4), "{temp:?}");
    assert_eq!(r.column("temp_code").unwrap()[0], f64::from(code));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A device whose clock runs 25 times faster than the host's (an emulator on a virtual clock
/// runs a test's minutes in seconds). Mapped onto the host's clock its rows would span the
/// seconds the host saw. With `device_clock` they span the device's time, from the first
/// frame's receipt, and the metadata says which clock times them.
#[test]
fn rows_on_the_device_clock_span_the_device_time() {
    let dir = scratch("logger-device-clock");
    let cfg = EmuConfig::new(dir.join("unused"));
    let info = info_for(&cfg);
    let mut setup = Setup::from_hardware("unit test".into()).unwrap();
    setup.device_clock = true;
    let start = UNIX_EPOCH + Duration::from_secs(1_800_000_000);
    let path = dir.join("r.csv");
    let mut rec = Recorder::create(&path, &info, &setup, start).unwrap();
    let frame_s = f64::from(cfg.batch) / f64::from(cfg.rate_hz);
    let frames = 400u32;
    for seq in 1..=frames {
        let frame = truth_frame(seq, cfg.batch, cfg.rate_hz, Status::default());
        let t_device_s = f64::from(frame.t_us) * 1e-6;
        let mut raw = encode_vec(&Message::Sample(frame.clone())).unwrap();
        raw.pop();
        rec.on_event(&Event::Frame(Frame {
            seq,
            t_device_us: u64::from(frame.t_us),
            host_time: start + Duration::from_secs_f64(t_device_s / 25.0),
            session: 0,
            frame,
            raw,
        }))
        .unwrap();
    }
    rec.finish("test").unwrap();
    let r = recording::read(&path).unwrap();
    let t = &r.channels.t_s;
    let span_s = t[t.len() - 1] - t[0];
    let device_span_s = f64::from(frames) * frame_s - 1.0 / f64::from(cfg.rate_hz);
    assert!(
        (span_s - device_span_s).abs() < 1e-6,
        "{span_s} s for {device_span_s} s"
    );
    let base = r.meta.other.iter().find(|(k, _)| k == "time_base").unwrap();
    assert!(base.1.starts_with("device clock"), "{}", base.1);
}

/// The MCAP file's record `clock <label>` at the end of a run names the time base its times
/// are on, as the CSV's header does, besides the clock's final values.
#[test]
fn the_mcap_clock_record_names_the_time_base() {
    use std::cell::RefCell;
    use std::rc::Rc;

    use host::logger::clock_key;
    use host::logger::mcap_io::McapSink;

    let dir = scratch("logger-mcap-clock");
    let cfg = EmuConfig::new(dir.join("unused"));
    let info = info_for(&cfg);
    let start = UNIX_EPOCH + Duration::from_secs(1_800_000_000);
    for device_clock in [false, true] {
        let mut setup = Setup::from_hardware("unit test".into()).unwrap();
        setup.device_clock = device_clock;
        let mcap_path = dir.join(format!("r-{device_clock}.mcap"));
        let sink = Rc::new(RefCell::new(McapSink::create(&mcap_path).unwrap()));
        let pairs = host::logger::metadata(&info, &setup, start).pairs();
        let channels = sink.borrow_mut().add_sensor("thumb", &pairs).unwrap();
        let csv = dir.join(format!("r-{device_clock}.csv"));
        let mut rec = Recorder::create(&csv, &info, &setup, start)
            .unwrap()
            .with_mcap((sink.clone(), channels));
        rec.finish("thumb").unwrap();
        rec.detach_mcap();
        Rc::try_unwrap(sink)
            .ok()
            .expect("the recorder let go of the writer")
            .into_inner()
            .finish()
            .unwrap();

        let bytes = std::fs::read(&mcap_path).unwrap();
        let record = mcap::read::LinearReader::new(&bytes)
            .unwrap()
            .filter_map(|r| match r.unwrap() {
                mcap::records::Record::Metadata(m) if m.name == "clock thumb" => Some(m),
                _ => None,
            })
            .next()
            .expect("a clock record");
        assert_eq!(
            record
                .metadata
                .get(clock_key::TIME_BASE)
                .map(String::as_str),
            Some(clock_key::time_base(device_clock)),
            "{record:?}"
        );
        for key in [clock_key::PPM, clock_key::UNCERTAINTY, clock_key::RESTARTS] {
            assert!(record.metadata.contains_key(key), "{key}: {record:?}");
        }
        // The CSV's header says the same.
        let r = recording::read(&csv).unwrap();
        assert_eq!(
            r.meta.get(clock_key::TIME_BASE),
            Some(clock_key::time_base(device_clock))
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
