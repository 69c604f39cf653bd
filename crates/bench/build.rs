//! Compiles the benchmark's yardstick, the Oscillator's step written plainly in C
//! (`c/dopri5_oscillator.c`), as a C compiler does for a hand-written FMU.

fn main() {
    println!("cargo:rerun-if-changed=c/dopri5_oscillator.c");
    cc::Build::new()
        .file("c/dopri5_oscillator.c")
        .opt_level(3)
        .warnings(true)
        .compile("mechfmu_c_step");
}
