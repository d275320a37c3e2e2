//! The lab sessions' designs: what each session varies from test to test, what it hides and
//! where (the sensor's and the gel's, shared by every test, or one test's own), all drawn from
//! the session's seed before anything is simulated. A design is the truth its session is scored
//! against; nothing here knows how the diagnosis works.

use baseline::synth::{Gaussian, Noise};
use baseline::BaselineParams;
use sim::effects::{Effect, EffectKind, MainsInterference, ThermalDrift};

use crate::truth_baseline;

/// What a lab session hides, and so what a right answer names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabKind {
    /// Two effects of the sensor or the gel shared by four tests, and one test with an effect
    /// of its own (a warm-up drift, mains pickup, a clip).
    Mixed,
    /// Another model's fingertip, nothing hidden, across azimuths, speeds or contact angles.
    NullOther,
    /// Contact friction at an inclined contact, pressed at rod speeds a decade apart.
    FrictionSpeeds,
    /// Hysteresis or relaxation (one of the two) at rod speeds a decade apart.
    HysteresisOrRelaxation,
    /// Tests at different sample rates, amplifier gains and excitation, with one shared effect
    /// or none.
    RatesAndGains,
}

impl LabKind {
    /// Every lab kind, in the order of the tables.
    pub const ALL: [LabKind; 5] = [
        LabKind::Mixed,
        LabKind::NullOther,
        LabKind::FrictionSpeeds,
        LabKind::HysteresisOrRelaxation,
        LabKind::RatesAndGains,
    ];

    /// The kind's key on the command line (`tactile prove --sessions --category lab --kind`).
    pub fn key(self) -> &'static str {
        match self {
            LabKind::Mixed => "mixed",
            LabKind::NullOther => "null-other",
            LabKind::FrictionSpeeds => "friction-speeds",
            LabKind::HysteresisOrRelaxation => "hysteresis-or-relaxation",
            LabKind::RatesAndGains => "rates-gains",
        }
    }

    /// The kind whose [`Self::key`] is `key`.
    pub fn from_key(key: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.key() == key)
    }

    pub fn name(self) -> &'static str {
        match self {
            LabKind::Mixed => "mixed: two shared, one test's own",
            LabKind::NullOther => "null on another model's fingertip",
            LabKind::FrictionSpeeds => "friction across speeds",
            LabKind::HysteresisOrRelaxation => "hysteresis or relaxation across speeds",
            LabKind::RatesAndGains => "rates, gains and excitation differ",
        }
    }

    /// Sessions of this kind per `--per-kind`: the kinds with several designs get two.
    pub fn sessions_per_round(self) -> usize {
        match self {
            LabKind::Mixed | LabKind::HysteresisOrRelaxation => 2,
            _ => 1,
        }
    }

    /// A right answer also needs the primary parameter of each hidden effect within 20 %
    /// (friction's mu: the brief's "friction across speeds").
    pub fn needs_parameters(self) -> bool {
        self == LabKind::FrictionSpeeds
    }
}

/// An effect of one test alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Own {
    /// This test's chip warmed up: its offset drifts and its `temp_C` rises.
    Drift(ThermalDrift),
    /// Mains pickup on this test's cabling.
    Mains(MainsInterference),
    /// The amplifiers clip at `share` of this test's largest output in its second (lower)
    /// press, so both presses clip; the rail in volts is known once the test is simulated.
    Clip { share: f64 },
}

impl Own {
    pub fn kind(self) -> EffectKind {
        match self {
            Own::Drift(_) => EffectKind::ThermalDrift,
            Own::Mains(_) => EffectKind::MainsInterference,
            Own::Clip { .. } => EffectKind::AmplifierSaturation,
        }
    }
}

/// The fingertip a session's tests are pressed on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Family {
    /// Our FE model's.
    Ours,
    /// Another model's ([`crate::categories::OtherFingertip`]): a power-law contact of
    /// `exponent`, its outputs linear in the load or following the FE's map.
    Other { exponent: f64, linear_outputs: bool },
}

/// One test of a session: what the lab set for it.
#[derive(Debug, Clone, PartialEq)]
pub struct TestDesign {
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    pub speed_mm_per_min: f64,
    pub sample_rate_hz: f64,
    /// This test's amplifier gains over the sensor's nominal ones, declared in its metadata.
    pub gain_factor: [f64; 3],
    /// This test's bridge excitation over the nominal one, declared in its metadata.
    pub excitation_factor: f64,
    /// The two presses' peak loads.
    pub peaks_n: [f64; 2],
    /// The jig's mounting error in azimuth, set anew for every test.
    pub azimuth_shift_deg: f64,
    pub own: Option<Own>,
    /// The seed of this test's noise.
    pub seed: u64,
}

