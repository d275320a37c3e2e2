//! Board support, one module per board, shared by that board's binaries (the layout of knurling's
//! app-template: the library holds each board's start-up, exit and panic reporting; a binary is
//! a preamble line and its own logic).
//!
//! Three things cannot live in a library function: the `#[panic_handler]`, the global defmt
//! logger and the device interrupt table are one per linked program, and the QEMU and NUCLEO
//! binaries link this same library with different ones. Each board gives them as a macro that its
//! binaries invoke once at the top, [`mps2_an386_binary!`](crate::mps2_an386_binary) and
//! [`nucleo_f411re_binary!`](crate::nucleo_f411re_binary); the macro also supplies the `main`
//! that tells someone who built the binary for the host to build it from `firmware/`.

#[cfg(target_os = "none")]
pub mod mps2_an386;
pub mod nucleo_f411re;

/// The link-time singletons of a QEMU `mps2-an386` binary, and its host notice: a panic prints
/// its message over semihosting and exits QEMU with a failure code (`board::mps2_an386::on_panic`);
/// defmt output is discarded (QEMU has no RTT reader); the machine's 32 external interrupts all go
/// to the default handler (the binaries poll the UART and are paced by SysTick, a core
/// exception; cortex-m-rt's `device` feature, switched on by the STM32 PAC in the same package,
/// expects the table).
#[macro_export]
macro_rules! mps2_an386_binary {
    () => {
        #[cfg(not(target_os = "none"))]
        fn main() {
            eprintln!(
                "this is a thumbv7em-none-eabihf binary for QEMU mps2-an386: build it from firmware/"
            );
            std::process::exit(2);
        }

        #[cfg(target_os = "none")]
        #[panic_handler]
        fn panic(info: &core::panic::PanicInfo) -> ! {
            $crate::board::mps2_an386::on_panic(info)
        }

        #[cfg(target_os = "none")]
        #[defmt::global_logger]
        struct DiscardLogger;

        // SAFETY: every method does nothing, so there is no state to guard.
        #[cfg(target_os = "none")]
        unsafe impl defmt::Logger for DiscardLogger {
            fn acquire() {}
            unsafe fn flush() {}
            unsafe fn release() {}
            unsafe fn write(_bytes: &[u8]) {}
        }

        #[cfg(target_os = "none")]
        extern "C" {
            fn DefaultHandler();
        }

        #[cfg(target_os = "none")]
        #[link_section = ".vector_table.interrupts"]
        #[no_mangle]
        #[used]
        static __INTERRUPTS: [unsafe extern "C" fn(); 32] = [DefaultHandler; 32];
    };
}

/// The link-time singletons of a NUCLEO-F411RE binary, and its host notice: defmt over RTT, and
/// panic-probe, which prints the panic over defmt and traps so that probe-rs reports it. The
/// interrupt table is the STM32 PAC's.
#[macro_export]
macro_rules! nucleo_f411re_binary {
    () => {
        #[cfg(not(target_os = "none"))]
        fn main() {
            eprintln!(
                "this is a thumbv7em-none-eabihf binary for the NUCLEO-F411RE: build it from firmware/"
            );
            std::process::exit(2);
        }

        #[cfg(target_os = "none")]
        use {defmt_rtt as _, panic_probe as _};
    };
}
