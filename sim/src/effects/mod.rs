//! The catalogue of physics the baseline leaves out (`docs/diagnosis-format.md`), as
//! switchable, parameterised signal-level operators, one module per effect and named exactly as
//! the catalogue. All are off unless listed in an [`EffectSet`]. The simulator applies them to make
//! recordings with effects; the diagnosis fits the very same operators.
//!
//! Where each acts: the gel's effects (viscoelastic relaxation, hysteresis) on the load and the
//! chip loads; the load path (stiffening, contact friction, crosstalk) on the chip loads; the
//! electronics (bridge nonlinearity, time offset, AC coupling, drift, mains) on the output
//! volts; saturation last, after offsets and noise, at the amplifier rail.

pub mod amplifier_saturation;
pub mod bridge_nonlinearity;
pub mod contact_friction;
pub mod crosstalk;
mod first_order;
pub mod highpass_coupling;
pub mod hysteresis;
pub mod mains_interference;
pub mod stiffening;
pub mod thermal_drift;
pub mod time_offset;
pub mod viscoelastic_relaxation;

pub use amplifier_saturation::AmplifierSaturation;
pub use bridge_nonlinearity::BridgeNonlinearity;
pub use contact_friction::ContactFriction;
pub use crosstalk::Crosstalk;
pub use highpass_coupling::HighpassCoupling;
pub use hysteresis::Hysteresis;
pub use mains_interference::MainsInterference;
pub use stiffening::Stiffening;
pub use thermal_drift::{ThermalDrift, ThermalReference};
pub use time_offset::TimeOffset;
pub use viscoelastic_relaxation::ViscoelasticRelaxation;

/// Where in the measuring chain a piece of physics acts (`docs/diagnosis-format.md`, "Where the
/// physics acts").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    /// Between the rod's travel and the load: the gel, the contact, the rig.
    Material,
    /// Between the load and the outputs: the load's share to the chip, the chip, the bridges.
    Transducer,
    /// After the transduction, on any measured channel (the load cell's included).
    Electronics,
}

impl Stage {
    /// The contract's word for the stage.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Material => "material",
            Stage::Transducer => "transducer",
            Stage::Electronics => "electronics",
        }
    }
}

/// Which catalogue entry, without parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    ViscoelasticRelaxation,
    Hysteresis,
    HighpassCoupling,
    ThermalDrift,
    Stiffening,
    Crosstalk,
    AmplifierSaturation,
    TimeOffset,
    MainsInterference,
    BridgeNonlinearity,
    ContactFriction,
}

impl EffectKind {
    /// Every catalogue entry, in catalogue order.
    pub const ALL: [EffectKind; 11] = [
        EffectKind::ViscoelasticRelaxation,
        EffectKind::Hysteresis,
        EffectKind::HighpassCoupling,
        EffectKind::ThermalDrift,
        EffectKind::Stiffening,
        EffectKind::Crosstalk,
        EffectKind::AmplifierSaturation,
        EffectKind::TimeOffset,
        EffectKind::MainsInterference,
        EffectKind::BridgeNonlinearity,
        EffectKind::ContactFriction,
    ];