/// One session: one sensor in one fingertip, its tests, and what it hides.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionDesign {
    pub id: usize,
    pub kind: LabKind,
    /// What the tests vary, in words.
    pub varies: String,
    pub family: Family,
    /// The sensor's and the gel's truth (its azimuth shift is each test's).
    pub base: BaselineParams,
    /// The load at which another model's force law meets the FE's (the session's peak).
    pub reference_n: f64,
    pub noise: Noise,
    /// The sensor's and the gel's effects: one parameter set for every test.
    pub shared: Vec<Effect>,
    pub tests: Vec<TestDesign>,
}

/// What a session's tests step through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Vary {
    Azimuth,
    Speed,
    Angle,
}

impl Vary {
    /// The settings of `n` (3 or 4) tests: azimuths and contact angles evenly over their
    /// range, rod speeds a decade apart (and a fourth, fast one).
    fn steps(self, n: usize) -> &'static [f64] {
        match (self, n >= 4) {
            (Vary::Azimuth, false) => &[0.0, 45.0, 90.0],
            (Vary::Azimuth, true) => &[0.0, 30.0, 60.0, 90.0],
            (Vary::Speed, false) => &[6.0, 20.0, 60.0],
            (Vary::Speed, true) => &[6.0, 20.0, 60.0, 200.0],
            (Vary::Angle, false) => &[0.0, 15.0, 30.0],
            (Vary::Angle, true) => &[0.0, 10.0, 20.0, 30.0],
        }
    }

    fn words(self) -> &'static str {
        match self {
            Vary::Azimuth => "azimuth",
            Vary::Speed => "rod speed",
            Vary::Angle => "contact angle",
        }
    }
}

/// Which test's own effect, before its parameters are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum OwnKind {
    Drift,
    Mains,
    Clip,
}

use EffectKind as K;

/// The mixed sessions' designs, in turn: two shared effects, what the tests vary, the kind of
/// one test's own effect. A drift is never under an AC coupling (which of the two acts first
/// is the lab's wiring, not the sensor's physics).
const MIXED: [([EffectKind; 2], Vary, OwnKind); 6] = [
    (
        [K::ViscoelasticRelaxation, K::Crosstalk],
        Vary::Azimuth,
        OwnKind::Drift,
    ),
    (
        [K::TimeOffset, K::HighpassCoupling],
        Vary::Speed,
        OwnKind::Mains,
    ),
    ([K::Hysteresis, K::Stiffening], Vary::Speed, OwnKind::Clip),
    (
        [K::ViscoelasticRelaxation, K::HighpassCoupling],
        Vary::Angle,
        OwnKind::Mains,
    ),
    ([K::Crosstalk, K::Hysteresis], Vary::Azimuth, OwnKind::Drift),
    ([K::Stiffening, K::TimeOffset], Vary::Speed, OwnKind::Clip),
];

/// The rates-and-gains sessions' shared effect, in turn (the last: none).
const RATES_SHARED: [Option<EffectKind>; 4] = [
    Some(K::ViscoelasticRelaxation),
    Some(K::Crosstalk),
    Some(K::TimeOffset),
    None,
];
/// Their three tests' sample rates over the run's, amplifier gains over nominal [fz, mx, my]
/// and excitation over nominal.
const RATE_FACTORS: [f64; 3] = [1.0, 0.5, 2.0];
const GAIN_FACTORS: [[f64; 3]; 3] = [[1.0, 1.0, 1.0], [0.6, 1.25, 1.25], [1.25, 0.8, 0.8]];
const EXCITATION_FACTORS: [f64; 3] = [1.0, 1.0, 0.8];

/// The lowest sample rate at which a mains line (up to 60 Hz) is one: below it a test's own
/// pickup would alias into a slow wave, and the test clips instead.
const MAINS_MIN_RATE_HZ: f64 = 150.0;

/// Uniform deviates of one session, in a fixed order.
struct Draw(Gaussian);

impl Draw {
    fn u(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.0.uniform()
    }

    fn sign(&mut self) -> f64 {
        if self.u(0.0, 1.0) < 0.5 {
            -1.0
        } else {
            1.0
        }
    }

    fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[((self.u(0.0, 1.0) * from.len() as f64) as usize).min(from.len() - 1)]
    }
}

