//! Fuzzes the Medit reader on arbitrary bytes: it must return a grid or an error, never panic,
//! hang, or allocate from an unchecked count; whatever it reads must write and read back as the
//! same grid (refs and flags included). Seed the corpus with fixtures/medit/*.mesh.
#![no_main]

use formats::{Format, WriteOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(grid) = formats::read_bytes(data, Format::Medit) else {
        return;
    };
    let mut out = Vec::new();
    // Failing here is the finding the fuzzer reports, so both are asserted, not handled.
    if let Err(e) = formats::write_to(&mut out, Format::Medit, &grid, &WriteOptions::default()) {
        panic!("what the reader gives, the writer writes: {e}");
    }
    match formats::read_bytes(&out, Format::Medit) {
        Ok(back) => assert_eq!(back, grid),
        Err(e) => panic!("own output reads: {e}"),
    }
});
