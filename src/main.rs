//! The `raytrace` binary: a thin wrapper over `rayshell::shell`.

fn main() -> std::process::ExitCode {
    rayshell::shell::main()
}
