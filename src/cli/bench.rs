//! `mechfmu bench` (not yet implemented).

#[derive(clap::Args)]
pub struct Args {
    /// Model identifiers (default: every mechanism).
    names: Vec<String>,
}

pub fn run(_args: Args) -> Result<(), String> {
    Err("`mechfmu bench` is not implemented yet".into())
}
