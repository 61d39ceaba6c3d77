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
    formats::write_to(&mut out, Format::Medit, &grid, &WriteOptions::default())
        .expect("what the reader gives, the writer writes");
    let back = formats::read_bytes(&out, Format::Medit).expect("own output reads");
    assert_eq!(back, grid);
});
