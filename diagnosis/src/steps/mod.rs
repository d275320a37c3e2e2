//! The steps of one recording's diagnosis, each a module with one entry point (`run`, or the
//! named function of a refit) and its own types. `crate::pipeline` calls them in order and
//! holds none of them; a step reads the types below it (`crate::prepared`, `crate::outcome`,
//! `crate::fit::Setup` ...) and what the steps before it returned, never the hub.
//!
//! Like rustc's MIR passes, each step can say what it did: with `TACTILE_TRACE_STEPS=1` in the
//! environment every step prints its name and a one-line summary on standard error ([`trace`]).
use std::sync::OnceLock;

use crate::outcome::Diagnosis;
use crate::prepared::Prepared;

pub(crate) mod assemble;
pub(crate) mod certified;
pub(crate) mod described;
pub(crate) mod discovery;
pub(crate) mod effects;
pub(crate) mod freeze;
pub(crate) mod full_rate;
pub(crate) mod lines;
pub(crate) mod protocol;
pub(crate) mod residual;
pub(crate) mod swap;
pub(crate) mod undecided;
pub(crate) mod verdict;

/// One diagnosis of a recording as it is prepared, and the channels it found frozen with the
/// time each froze.
pub(crate) type Pass = (Diagnosis, Vec<(usize, f64)>);

/// One pass of the steps over a prepared recording: what the refits (`swap`, `freeze`,
/// `discovery`) run again on the recording as they leave it.
pub(crate) type Rerun<'a> = dyn Fn(&Prepared) -> Pass + 'a;

/// The environment variable that switches the steps' trace on.
pub const TRACE_VAR: &str = "TACTILE_TRACE_STEPS";

/// Print `step` and its `summary` on standard error where the trace is on ([`TRACE_VAR`] set
/// and not `0`); the summary is not worked out otherwise.
pub(crate) fn trace(step: &str, summary: impl FnOnce() -> String) {
    static ON: OnceLock<bool> = OnceLock::new();
    let on = *ON.get_or_init(|| std::env::var_os(TRACE_VAR).is_some_and(|v| v != "0"));
    if on {
        eprintln!("diagnosis step {step}: {}", summary());
    }
}
