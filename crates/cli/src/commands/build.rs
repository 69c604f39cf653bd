//! `mechfmu build`: compile the named mechanism crates (or all of them) for each platform
//! and write their FMI 2.0 and FMI 3.0 FMUs (and, with `--cross-check DIR`, the same as an
//! FMI cross-check tree).

use crate::build::{Flavor, Platforms};
use crate::package::write_fmus;
use mechfmu_host::platform::Platform;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Model identifiers, e.g. Oscillator Crane (default: every mechanism).
    names: Vec<String>,
    /// Where to write the .fmu files.
    #[arg(long, default_value = "fmus")]
    out: PathBuf,
    /// The Cargo.toml of the workspace or crate holding the mechanisms.
    #[arg(long)]
    manifest_path: Option<PathBuf>,
    /// The platforms to carry binaries for, comma-separated: x86_64-linux (linux64),
    /// x86_64-windows (win64), aarch64-linux, x86_64-darwin (darwin64), aarch64-darwin,
    /// or all; a platform whose toolchain is
    /// missing is then an error. Default: every platform this machine can build for
    /// (those it cannot are named, with how to install their toolchains).
    #[arg(long, value_name = "PLATFORMS")]
    platform: Option<String>,
    /// Also lay the FMUs out as an FMI cross-check tree under DIR:
    /// DIR/fmus/<2.0|3.0>/<cs|me>/<platform>/mechfmu/<version>/<Model>/, each folder with the
    /// .fmu, its reference files (<Model>_ref.csv, _in.csv, _ref.opt) and a README.md.
    #[arg(long, value_name = "DIR")]
    cross_check: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<(), String> {
    let chosen = args.platform.as_deref().map(parse_list).transpose()?;
    write_fmus(
        &args.names,
        &args.out,
        args.manifest_path.as_deref(),
        Flavor::Shipped,
        chosen.map_or(Platforms::Available, Platforms::Chosen),
        args.cross_check.as_deref(),
    )
}

/// The platforms `--platform` names (comma-separated tuples or FMI 2.0 names, or `all`).
fn parse_list(text: &str) -> Result<Vec<Platform>, String> {
    if text == "all" {
        return Ok(Platform::ALL.to_vec());
    }
    let mut platforms = Vec::new();
    for name in text.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let platform = Platform::parse(name).ok_or_else(|| {
            let known: Vec<&str> = Platform::ALL.iter().map(|p| p.tuple()).collect();
            format!(
                "unknown platform `{name}` (known: {}, or all; FMI 2.0's linux64, win64 and darwin64 are accepted too)",
                known.join(", ")
            )
        })?;
        if !platforms.contains(&platform) {
            platforms.push(platform);
        }
    }
    if platforms.is_empty() {
        return Err("--platform names no platform".into());
    }
    platforms.sort();
    Ok(platforms)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn platform_lists_parse_and_name_the_unknown() {
        assert_eq!(parse_list("all").unwrap(), Platform::ALL.to_vec());
        assert_eq!(
            parse_list("win64,x86_64-linux,win64").unwrap(),
            vec![Platform::X86_64Linux, Platform::X86_64Windows]
        );
        assert_eq!(
            parse_list("darwin64,aarch64-darwin").unwrap(),
            vec![Platform::X86_64Darwin, Platform::Aarch64Darwin]
        );
        let err = parse_list("linux64,darwin32").unwrap_err();
        assert!(err.contains("`darwin32`"), "{err}");
        assert!(
            err.contains("linux64, win64 and darwin64 are accepted too"),
            "{err}"
        );
        assert!(parse_list(",").is_err());
    }
}