/// The physical ranges of the shared effects' parameters (the proof's own, not the
/// diagnosis's bounds), in the catalogue's parameter order.
fn shared_effect(kind: EffectKind, d: &mut Draw) -> Effect {
    let p = match kind {
        K::ViscoelasticRelaxation => vec![d.u(2.0, 12.0), d.u(0.1, 0.3)],
        K::Hysteresis => vec![d.u(0.03, 0.08)],
        K::HighpassCoupling => vec![d.u(15.0, 80.0)],
        K::Stiffening => vec![d.u(1.2, 1.5)],
        K::Crosstalk => vec![d.sign() * d.u(6.0, 15.0)],
        K::TimeOffset => vec![d.sign() * d.u(0.05, 0.2)],
        K::BridgeNonlinearity => vec![d.sign() * d.u(0.15, 0.3)],
        K::ContactFriction => vec![d.u(0.05, 0.12)],
        // A test's own effects are drawn by `own_effect`.
        K::ThermalDrift | K::AmplifierSaturation | K::MainsInterference => {
            unreachable!("{} is drawn as a test's own effect", kind.name())
        }
    };
    kind.with_params(&p)
}

fn own_effect(kind: OwnKind, rate_hz: f64, d: &mut Draw) -> Own {
    let kind = if kind == OwnKind::Mains && rate_hz < MAINS_MIN_RATE_HZ {
        OwnKind::Clip
    } else {
        kind
    };
    match kind {
        OwnKind::Drift => Own::Drift(ThermalDrift {
            amplitude_v: d.sign() * d.u(0.03, 0.1),
            tau_s: d.u(20.0, 80.0),
        }),
        OwnKind::Mains => Own::Mains(MainsInterference {
            freq_hz: d.pick(&[50.0, 60.0]) + d.u(-0.1, 0.1),
            amplitude_v: d.u(4e-3, 12e-3),
        }),
        OwnKind::Clip => Own::Clip {
            share: d.u(0.65, 0.85),
        },
    }
}

/// What is common to a session's tests before its kind decides the rest.
struct Common {
    angle_deg: f64,
    azimuth_deg: f64,
    peaks_n: [f64; 2],
    base: BaselineParams,
    exponent: f64,
    linear_outputs: bool,
    noise: Noise,
}

impl Common {
    fn draw(d: &mut Draw) -> Self {
        let angle_deg = d.pick(&[10.0, 15.0, 20.0]);
        let azimuth_deg = d.pick(&[30.0, 60.0]);
        let peak_n = d.u(30.0, 50.0);
        let second_n = peak_n * d.u(0.5, 0.8);
        let base = truth_baseline(d.u(1.0e5, 1.5e5), &mut |a, b| d.u(a, b));
        Self {
            angle_deg,
            azimuth_deg,
            peaks_n: [peak_n, second_n],
            base,
            exponent: d.u(1.5, 2.3),
            linear_outputs: d.u(0.0, 1.0) < 0.5,
            noise: Noise {
                load_n: 0.02,
                volts: [d.u(1e-3, 3e-3); 3],
                temp_c: 0.02,
            },
        }
    }
}

/// The `j`-th session of `kind` (its id `id` in the run), drawn from `seed` for a run at
/// `rate_hz`: the same arguments give the same design.
pub fn draw(seed: u64, rate_hz: f64, id: usize, kind: LabKind, j: usize) -> SessionDesign {
    let mut d = Draw(Gaussian::new(
        seed.wrapping_mul(0xD1B5_4A32_D192_ED03)
            .wrapping_add(id as u64 * 7_368_787 + 41),
    ));
    let c = Common::draw(&mut d);
    let other = Family::Other {
        exponent: c.exponent,
        linear_outputs: c.linear_outputs,
    };
    // Our fingertip and another model's in turn (decorrelated from the designs' turn).
    let turn = if (j + j / MIXED.len()) % 2 == 0 {
        Family::Ours
    } else {
        other
    };
    let plan = match kind {
        LabKind::Mixed => mixed(j, &mut d, rate_hz),
        LabKind::NullOther => null_other(j),
        LabKind::FrictionSpeeds => friction(&mut d),
        LabKind::HysteresisOrRelaxation => hysteresis_or_relaxation(j, &mut d),
        LabKind::RatesAndGains => rates_and_gains(j, &mut d),
    };
    let family = match kind {
        LabKind::NullOther => other,
        LabKind::HysteresisOrRelaxation => [Family::Ours, other][(j / 2) % 2],
        _ => turn,
    };
    let tests = plan
        .tests
        .iter()
        .enumerate()
        .map(|(i, s)| TestDesign {
            contact_angle_deg: s.angle_deg.unwrap_or(c.angle_deg),
            azimuth_deg: s.azimuth_deg.unwrap_or(c.azimuth_deg),
            speed_mm_per_min: s.speed_mm_per_min.unwrap_or(20.0),
            sample_rate_hz: rate_hz * s.rate_factor,
            gain_factor: s.gain_factor,
            excitation_factor: s.excitation_factor,
            peaks_n: c.peaks_n,
            azimuth_shift_deg: d.u(-1.5, 1.5),
            own: s.own,
            seed: seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ ((id * 16 + i) as u64) << 24,
        })
        .collect();
    SessionDesign {
        id,
        kind,
        varies: plan.varies,
        family,
        base: c.base,
        reference_n: c.peaks_n[0],
        noise: c.noise,
        shared: plan.shared,
        tests,
    }
}

