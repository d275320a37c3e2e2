//! The full-rate evaluation: the baseline and the chosen model on every recorded sample, the
//! lines their residuals hold (`steps::lines`), and the contract's RMSEs.
use baseline::{Drive, Outputs};

use crate::candidate::Candidate;
use crate::data::{Data, CHANNELS};
use crate::fit::Setup;
use crate::mains::Line;
use crate::misfit::{channel_rmse, contract_rmse};
use crate::output::{Fit, Heldout, Numbers};
use crate::steps::lines::{
    add_line, fast_lines, line_in_residual, mains_helps, LOAD_CELL, OUTPUTS,
};
use crate::stretches::Stretches;
use crate::terms;

/// The baseline `base` at the full rate (`drive`) beside `chosen_full`, evaluated with the
/// lines their residuals hold ([`full_rate`]).
pub(crate) fn run(
    setup: &Setup,
    (base, drive): (&Candidate, &Drive),
    chosen_full: &Outputs,
    stretches: &Stretches,
    mains_allowed: bool,
) -> FullRate {
    let base_full = base.outputs(drive);
    full_rate(setup, &base_full, chosen_full, stretches, mains_allowed)
}

/// The full-rate evaluation: the contract's RMSEs and the mains line.
pub(crate) struct FullRate {
    /// The line in the baseline's residual (prominent or not).
    pub baseline_line: Option<Line>,
    /// The mains line the final model includes, if it passed both tests.
    pub mains: Option<Line>,
    /// The mains line on the load cell, if it passed both tests.
    pub load_mains: Option<Line>,
    /// Lines faster than the decimated series shows, each on its channel.
    pub fast: Vec<terms::FastLine>,
    /// RMSE of the baseline per compared channel.
    pub baseline_rmse: Numbers,
    /// RMSEs before and after, whole recording and held-out stretch.
    pub fit: Fit,
    /// The final model at the full rate, the lines included.
    pub model: Outputs,
    /// The fitting and the held-out stretch at the full rate.
    fitting: Vec<bool>,
    heldout: Vec<bool>,
}

impl FullRate {
    /// The fitting and the held-out stretch at the full rate.
    pub(crate) fn masks(&self) -> (&[bool], &[bool]) {
        (&self.fitting, &self.heldout)
    }

    /// The fit's `rmse_after` numbers of `model` instead (an effect left out of the answer).
    pub(crate) fn refit(&mut self, data: &Data, model: &Outputs) {
        self.fit.rmse_after = contract_rmse(data, model, &vec![true; data.full.len()]);
        self.fit.heldout.rmse_after = contract_rmse(data, model, &self.heldout);
        self.model = model.clone();
    }
}

/// The baseline and the chosen model at the full rate; the mains line searched in the chosen
/// model's residual joins it if it helps on both stretches.
fn full_rate(
    setup: &Setup,
    base_full: &Outputs,
    chosen_full: &Outputs,
    stretches: &Stretches,
    mains_allowed: bool,
) -> FullRate {
    let data = setup.data;
    let heldout = stretches.heldout;
    let full_heldout = stretches.mask(&data.full.t_s);
    let full_fit: Vec<bool> = full_heldout.iter().map(|h| !h).collect();
    // An output the baseline does not model (a user's simulation without moments) leaves the
    // recorded output itself as its residual: no line is looked for there.
    let outputs: Vec<usize> = OUTPUTS.into_iter().filter(|&c| data.modelled(c)).collect();
    let baseline_line = line_in_residual(data, base_full, &full_fit, &outputs);
    let mains = line_in_residual(data, chosen_full, &full_fit, &outputs)
        .filter(|_| mains_allowed)
        .filter(|l| mains_helps(data, chosen_full, l, (&full_fit, &full_heldout), &outputs));
    let with_mains = add_line(data, chosen_full, mains.as_ref(), &outputs);
    // The load cell picks up the mains as well: its line is looked for on its own (it need
    // not share the outputs' phase or even their presence: a test of the material alone has
    // only the rate's precondition, the mains' own).
    let load_mains = line_in_residual(data, &with_mains, &full_fit, &LOAD_CELL)
        .filter(|_| crate::preconditions::mains_visible(data.rate_hz) && setup.used[0])
        .filter(|l| mains_helps(data, &with_mains, l, (&full_fit, &full_heldout), &LOAD_CELL));
    let with_load_mains = add_line(data, &with_mains, load_mains.as_ref(), &LOAD_CELL);
    let fast = fast_lines(setup, &with_load_mains, (&full_fit, &full_heldout));
    let final_full = fast.iter().fold(with_load_mains, |o, f| {
        add_line(data, &o, Some(&f.line), &[f.channel])
    });
    let all_rows = vec![true; data.full.len()];
    let rmse = |o: &Outputs, mask: &[bool]| contract_rmse(data, o, mask);
    let baseline_rmse = Numbers(
        (0..4)
            .filter(|&c| setup.used[c])
            .map(|c| {
                // In the channel's unit (the contract's `fit.rmse_*` is the one per range).
                let r = channel_rmse(data, base_full, c, &all_rows) * data.range[c].max(1e-300);
                (CHANNELS[c].to_string(), r)
            })
            .collect(),
    );
    let fit = Fit {
        rmse_before: rmse(base_full, &all_rows),
        rmse_after: rmse(&final_full, &all_rows),
        heldout: Heldout {
            t_start_s: heldout.0,
            t_end_s: heldout.1,
            rmse_before: rmse(base_full, &full_heldout),
            rmse_after: rmse(&final_full, &full_heldout),
        },
    };
    FullRate {
        baseline_line,
        mains,
        load_mains,
        fast,
        baseline_rmse,
        fit,
        model: final_full,
        fitting: full_fit,
        heldout: full_heldout,
    }
}
