//! The integration tests: one binary (ripgrep's layout).

mod bad;
mod cli;
mod farm;
mod interrupt;
mod lang;
mod mesh;
mod pov;
mod render;
mod tidy;
mod util;
