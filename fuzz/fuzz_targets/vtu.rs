//! Fuzzes the VTU reader on arbitrary bytes: it must return a grid or an error, never panic,
//! hang, or allocate from an unchecked size. Seed the corpus with fixtures/vtk/*.vtu.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(grid) = formats::read_bytes(data, formats::Format::Vtu) {
        // Whatever reads must write and read back.
        let mut out = Vec::new();
        if formats::write_to(&mut out, formats::Format::Vtu, &grid, &Default::default()).is_ok() {
            assert!(formats::read_bytes(&out, formats::Format::Vtu).is_ok());
        }
    }
});
