//! Board binary (thumbv7em-none-eabihf only).
#![cfg_attr(target_os = "none", no_std, no_main)]

/// On the host this binary only explains itself; the library is what the host uses.
#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("this is a thumbv7em-none-eabihf board binary: build it from firmware/ (the default target)");
    std::process::exit(2);
}
