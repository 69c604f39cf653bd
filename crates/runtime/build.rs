//! Makes every binary linked with the runtime on GNU/Linux (an FMU's shared library above
//! all) carry libgcc's unwinder instead of loading `libgcc_s.so.1`, so that an FMU needs
//! glibc only. Rust's standard library unwinds (panics caught at the FMI boundary) through
//! libgcc, which it links as `-lgcc_s`; a linker script of that name, found first on the
//! library search path this script adds (cargo passes it on to every crate that depends on
//! the runtime), pulls in `libgcc_eh.a`, libgcc's static unwinder, as `gcc -static-libgcc`
//! does. Unwinding never crosses the library's boundary (every exported function catches
//! its panics), so the library's own unwinder is the only one that sees its frames.

use std::path::PathBuf;

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    let var = |name: &str| std::env::var(name).unwrap_or_default();
    if var("CARGO_CFG_TARGET_OS") != "linux" || var("CARGO_CFG_TARGET_ENV") != "gnu" {
        return;
    }
    let dir = PathBuf::from(var("OUT_DIR")).join("static-unwinder");
    let script = dir.join("libgcc_s.so");
    std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(&script, "INPUT(-lgcc_eh)\n"))
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", script.display()));
    println!("cargo::rustc-link-search=native={}", dir.display());
}
