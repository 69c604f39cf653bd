//! `mechfmu list`: the mechanisms of the workspace.

use crate::build::workspace::mechanism_crates;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    #[arg(long)]
    manifest_path: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<(), String> {
    for c in mechanism_crates(args.manifest_path.as_deref())? {
        println!("{:<20} {:<24} {}", c.model, c.package, c.manifest.display());
    }
    Ok(())
}