    /// The catalogue name.
    pub fn name(self) -> &'static str {
        use EffectKind::*;
        match self {
            ViscoelasticRelaxation => "viscoelastic_relaxation",
            Hysteresis => "hysteresis",
            HighpassCoupling => "highpass_coupling",
            ThermalDrift => "thermal_drift",
            Stiffening => "stiffening",
            Crosstalk => "crosstalk",
            AmplifierSaturation => "amplifier_saturation",
            TimeOffset => "time_offset",
            MainsInterference => "mains_interference",
            BridgeNonlinearity => "bridge_nonlinearity",
            ContactFriction => "contact_friction",
        }
    }

    /// Every catalogue entry with its parameters, `name:param,...` in catalogue order, for
    /// help texts and for the error that meets an unknown name.
    pub fn catalogue() -> String {
        Self::ALL
            .map(|k| format!("{}:{}", k.name(), k.param_names().join(",")))
            .join(" ")
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Parameter names, primary first, as in the catalogue.
    pub fn param_names(self) -> &'static [&'static str] {
        use EffectKind::*;
        match self {
            ViscoelasticRelaxation => &["tau_s", "fraction"],
            Hysteresis => &["width"],
            HighpassCoupling => &["tau_s"],
            ThermalDrift => &["amplitude_V", "tau_s"],
            Stiffening => &["exponent"],
            Crosstalk => &["angle_deg"],
            AmplifierSaturation => &["limit_V"],
            TimeOffset => &["lag_s"],
            MainsInterference => &["freq_hz", "amplitude_V"],
            BridgeNonlinearity => &["quadratic"],
            ContactFriction => &["mu"],
        }
    }

    /// The recording channels the effect changes.
    pub fn channels(self) -> &'static [&'static str] {
        use EffectKind::*;
        match self {
            ViscoelasticRelaxation | Hysteresis => &["load_N", "fz_V", "mx_V", "my_V"],
            Crosstalk | ContactFriction => &["mx_V", "my_V"],
            _ => &["fz_V", "mx_V", "my_V"],
        }
    }

    /// Where the forward model acts in the emulator's chain ([`EffectSet`]): on the load and the
    /// chip loads alike (the gel), on the chip loads only or on the bridges' response (the
    /// transducer), or on the output volts (the electronics). `thermal_drift` moves the outputs'
    /// offset with temperature, an additive term after the bridges; `bridge_nonlinearity` is the
    /// bridges' own response to stress, although the emulator applies it to the volts.
    pub fn stage(self) -> Stage {
        use EffectKind::*;
        match self {
            ViscoelasticRelaxation | Hysteresis => Stage::Material,
            Stiffening | Crosstalk | ContactFriction | BridgeNonlinearity => Stage::Transducer,
            HighpassCoupling | ThermalDrift | AmplifierSaturation | TimeOffset
            | MainsInterference => Stage::Electronics,
        }
    }

    /// The effect with parameters `p` in `param_names` order.
    pub fn with_params(self, p: &[f64]) -> Effect {
        assert_eq!(
            p.len(),
            self.param_names().len(),
            "{} takes {} parameters",
            self.name(),
            self.param_names().len()
        );
        use EffectKind as K;
        match self {
            K::ViscoelasticRelaxation => Effect::ViscoelasticRelaxation(ViscoelasticRelaxation {
                tau_s: p[0],
                fraction: p[1],
            }),
            K::Hysteresis => Effect::Hysteresis(Hysteresis { width: p[0] }),
            K::HighpassCoupling => Effect::HighpassCoupling(HighpassCoupling { tau_s: p[0] }),
            K::ThermalDrift => Effect::ThermalDrift(ThermalDrift {
                amplitude_v: p[0],
                tau_s: p[1],
            }),
            K::Stiffening => Effect::Stiffening(Stiffening { exponent: p[0] }),
            K::Crosstalk => Effect::Crosstalk(Crosstalk { angle_deg: p[0] }),
            K::AmplifierSaturation => {
                Effect::AmplifierSaturation(AmplifierSaturation { limit_v: p[0] })
            }
            K::TimeOffset => Effect::TimeOffset(TimeOffset { lag_s: p[0] }),
            K::MainsInterference => Effect::MainsInterference(MainsInterference {
                freq_hz: p[0],
                amplitude_v: p[1],
            }),
            K::BridgeNonlinearity => {
                Effect::BridgeNonlinearity(BridgeNonlinearity { quadratic: p[0] })
            }
            K::ContactFriction => Effect::ContactFriction(ContactFriction { mu: p[0] }),
        }
    }
}

/// One catalogue effect with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Effect {
    ViscoelasticRelaxation(ViscoelasticRelaxation),
    Hysteresis(Hysteresis),
    HighpassCoupling(HighpassCoupling),
    ThermalDrift(ThermalDrift),
    Stiffening(Stiffening),
    Crosstalk(Crosstalk),
    AmplifierSaturation(AmplifierSaturation),
    TimeOffset(TimeOffset),
    MainsInterference(MainsInterference),
    BridgeNonlinearity(BridgeNonlinearity),
    ContactFriction(ContactFriction),
}

impl Effect {
    pub fn kind(&self) -> EffectKind {
        use EffectKind as K;
        match self {
            Effect::ViscoelasticRelaxation(_) => K::ViscoelasticRelaxation,
            Effect::Hysteresis(_) => K::Hysteresis,
            Effect::HighpassCoupling(_) => K::HighpassCoupling,
            Effect::ThermalDrift(_) => K::ThermalDrift,
            Effect::Stiffening(_) => K::Stiffening,
            Effect::Crosstalk(_) => K::Crosstalk,
            Effect::AmplifierSaturation(_) => K::AmplifierSaturation,
            Effect::TimeOffset(_) => K::TimeOffset,
            Effect::MainsInterference(_) => K::MainsInterference,
            Effect::BridgeNonlinearity(_) => K::BridgeNonlinearity,
            Effect::ContactFriction(_) => K::ContactFriction,
        }
    }

