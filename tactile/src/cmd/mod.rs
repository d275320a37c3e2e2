//! One module per subcommand: its `Args` (clap) and `run`.

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
pub mod plot;
pub mod prove;
pub mod replay;
pub mod simulate;
pub mod tare;

use crate::cli::Command;

pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::List(a) => list::run(a),
        Command::Info(a) => info::run(a),
        Command::Log(a) => log::run(a),
        Command::Tare(a) => tare::run(a),
        Command::Config(a) => config::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Chip(a) => chip::run(a),
        Command::Fe(a) => fe::run(a),
        Command::Observations(a) => observations::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Diagnose(a) => diagnose::run(a),
        Command::Prove(a) => prove::run(a),
        Command::Import(a) => import::run(a),
    }
}
