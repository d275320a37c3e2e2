//! One module per subcommand: its `Args` (clap) and `run`. The dispatch from the argument tree
//! is `cli::Command::run`, so that this module does not import the tree that imports it.

pub mod chip;
pub mod common;
pub mod config;
pub mod diagnose;
pub mod fe;
pub mod import;
pub mod info;
pub mod list;
pub mod log;
pub mod observations;
pub mod paper_session;
pub mod plot;
pub mod prove;
pub mod replay;
pub mod simulate;
pub mod tare;
