//! One plain sentence per effect: what physics the baseline left out and how it shows.

use sim::effects::EffectKind;

use super::data::Data;
use super::output::Numbers;

/// The sentence for `kind` with its fitted `params`; `bic_gain` and `heldout_gain` (held-out
/// chi-square without the effect over with it) quantify the evidence where known.
pub fn sentence(
    kind: EffectKind,
    params: &Numbers,
    bic_gain: f64,
    heldout_gain: f64,
    _data: &Data,
) -> String {
    let p = |k: &str| params.get(k).unwrap_or(f64::NAN);
    use EffectKind::*;
    let what = match kind {
        ViscoelasticRelaxation => format!(
            "The gel is viscoelastic: {:.0} % of its instantaneous response relaxes with tau = {:.2} s, so the force decays under the hold and the outputs creep back after the fast release, which a quasi-static model cannot show.",
            100.0 * p("fraction"), p("tau_s")),
        Hysteresis => format!(
            "The gel loses energy independently of rate: the unloading path runs {:.1} % of full scale below the loading path.",
            100.0 * p("width")),
        HighpassCoupling => format!(
            "The offset cut acts as AC coupling with tau = {:.1} s: outputs sag under constant load and undershoot their initial value after release before creeping back.",
            p("tau_s")),
        ThermalDrift => format!(
            "The bridge offsets drift with warm-up by {:.4} V with tau = {:.0} s, visible at rest and unrelated to the load.",
            p("amplitude_V"), p("tau_s")),
        Stiffening => format!(
            "The load path stiffens: the outputs grow as the {:.2} power of the elastic response, the same on loading and unloading.",
            p("exponent")),
        Crosstalk => format!(
            "The chip is rotated {:.1} deg against its nominal axes: each moment channel carries a load-proportional share of the other.",
            p("angle_deg")),
        AmplifierSaturation => format!(
            "An amplifier clips at +-{:.3} V: the outputs have flat tops at that voltage.",
            p("limit_V")),
        TimeOffset => format!(
            "The sensor stream lags the load reference by {:.1} ms: the residual follows the signals' derivative, largest during the fast release.",
            1e3 * p("lag_s")),
        MainsInterference => format!(
            "Mains pickup at {:.2} Hz with {:.4} V amplitude (and its third harmonic) shows as a narrow spectral line in the outputs.",
            p("freq_hz"), p("amplitude_V")),
        BridgeNonlinearity => format!(
            "The bridges respond to the square of the stress: a quadratic term of {:.1} % of full scale at full load.",
            100.0 * p("quadratic")),
        ContactFriction => format!(
            "Coulomb friction (mu = {:.2}) at the inclined contact makes the moments stick at the reversal and lag the load while Fz stays smooth.",
            p("mu")),
    };
    let what = match params.get("tau2_s") {
        Some(tau2) => format!("{what} A second relaxation term of {:.0} % with tau = {:.2} s shows that the relaxation spans more than one time scale.", 100.0 * p("fraction2"), tau2),
        None => what,
    };
    if bic_gain.is_finite() && heldout_gain.is_finite() {
        format!(
            "{what} (Against the model without it: BIC lower by {:.0}, held-out misfit {:.1} times smaller.)",
            bic_gain, heldout_gain
        )
    } else {
        what
    }
}
