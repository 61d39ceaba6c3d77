//! Fuzzes the legacy VTK reader on arbitrary bytes: it must return a grid or an error, never
//! panic, hang, or allocate from an unchecked size; whatever it reads must write (every version
//! and encoding that can hold it) and read back. Seed the corpus with fixtures/legacy/*.vtk.
#![no_main]

use formats::{Encoding, Format, LegacyVersion, WriteOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(grid) = formats::read_bytes(data, Format::Legacy) else {
        return;
    };
    for legacy_version in [LegacyVersion::V42, LegacyVersion::V51] {
        for encoding in [Encoding::Binary, Encoding::Ascii] {
            let opts = WriteOptions { encoding, legacy_version, ..Default::default() };
            let mut out = Vec::new();
            // 4.2 refuses ids beyond 32 bits and unnamed arrays are refused: both are errors.
            if formats::write_to(&mut out, Format::Legacy, &grid, &opts).is_ok() {
                let back = formats::read_bytes(&out, Format::Legacy).expect("own output reads");
                assert_eq!(back.num_points(), grid.num_points());
                assert_eq!(back.cells, grid.cells);
            }
        }
    }
});
