//! `tactile simulate`: the baseline model's recording of the standard compression test
//! (`docs/diagnosis-format.md`), optionally with catalogue effects and noise, through the same
//! forward model as the emulated sensor (`baseline::standard_test`, shared with the Python
//! package; `sim::forward`). This module parses the flags and writes the files.

use std::path::PathBuf;
use sysexit::ResultExt as _;

use anyhow::Context;
use baseline::standard_test::{simulate_standard_test, SimulateOptions};
use recording::machine::MachineExport;
use recording::Recording;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Inclination theta_p of the load axis from the fingertip axis, deg.
    #[arg(long, allow_hyphen_values = true)]
    pub contact_angle: f64,
    /// Azimuth phi of the tilt plane from the chip's x axis, deg.
    #[arg(long, allow_hyphen_values = true)]
    pub azimuth: f64,
    /// Load at which the rod stops and holds, N: the recorded load's peak, as a test machine
    /// that stops at a load (with an effect on the load, a relaxation, the rod travels further
    /// than the elastic gel would need).
    #[arg(long)]
    pub peak_load: f64,
    /// Output recording (CSV, `docs/recording-format.md`); `-` is the standard output, a device
    /// or FIFO is written as it is.
    #[arg(long)]
    pub out: PathBuf,
    /// Sample rate, Hz [default: hardware/fingertip.toml test.sample_rate_hz].
    #[arg(long)]
    pub rate: Option<f64>,
    /// The rod's speed while it loads, mm/min [default: hardware/fingertip.toml
    /// test.rod_speed_mm_per_min]; written to the metadata as `rod_speed_mm_per_min`.
    #[arg(long, value_name = "MM_PER_MIN")]
    pub rod_speed: Option<f64>,
    /// Rest after each return, s [default: hardware/fingertip.toml test.recovery_s]. With
    /// --then-peak-load it sets the length of a long recording (the benchmark's 300 s).
    #[arg(long)]
    pub recovery_s: Option<f64>,
    /// Gel Young's modulus, Pa [default: hardware/fingertip.toml].
    #[arg(long)]
    pub modulus_pa: Option<f64>,
    /// Repeat the compression cycle with these further peak loads, N.
    #[arg(long = "then-peak-load")]
    pub then_peak_load: Vec<f64>,
    /// White noise on each output, V (standard deviation).
    #[arg(long, default_value_t = 0.0)]
    pub noise_v: f64,
    /// White noise on the load cell, N.
    #[arg(long, default_value_t = 0.0)]
    pub noise_load_n: f64,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Switch on a catalogue effect (docs/diagnosis-format.md)
    #[arg(long = "effect", value_name = "NAME:PARAM=VALUE,...", long_help = effect_help())]
    pub effects: Vec<String>,
    /// Amplifier gains Fz,Mx,My, e.g. `2000,200,200` [default: the amplifier chain of
    /// hardware/frontend.toml].
    #[arg(long, value_name = "FZ,MX,MY", value_delimiter = ',', num_args = 1..=3)]
    pub gain: Option<Vec<f64>>,
    /// The firmware's first-order smoother y += alpha (x - y) on the outputs (written to the
    /// recording's metadata as `firmware_smoother_alpha`) [default: off].
    #[arg(long)]
    pub smoother_alpha: Option<f64>,
    /// A sinusoidal swing of the ambient temperature: amplitude (degC) and period (s). A
    /// `thermal_drift` follows the temperature, so it then departs from a pure warm-up.
    /// E.g. `1.5,60`.
    #[arg(long, value_name = "DEG_C,PERIOD_S", value_delimiter = ',', num_args = 1..=2)]
    pub ambient_swing: Option<Vec<f64>>,
    /// Bridge excitation, V [default: hardware/chip.toml].
    #[arg(long)]
    pub excitation_v: Option<f64>,
    /// Also write the volts at the ADC inputs (Fz, Mx, My as in the recording, the temperature
    /// sensor's output on channel 3) as a stimulus file for the QEMU board
    /// (`sim::ads131m04::stimulus_file`; scripts/demo-chain.sh).
    #[arg(long, value_name = "FILE", conflicts_with = "smoother_alpha")]
    pub adc_stimulus: Option<PathBuf>,
    /// Also write the test machine's export of the run (t_s, rod_mm, load_N), what `tactile log
    /// --reference` merges into a recording.
    #[arg(long, value_name = "CSV")]
    pub machine_csv: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let params = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let options = options(&args).coded()?;
    if args.adc_stimulus.is_some() {
        let rate_hz = options.compression_test(&params.fingertip).sample_rate_hz;
        anyhow::ensure!(
            sim::ads131m04::stimulus_file::is_data_rate(
                rate_hz,
                sim::ads131m04::AdcParams::from_hardware(&params.adc).clkin_hz
            ),
            "--adc-stimulus: {} Hz is not a data rate of the ADS131M04 (CLKIN/2/OSR: 500, 1000, \
             2000, ... 32000 Hz)",
            rate_hz
        );
    }
    let rec = simulate_standard_test(&options, &params).coded()?;
    write_outputs(&args, &params, &rec)
}