/// One test's settings where the kind sets them (`None`: the session's).
#[derive(Debug, Clone, Copy)]
struct Step {
    angle_deg: Option<f64>,
    azimuth_deg: Option<f64>,
    speed_mm_per_min: Option<f64>,
    rate_factor: f64,
    gain_factor: [f64; 3],
    excitation_factor: f64,
    own: Option<Own>,
}

impl Step {
    fn along(vary: Vary, value: f64) -> Self {
        let mut s = Step {
            angle_deg: None,
            azimuth_deg: None,
            speed_mm_per_min: None,
            rate_factor: 1.0,
            gain_factor: [1.0; 3],
            excitation_factor: 1.0,
            own: None,
        };
        match vary {
            Vary::Azimuth => s.azimuth_deg = Some(value),
            Vary::Speed => s.speed_mm_per_min = Some(value),
            Vary::Angle => s.angle_deg = Some(value),
        }
        s
    }
}

/// A kind's part of a design.
struct KindPlan {
    varies: String,
    shared: Vec<Effect>,
    tests: Vec<Step>,
}

fn along(vary: Vary, n: usize) -> Vec<Step> {
    vary.steps(n)
        .iter()
        .map(|&v| Step::along(vary, v))
        .collect()
}

fn mixed(j: usize, d: &mut Draw, rate_hz: f64) -> KindPlan {
    let (kinds, vary, own) = MIXED[j % MIXED.len()];
    let shared = kinds.iter().map(|&k| shared_effect(k, d)).collect();
    let mut tests = along(vary, 4);
    let at = d.pick(&[0usize, 1, 2, 3]);
    tests[at].own = Some(own_effect(own, rate_hz, d));
    KindPlan {
        varies: format!("{} (test {at} has its own)", vary.words()),
        shared,
        tests,
    }
}

fn null_other(j: usize) -> KindPlan {
    let vary = [Vary::Azimuth, Vary::Speed, Vary::Angle][j % 3];
    KindPlan {
        varies: vary.words().into(),
        shared: Vec::new(),
        tests: along(vary, 3 + j % 2),
    }
}

/// An inclined contact (20 or 25 deg: the friction band mu cot(theta) is a fair share of the
/// tangential load) at three speeds.
fn friction(d: &mut Draw) -> KindPlan {
    let angle_deg = d.pick(&[20.0, 25.0]);
    let shared = vec![shared_effect(K::ContactFriction, d)];
    let mut tests = along(Vary::Speed, 3);
    tests.iter_mut().for_each(|s| s.angle_deg = Some(angle_deg));
    KindPlan {
        varies: format!("rod speed at {angle_deg:.0} deg"),
        shared,
        tests,
    }
}

/// Hysteresis in even sessions, relaxation in odd ones.
fn hysteresis_or_relaxation(j: usize, d: &mut Draw) -> KindPlan {
    let kind = [K::Hysteresis, K::ViscoelasticRelaxation][j % 2];
    KindPlan {
        varies: Vary::Speed.words().into(),
        shared: vec![shared_effect(kind, d)],
        tests: along(Vary::Speed, 3),
    }
}

/// Three azimuths, each test at its own rate, gains and excitation.
fn rates_and_gains(j: usize, d: &mut Draw) -> KindPlan {
    let shared = RATES_SHARED[j % RATES_SHARED.len()]
        .map(|k| shared_effect(k, d))
        .into_iter()
        .collect();
    let mut tests = along(Vary::Azimuth, 3);
    for (i, s) in tests.iter_mut().enumerate() {
        s.rate_factor = RATE_FACTORS[i];
        s.gain_factor = GAIN_FACTORS[i];
        s.excitation_factor = EXCITATION_FACTORS[i];
    }
    KindPlan {
        varies: "azimuth, sample rate, gains, excitation".into(),
        shared,
        tests,
    }
}
