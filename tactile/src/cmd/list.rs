//! `tactile list`: serial ports and their USB serial numbers.

/// List the serial ports this machine has; USB adapters with vendor, product and serial
/// number (use `--port serial:<number>` to open one regardless of its ttyACM/ttyUSB name).
#[derive(Debug, clap::Args)]
pub struct Args {}

pub fn run(_args: Args) -> anyhow::Result<()> {
    let ports = host::device::list_ports();
    if ports.is_empty() {
        eprintln!("no serial ports found");
    }
    for p in ports {
        println!(
            "{}\t{}\t{}",
            p.path,
            p.serial_number.as_deref().unwrap_or("-"),
            p.description
        );
    }
    Ok(())
}
