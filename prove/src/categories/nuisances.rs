//! Nuisances: what real recordings carry that is not missing physics, and must not be named.

use recording::Recording;

use baseline::synth::Noise;

/// One nuisance applied to a finished recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Nuisance {
    /// The gains in the metadata off by 20–35 % each (the amplifier's real gain differs from
    /// its nominal one, or the user copied another sensor's metadata).
    WrongGains,
    /// The load cell not tared: a constant 0.3–1 N on the load.
    LoadOffset,
    /// Coarse loggers: outputs in steps of twice their noise, rod in 1 µm, load in 0.05 N.
    Quantisation,
    /// Eight isolated spikes of 20–50 noise deviations on random channels (a loose connector).
    Spikes,
    /// 2 % of the rows dropped at random and one gap of a second (a logger that lost packets).
    MissingRows,
    /// Noise with a correlation time of 0.1 s on top of the white noise, as strong as it.
    ColouredNoise,
    /// The temperature column swings by 1–2 °C while the outputs do not follow it.
    TemperatureIgnored,
}

impl Nuisance {
    pub const ALL: [Nuisance; 7] = [
        Nuisance::WrongGains,
        Nuisance::LoadOffset,
        Nuisance::Quantisation,
        Nuisance::Spikes,
        Nuisance::MissingRows,
        Nuisance::ColouredNoise,
        Nuisance::TemperatureIgnored,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Nuisance::WrongGains => "wrong gains in the metadata",
            Nuisance::LoadOffset => "load-cell offset",
            Nuisance::Quantisation => "quantisation",
            Nuisance::Spikes => "isolated spikes",
            Nuisance::MissingRows => "missing rows",
            Nuisance::ColouredNoise => "coloured noise",
            Nuisance::TemperatureIgnored => "temperature the outputs ignore",
        }
    }

    /// Apply to `rec`, with uniform deviates `u(a, b)` and standard normals `z()`; `noise` is
    /// the recording's white noise. (The temperature swing is set before simulating, in the
    /// generator, since the simulator writes the temperature column.)
    pub fn apply(
        self,
        rec: &mut Recording,
        u: &mut dyn FnMut(f64, f64) -> f64,
        z: &mut dyn FnMut() -> f64,
        noise: &Noise,
    ) {
        let c = &mut rec.channels;
        match self {
            Nuisance::WrongGains => {
                let mut off = || {
                    let s = if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
                    1.0 + s * u(0.2, 0.35)
                };
                rec.meta.gain_fz *= off();
                rec.meta.gain_mx *= off();
                rec.meta.gain_my *= off();
            }
            Nuisance::LoadOffset => {
                let offset = u(0.3, 1.0);
                c.load_n.iter_mut().for_each(|x| *x += offset);
            }
            Nuisance::Quantisation => {
                let q = |x: &mut f64, step: f64| *x = (*x / step).round() * step;
                for (ch, s) in [&mut c.fz_v, &mut c.mx_v, &mut c.my_v]
                    .into_iter()
                    .zip(noise.volts)
                {
                    ch.iter_mut().for_each(|x| q(x, 2.0 * s));
                }
                c.rod_mm.iter_mut().for_each(|x| q(x, 1e-3));
                c.load_n.iter_mut().for_each(|x| q(x, 0.05));
            }
            Nuisance::Spikes => spikes(rec, u, noise),
            Nuisance::MissingRows => missing_rows(rec, u),
            Nuisance::ColouredNoise => coloured(rec, z, noise),
            Nuisance::TemperatureIgnored => {}
        }
    }
}

fn spikes(rec: &mut Recording, u: &mut dyn FnMut(f64, f64) -> f64, noise: &Noise) {
    let n = rec.channels.t_s.len();
    for _ in 0..8 {
        let k = (u(0.0, 1.0) * n as f64) as usize % n.max(1);
        let size = u(20.0, 50.0) * if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
        let c = &mut rec.channels;
        match (u(0.0, 4.0) as usize).min(3) {
            0 => c.load_n[k] += size * noise.load_n,
            1 => c.fz_v[k] += size * noise.volts[0],
            2 => c.mx_v[k] += size * noise.volts[1],
            _ => c.my_v[k] += size * noise.volts[2],
        }
    }
}

fn missing_rows(rec: &mut Recording, u: &mut dyn FnMut(f64, f64) -> f64) {
    let t = &rec.channels.t_s;
    let end = t.last().copied().unwrap_or(0.0);
    let gap_start = u(0.2, 0.8) * end;
    let keep: Vec<bool> = t
        .iter()
        .map(|&ts| !(gap_start..gap_start + 1.0).contains(&ts) && u(0.0, 1.0) >= 0.02)
        .collect();
    let rows: Vec<usize> = (0..keep.len()).filter(|&i| keep[i]).collect();
    *rec = rec.rows(&rows);
}

/// AR(1) noise with a 0.1 s correlation time and the white noise's own deviation.
fn coloured(rec: &mut Recording, z: &mut dyn FnMut() -> f64, noise: &Noise) {
    let dt = 1.0 / rec.meta.sample_rate_hz;
    let rho = (-dt / 0.1f64).exp();
    let innovation = (1.0 - rho * rho).sqrt();
    let c = &mut rec.channels;
    for (ch, s) in [
        (&mut c.load_n, noise.load_n),
        (&mut c.fz_v, noise.volts[0]),
        (&mut c.mx_v, noise.volts[1]),
        (&mut c.my_v, noise.volts[2]),
    ] {
        let mut state = z();
        for x in ch.iter_mut() {
            state = rho * state + innovation * z();
            *x += s * state;
        }
    }
}
