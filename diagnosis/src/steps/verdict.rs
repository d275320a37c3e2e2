//! The verdict (`docs/diagnosis-format.md`): whether any effect was found and whether the
//! final model leaves noise.
use crate::misfit::RESOLUTION_FLOOR;
use crate::output::Verdict;

/// The verdict of a diagnosis that found `effects_found`, whose chosen model leaves a white
/// residual on the decimated series where `white_after`, and whose baseline misses the
/// recording by `rmse_before` (the contract's RMSE, whole recording).
pub(crate) fn run(effects_found: bool, white_after: bool, rmse_before: f64) -> Verdict {
    // Below the resolution floor the baseline's residual is arithmetic, not a mismatch.
    verdict_of(effects_found, white_after || rmse_before < RESOLUTION_FLOOR)
}

/// The verdict from whether any effect was found and whether the final residual is white.
fn verdict_of(found: bool, white_after: bool) -> Verdict {
    match (found, white_after) {
        (false, true) => Verdict::NoSignificantMismatch,
        (false, false) => Verdict::Unexplained,
        (true, true) => Verdict::Explained,
        (true, false) => Verdict::PartiallyExplained,
    }
}
