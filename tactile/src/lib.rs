//! The `tactile` command as a library, so its tests can call a subcommand directly: the
//! argument tree and error reporting ([`cli`]), one module per subcommand ([`cmd`]), the live
//! view and the plots. Each subcommand is thin: the work is in the driver (`host`) and the
//! model, recording and diagnosis libraries, none of which imports this crate.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod cli;
pub mod cmd;
mod live;
mod plot;
