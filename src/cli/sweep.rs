//! `mechfmu sweep` (not yet implemented).

#[derive(clap::Args)]
pub struct Args {
    /// The FMU to sweep.
    fmu: std::path::PathBuf,
}

pub fn run(_args: Args) -> Result<(), String> {
    Err("`mechfmu sweep` is not implemented yet".into())
}