    /// Parameters in `param_names` order.
    pub fn params(&self) -> Vec<f64> {
        match *self {
            Effect::ViscoelasticRelaxation(e) => vec![e.tau_s, e.fraction],
            Effect::Hysteresis(e) => vec![e.width],
            Effect::HighpassCoupling(e) => vec![e.tau_s],
            Effect::ThermalDrift(e) => vec![e.amplitude_v, e.tau_s],
            Effect::Stiffening(e) => vec![e.exponent],
            Effect::Crosstalk(e) => vec![e.angle_deg],
            Effect::AmplifierSaturation(e) => vec![e.limit_v],
            Effect::TimeOffset(e) => vec![e.lag_s],
            Effect::MainsInterference(e) => vec![e.freq_hz, e.amplitude_v],
            Effect::BridgeNonlinearity(e) => vec![e.quadratic],
            Effect::ContactFriction(e) => vec![e.mu],
        }
    }

    /// Parse `name:key=value,key=value` (every parameter given), as on the command line.
    pub fn from_spec(spec: &str) -> Result<Effect, String> {
        let (name, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let kind = EffectKind::from_name(name.trim()).ok_or_else(|| {
            format!(
                "unknown effect `{name}` (the catalogue's: {})",
                EffectKind::catalogue()
            )
        })?;
        let mut values = vec![f64::NAN; kind.param_names().len()];
        for pair in rest.split(',').filter(|s| !s.trim().is_empty()) {
            let (k, v) = pair
                .split_once('=')
                .ok_or_else(|| format!("`{pair}`: expected key=value"))?;
            let i = kind
                .param_names()
                .iter()
                .position(|n| *n == k.trim())
                .ok_or_else(|| {
                    format!(
                        "{name} has no parameter `{k}` (has {:?})",
                        kind.param_names()
                    )
                })?;
            values[i] = v
                .trim()
                .parse::<f64>()
                .map_err(|_| format!("`{v}` is not a number"))?;
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "{name}: parameter `{}` missing",
                kind.param_names()[i]
            ));
        }
        Ok(kind.with_params(&values))
    }
}

/// The effects switched on; the order of application is fixed by physics, not by the list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EffectSet {
    pub effects: Vec<Effect>,
    /// With a measured temperature (see [`EffectSet::apply_electrical_at`]), `thermal_drift` is
    /// regressed on it against this reference instead of following the exponential warm-up.
    pub thermal_reference: Option<ThermalReference>,
}

impl EffectSet {
    pub fn new(effects: Vec<Effect>) -> Self {
        Self {
            effects,
            thermal_reference: None,
        }
    }

    fn each(&self, kind: EffectKind) -> impl Iterator<Item = &Effect> {
        self.effects.iter().filter(move |e| e.kind() == kind)
    }

    /// The gel and load path, on the load (N) and the chip loads [Fz, Mx, My].
    pub fn apply_mechanical(
        &self,
        t_s: &[f64],
        load: &mut [f64],
        chip: &mut [Vec<f64>; 3],
        contact_angle_deg: f64,
    ) {
        for e in self.each(EffectKind::ViscoelasticRelaxation) {
            if let Effect::ViscoelasticRelaxation(v) = e {
                v.apply(t_s, load);
                // The rod cannot pull: once the gel lags behind a fast return the contact opens.
                load.iter_mut().for_each(|f| *f = f.max(0.0));
                chip.iter_mut().for_each(|c| v.apply(t_s, c));
            }
        }
        for e in self.each(EffectKind::Hysteresis) {
            if let Effect::Hysteresis(h) = e {
                h.apply(load);
                chip.iter_mut().for_each(|c| h.apply(c));
            }
        }
        for e in self.each(EffectKind::Stiffening) {
            if let Effect::Stiffening(s) = e {
                chip.iter_mut().for_each(|c| s.apply(c));
            }
        }
        let [_, mx, my] = chip;
        for e in self.each(EffectKind::ContactFriction) {
            if let Effect::ContactFriction(f) = e {
                f.apply(contact_angle_deg, mx);
                f.apply(contact_angle_deg, my);
            }
        }
        for e in self.each(EffectKind::Crosstalk) {
            if let Effect::Crosstalk(c) = e {
                c.apply(mx, my);
            }
        }
    }

