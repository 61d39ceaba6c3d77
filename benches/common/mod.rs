//! What the benches share: set-up failures (a generated mesh without its array, a file that
//! cannot be written) end the bench with a message and a non-zero exit, not a panic.
#![allow(dead_code)]

use std::fmt::Display;

pub trait OrExit<T> {
    /// The value, or: print `what` (and the error) on stderr and exit with status 1.
    fn or_exit(self, what: &str) -> T;
}

fn exit(what: &str, why: &dyn Display) -> ! {
    eprintln!("bench set-up failed: {what}: {why}");
    std::process::exit(1)
}

impl<T, E: Display> OrExit<T> for Result<T, E> {
    fn or_exit(self, what: &str) -> T {
        self.unwrap_or_else(|e| exit(what, &e))
    }
}

impl<T> OrExit<T> for Option<T> {
    fn or_exit(self, what: &str) -> T {
        self.unwrap_or_else(|| exit(what, &"missing"))
    }
}
