//! Per-board memory layout: cortex-m-rt's link.x does `INCLUDE memory.x`, and each board binary
//! gets its own directory on the linker search path, so the QEMU machine and the real board link
//! from one package without features. Only for the thumb target; host builds need nothing.

use std::path::PathBuf;

/// (binary, memory.x of its board)
const BINARIES: [(&str, &str); 4] = [
    ("qemu-mps2-an386", "boards/mps2-an386.x"),
    ("qemu-selftest", "boards/mps2-an386.x"),
    ("qemu-bench", "boards/mps2-an386.x"),
    ("nucleo-f411re", "boards/nucleo-f411re.x"),
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    for (bin, layout) in BINARIES {
        println!("cargo:rerun-if-changed={layout}");
        let dir = out.join(bin);
        std::fs::create_dir_all(&dir).expect("create per-binary link directory");
        std::fs::copy(layout, dir.join("memory.x")).expect("copy memory layout");
        println!("cargo:rustc-link-arg-bin={bin}=-L{}", dir.display());
    }
}
