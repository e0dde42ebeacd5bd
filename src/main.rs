//! The `raytrace` binary: a thin wrapper over `rayshell::shell`.

use mimalloc::MiMalloc;

#[global_allocator]
static GLOBAL: MiMalloc = MiMalloc;

fn main() -> std::process::ExitCode {
    rayshell::shell::main()
}
