//! Fuzzes the TetGen reader: the input is split at 0xff bytes into `.node`, `.ele`, `.face` and
//! `.neigh` contents. It must return a grid or an error naming the file and line, never panic or
//! allocate from an unchecked count. Seed with fixtures/tetgen files joined by 0xff.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let mut parts = data.split(|&b| b == 0xff);
    let node = parts.next().unwrap_or_default();
    let ele = parts.next();
    let face = parts.next();
    let neigh = parts.next();
    match formats::tetgen::read_parts(Path::new("fuzz.1"), node, ele, face, neigh) {
        Ok(grid) => assert!(grid.validate().is_ok(), "the reader let an invalid mesh through"),
        Err(e) => assert!(e.file.is_some(), "errors name the file: {e}"),
    }
});