/// `--effect`'s help: the form, and every catalogue entry with its parameters.
fn effect_help() -> String {
    format!(
        "Switch on a catalogue effect (docs/diagnosis-format.md): `name:param=value,...`, e.g. \
         `viscoelastic_relaxation:tau_s=4,fraction=0.3`. Repeatable. The effects and their \
         parameters: {}",
        sim::effects::EffectKind::catalogue()
    )
}

/// A flag given the wrong number of values.
#[derive(Debug, thiserror::Error)]
#[error("{flag} takes {want} numbers, {form} (got {got})")]
pub struct CountError {
    flag: &'static str,
    want: usize,
    form: &'static str,
    got: usize,
}

impl sysexit::ExitStatus for CountError {
    fn exit_code(&self) -> u8 {
        sysexit::USAGE
    }
}

/// `values` as `N` numbers, given as one comma-separated value or as `N` values.
fn exactly<const N: usize>(
    values: Option<&[f64]>,
    flag: &'static str,
    form: &'static str,
) -> Result<Option<[f64; N]>, CountError> {
    values
        .map(|v| {
            <[f64; N]>::try_from(v).map_err(|_| CountError {
                flag,
                want: N,
                form,
                got: v.len(),
            })
        })
        .transpose()
}

/// The command line's options of the recording.
fn options(args: &Args) -> Result<SimulateOptions, CountError> {
    let gain = exactly::<3>(args.gain.as_deref(), "--gain", "FZ,MX,MY")?;
    let swing = exactly::<2>(
        args.ambient_swing.as_deref(),
        "--ambient-swing",
        "DEG_C,PERIOD_S",
    )?;
    Ok(SimulateOptions {
        rate_hz: args.rate,
        rod_speed_mm_per_min: args.rod_speed,
        recovery_s: args.recovery_s,
        modulus_pa: args.modulus_pa,
        then_peak_loads_n: args.then_peak_load.clone(),
        noise_v: args.noise_v,
        noise_load_n: args.noise_load_n,
        seed: args.seed,
        effects: args.effects.clone(),
        gain,
        smoother_alpha: args.smoother_alpha,
        ambient_swing: swing.map(|[amplitude_c, period_s]| (amplitude_c, period_s)),
        excitation_v: args.excitation_v,
        ..SimulateOptions::new(args.contact_angle, args.azimuth, args.peak_load)
    })
}

/// The recording, and the ADC stimulus and the machine's export where asked for, written
/// together where the user points (`diagnosis::outputs`: `-` the standard output, a device or
/// FIFO as it is, a file whole).
fn write_outputs(args: &Args, params: &hardware::Params, rec: &Recording) -> anyhow::Result<()> {
    let mut recording = Vec::new();
    rec.write_to(&mut recording)
        .context("encoding the recording")?;
    let mut files: Vec<(&std::path::Path, Vec<u8>)> = vec![(&args.out, recording)];
    if let Some(path) = &args.adc_stimulus {
        let sensor = sim::frontend::FrontEnd::from_params(params).temperature;
        let mut bytes = Vec::new();
        write_adc_stimulus(&mut bytes, rec, &sensor).context("encoding the ADC stimulus")?;
        files.push((path, bytes));
    }
    if let Some(path) = &args.machine_csv {
        let c = &rec.channels;
        let export = MachineExport {
            t_s: c.t_s.clone(),
            rod_mm: c.rod_mm.clone(),
            load_n: c.load_n.clone(),
        };
        let mut bytes = Vec::new();
        export
            .write_to(&mut bytes)
            .context("encoding the machine's export")?;
        files.push((path, bytes));
    }
    let paths: Vec<&std::path::Path> = files.iter().map(|(p, _)| *p).collect();
    diagnosis::outputs::check(&paths, &[], &[]).coded()?;
    let whole: Vec<(&std::path::Path, &[u8])> =
        files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    Ok(diagnosis::outputs::write_all_whole(&whole)?)
}

/// The recording's volts, sample by sample, as the QEMU board's ADC inputs. Without noise the
/// rest reads exactly zero; the temperature channel is the sensor's output at `temp_C` (its
/// offset where the recording has none).
fn write_adc_stimulus(
    out: &mut Vec<u8>,
    rec: &Recording,
    sensor: &sim::frontend::TempSensor,
) -> anyhow::Result<()> {
    let c = &rec.channels;
    let records: Vec<[f32; 4]> = (0..c.len())
        .map(|i| {
            let temp_v = rec
                .temp_c
                .as_ref()
                .map_or(sensor.offset_v, |t| sensor.output_v(t[i]));
            [c.fz_v[i], c.mx_v[i], c.my_v[i], temp_v].map(|v| v as f32)
        })
        .collect();
    let m = &rec.meta;
    sim::ads131m04::stimulus_file::write(
        out,
        m.sample_rate_hz as f32,
        [m.gain_fz, m.gain_mx, m.gain_my].map(|g| g as f32),
        m.excitation_v as f32,
        &records,
    )?;
    Ok(())
}
