//! Scenes: cutting bodies and per-region transfer functions (seed 003), region codes and their merging.
