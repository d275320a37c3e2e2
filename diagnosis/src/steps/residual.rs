//! Where the calibrated baseline misses, in time and channel, and whether the chosen model
//! (with its described terms) leaves noise: both on the decimated series.
use baseline::Outputs;

use crate::candidate::Candidate;
use crate::data::{Data, CHANNELS};
use crate::fit::Setup;
use crate::localise::{self, ChannelLocalisation, Mismatch};
use crate::misfit::{diff, weighted, white, LB_LAGS, LB_P};
use crate::regimes::Segment;
use crate::stats;
use crate::terms::Described;

/// The baseline's residual localised and the chosen model's tested for whiteness, the terms
/// `described` beyond the catalogue added to the chosen model.
pub(crate) fn run(
    setup: &Setup,
    (base, chosen): (&Candidate, &Candidate),
    segments: &[Segment],
    described: &Described,
) -> Localised {
    let mut local = localise_residual(setup, base, chosen, segments);
    if !described.found.terms.is_empty() {
        local.chosen = described.add_decimated(&local.chosen);
        local.white_after = white(setup, &local.chosen);
    }
    local
}

/// Where the baseline misses, on the decimated series.
pub(crate) struct Localised {
    pub mismatches: Vec<Mismatch>,
    pub channels: Vec<ChannelLocalisation>,
    /// The baseline's and the chosen model's channels on the decimated series.
    pub baseline: [Vec<f64>; 4],
    pub chosen: [Vec<f64>; 4],
    /// Whether the chosen model leaves a white residual on every compared channel.
    pub white_after: bool,
}

/// Localise the calibrated baseline's residual in time and channel, and test the chosen
/// model's residual for whiteness.
fn localise_residual(
    setup: &Setup,
    base: &Candidate,
    chosen: &Candidate,
    segments: &[Segment],
) -> Localised {
    let data = setup.data;
    // Both models were evaluated on the decimated series when they were scored.
    let base_dec = &base.outputs;
    let residual: [Vec<f64>; 4] =
        std::array::from_fn(|c| diff(&data.fit.y[c], base_dec.channel(c)));
    let mismatches = localise::mismatches(
        &data.fit.t_s,
        segments,
        &residual,
        &data.range,
        &setup.used,
        0.02,
    );
    let channels = channel_localisation(data, base_dec, &residual);
    let chosen_dec = &chosen.outputs;
    // Whether the chosen model leaves noise ([`white`]).
    let white_after = white(
        setup,
        &std::array::from_fn(|c| chosen_dec.channel(c).to_vec()),
    );
    Localised {
        mismatches,
        channels,
        baseline: std::array::from_fn(|c| base_dec.channel(c).to_vec()),
        chosen: std::array::from_fn(|c| chosen_dec.channel(c).to_vec()),
        white_after,
    }
}

fn channel_localisation(
    data: &Data,
    base: &Outputs,
    residual: &[Vec<f64>; 4],
) -> Vec<ChannelLocalisation> {
    let d = &data.fit;
    let load = &d.y[0];
    let load2: Vec<f64> = load.iter().map(|v| v * v).collect();
    let dload: Vec<f64> = (0..d.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(d.len() - 1));
            if d.t_s[b] > d.t_s[a] {
                (load[b] - load[a]) / (d.t_s[b] - d.t_s[a])
            } else {
                0.0
            }
        })
        .collect();
    (0..4)
        .filter(|&c| data.compared(c))
        .map(|c| {
            let r = &residual[c];
            let (q, p) = stats::ljung_box(&weighted(data, c, r), LB_LAGS);
            ChannelLocalisation {
                channel: CHANNELS[c],
                ljung_box_q: q,
                ljung_box_p: p,
                white: p > LB_P,
                corr_load: stats::pearson(r, load),
                corr_load_squared: stats::pearson(r, &load2),
                corr_dload_dt: stats::pearson(r, &dload),
                corr_temperature: d.temp_c.as_ref().map(|t| stats::pearson(r, t)),
                corr_other_residuals: (0..4)
                    .filter(|&o| o != c)
                    .map(|o| (CHANNELS[o].to_string(), stats::pearson(r, &residual[o])))
                    .collect(),
                lag_estimate_s: localise::lag_estimate(&d.t_s, base.channel(c), r),
            }
        })
        .collect()
}