    /// The electronics, on the output volts [fz, mx, my], ahead of offsets and noise.
    pub fn apply_electrical(&self, t_s: &[f64], volts: &mut [Vec<f64>; 3]) {
        self.apply_electrical_at(t_s, None, volts);
    }

    /// As [`EffectSet::apply_electrical`], with the temperature measured at each sample, if any.
    pub fn apply_electrical_at(
        &self,
        t_s: &[f64],
        temp_c: Option<&[f64]>,
        volts: &mut [Vec<f64>; 3],
    ) {
        for e in &self.effects {
            if let Effect::BridgeNonlinearity(b) = e {
                volts.iter_mut().for_each(|v| b.apply(v));
            }
        }
        for e in &self.effects {
            if let Effect::TimeOffset(d) = e {
                volts.iter_mut().for_each(|v| d.apply(t_s, v));
            }
        }
        for e in &self.effects {
            match e {
                Effect::HighpassCoupling(h) => volts.iter_mut().for_each(|v| h.apply(t_s, v)),
                Effect::ThermalDrift(d) => match (self.thermal_reference, temp_c) {
                    (Some(r), Some(temp)) => {
                        volts.iter_mut().for_each(|v| d.apply_regressed(temp, r, v))
                    }
                    _ => volts.iter_mut().for_each(|v| d.apply(t_s, v)),
                },
                Effect::MainsInterference(m) => volts.iter_mut().for_each(|v| m.apply(t_s, v)),
                _ => {}
            }
        }
    }

    /// The amplifier rails, last (after offsets and noise).
    pub fn apply_saturation(&self, volts: &mut [Vec<f64>; 3]) {
        for e in self.each(EffectKind::AmplifierSaturation) {
            if let Effect::AmplifierSaturation(s) = e {
                volts.iter_mut().for_each(|v| s.apply(v));
            }
        }
    }
}

/// Largest magnitude in `x` (0 for an empty slice).
pub fn peak_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// x(t) by linear interpolation on the non-decreasing time base `t_s`, held at both ends.
pub fn interpolate(t_s: &[f64], x: &[f64], t: f64) -> f64 {
    let n = t_s.len();
    if n == 0 {
        return 0.0;
    }
    if t <= t_s[0] {
        return x[0];
    }
    if t >= t_s[n - 1] {
        return x[n - 1];
    }
    let i = t_s.partition_point(|&s| s <= t);
    let (t0, t1) = (t_s[i - 1], t_s[i]);
    if t1 <= t0 {
        return x[i];
    }
    x[i - 1] + (x[i] - x[i - 1]) * (t - t0) / (t1 - t0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_round_trips_through_its_spec() {
        for kind in EffectKind::ALL {
            let p: Vec<f64> = (0..kind.param_names().len())
                .map(|i| 0.5 + i as f64)
                .collect();
            let e = kind.with_params(&p);
            let spec = format!(
                "{}:{}",
                kind.name(),
                kind.param_names()
                    .iter()
                    .zip(&p)
                    .map(|(n, v)| format!("{n}={v}"))
                    .collect::<Vec<_>>()
                    .join(",")
            );
            assert_eq!(Effect::from_spec(&spec).unwrap(), e);
            assert_eq!(e.params(), p);
        }
        assert!(Effect::from_spec("hysteresis").is_err());
        let unknown = Effect::from_spec("warp_drive:x=1").unwrap_err();
        // An unknown name is answered with every valid one.
        for k in EffectKind::ALL {
            assert!(unknown.contains(k.name()), "{unknown}");
        }
        assert!(unknown.starts_with("unknown effect `warp_drive` (the catalogue's: viscoelastic_relaxation:tau_s,fraction hysteresis:width"), "{unknown}");
    }

    #[test]
    fn empty_chain_is_identity() {
        let t = vec![0.0, 1.0, 2.0];
        let mut load = vec![0.0, 1.0, 0.5];
        let mut chip = [
            vec![0.0, 1.0, 0.5],
            vec![0.0, -1.0, -0.5],
            vec![0.0, 2.0, 1.0],
        ];
        let (l0, c0) = (load.clone(), chip.clone());
        let chain = EffectSet::default();
        chain.apply_mechanical(&t, &mut load, &mut chip, 20.0);
        chain.apply_electrical(&t, &mut chip);
        chain.apply_saturation(&mut chip);
        assert_eq!((load, chip), (l0, c0));
    }
}
