//! The `tetkit` command: parses arguments and hands over to the library.

fn main() -> std::process::ExitCode {
    tetkit::cli::main()
}
