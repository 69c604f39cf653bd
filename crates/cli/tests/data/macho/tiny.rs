//! The tiny cdylib whose macOS builds are mechfmu-cli's Mach-O test fixtures
//! (crates/cli/tests/data/macho/README.md says how they were built).
#![no_std]

#[link(name = "System")]
extern "C" {
    fn malloc(size: usize) -> *mut u8;
}

/// The sum of two numbers.
#[no_mangle]
pub extern "C" fn tiny_add(a: i32, b: i32) -> i32 {
    a.wrapping_add(b)
}

/// A block of `n` bytes from libSystem's `malloc`, each set to `fill` (null if none).
#[no_mangle]
pub extern "C" fn tiny_alloc(n: usize, fill: u8) -> *mut u8 {
    // SAFETY: malloc may be called with any size; the block, when not null, has `n` bytes.
    unsafe {
        let p = malloc(n);
        if !p.is_null() {
            for i in 0..n {
                *p.add(i) = fill;
            }
        }
        p
    }
}

/// The version of the fixture.
#[no_mangle]
pub extern "C" fn tiny_version() -> u32 {
    1
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
